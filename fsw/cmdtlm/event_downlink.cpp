#include "fsw/cmdtlm/event_downlink.hpp"

#include <algorithm>
#include <cstring>

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
    }
}

}  // namespace rse::cmdtlm
