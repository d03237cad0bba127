// EVENT packets: the event log's events to the ground, oldest first, each once
// (the telemetry task is the event log's primary reader: it pops them). At
// most kEventsPerFrame a frame, and no more than the slowest link's event
// queue takes now (TelemetryOutput::room): the rest wait in the event log
// (kEventRingDepth), so a burst on the CAN link goes down late instead of
// being refused; only a backlog beyond the log is lost (counted, HK.events_lost).
//
// An event with numbers (core::EventData; dictionary.def, "Event data") is
// followed at once by its EVENT_DATA packet, at the same (event) priority, so
// the pair comes down together and in order. EVENT_DATA never changes when the
// EVENT packets go out: the frame's budget counts EVENT packets only, as
// before, and an EVENT_DATA is offered only while the event queue keeps room
// for the EVENT packets still due in this frame's budget; otherwise it is
// withheld: counted (dataWithheld(), EVENT_DATA.data_withheld) and evented
// (511, the 1st, 2nd, 4th ... time). An EVENT_DATA a link refuses is counted
// and evented by TelemetryOutput as any refused packet (HK.tlm_dropped, 507).
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
    std::uint32_t dataSent() const { return dataSent_; }          // EVENT_DATA packets offered to the links
    std::uint32_t dataWithheld() const { return dataWithheld_; }  // ... withheld to keep the EVENTs' place

private:
    // The event's EVENT_DATA, when the event queue has room for it beyond the
    // eventsStillDue EVENT packets this frame may still send.
    void sendData(const core::Event& event, std::size_t eventsStillDue);

    core::EventLog& events_;
    TelemetryOutput& output_;
    std::uint32_t eventsSent_ = 0;
    std::uint32_t dataSent_ = 0;
    std::uint32_t dataWithheld_ = 0;
};

}  // namespace rse::cmdtlm
