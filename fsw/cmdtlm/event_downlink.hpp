// EVENT packets: the event log's events to the ground, oldest first, each once
// (the telemetry task is the event log's primary reader: it pops them). At
// most kEventsPerFrame a frame, and no more than the slowest link's event
// queue takes now (TelemetryOutput::room): the rest wait in the event log
// (kEventRingDepth), so a burst on the CAN link goes down late instead of
// being refused; only a backlog beyond the log is lost (counted, HK.events_lost).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kEventsPerFrame = 8;  // 800 events/s downlink at most

class EventDownlink {
public:
    EventDownlink(core::EventLog& events, TelemetryOutput& output) : events_(events), output_(output) {}

    // Every telemetry run, before the packers: the events due.
    void send();
    std::uint32_t eventsSent() const { return eventsSent_; }

private:
    core::EventLog& events_;
    TelemetryOutput& output_;
    std::uint32_t eventsSent_ = 0;
};

}  // namespace rse::cmdtlm
