#include "fsw/cmdtlm/event_downlink.hpp"

#include <algorithm>
#include <cstring>

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

void EventDownlink::send() {
    const std::size_t budget = std::min(kEventsPerFrame, output_.room(hal::TxPriority::kEvent));
    core::Event event;
    for (std::size_t i = 0; i < budget && core::isOk(events_.pop(&event)); ++i) {
        EVENT_Tlm tlm{};
        tlm.event_sequence = event.sequence;
        tlm.event_time = static_cast<double>(event.time) / static_cast<double>(core::kNsPerSec);
        tlm.event_id = event.id;
        tlm.severity = static_cast<std::uint8_t>(event.severity);
        std::memcpy(tlm.text, event.text, std::min(sizeof tlm.text, sizeof event.text));
        output_.send(tlm);
        ++eventsSent_;
        if (event.data.count > 0) {
            sendData(event, std::min(budget - i - 1, events_.unread()));
        }
    }
}

void EventDownlink::sendData(const core::Event& event, std::size_t eventsStillDue) {
    if (output_.room(hal::TxPriority::kEvent) <= eventsStillDue) {
        ++dataWithheld_;
        if (core::isReportableOccurrence(dataWithheld_)) {
            events_.report(events::kEventDataWithheld, core::Severity::kWarning,
                           "tlm: numbers of event %u (sequence %u) withheld: the event queue keeps its room for "
                           "events (%u times)",
                           static_cast<unsigned>(event.id), static_cast<unsigned>(event.sequence),
                           static_cast<unsigned>(dataWithheld_));
        }
        return;
    }
    EVENT_DATA_Tlm tlm{};
    tlm.event_sequence = event.sequence;
    tlm.event_id = event.id;
    const std::size_t count = std::min<std::size_t>(event.data.count, sizeof tlm.value / sizeof tlm.value[0]);
    tlm.value_count = static_cast<std::uint8_t>(count);
    for (std::size_t v = 0; v < count; ++v) {
        tlm.value[v] = event.data.values[v];
    }
    tlm.data_withheld = dataWithheld_;
    output_.send(tlm);
    ++dataSent_;
}

}  // namespace rse::cmdtlm
