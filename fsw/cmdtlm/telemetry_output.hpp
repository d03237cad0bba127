// Telemetry output: encodes a dictionary telemetry struct, wraps it in a CCSDS
// packet (per-APID sequence count, MET time) and hands it to every ground link.
// Single-threaded like everything in the executive: any task may send.
//
// Each packet goes with a downlink priority (hal::TxPriority, telemetryPriority()):
// CMD_ACK first, EVENT and EVENT_DATA (an event's numbers, which follow it) next,
// everything else routine. A link that queues (ISO-TP
// on CAN) keeps them apart, so a congested downlink refuses routine telemetry
// before it refuses an event, and never because of routine telemetry refuses an
// acknowledgement. A refusal is counted (dropped(), per priority, and in HK
// tlm_dropped) and evented (507, the 1st, 2nd, 4th ... of each priority).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/ground_links.hpp"
#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr hal::TxPriority telemetryPriority(std::uint16_t apid) {
    return apid == CMD_ACK_Tlm::kApid ? hal::TxPriority::kAck
           : apid == EVENT_Tlm::kApid || apid == EVENT_DATA_Tlm::kApid ? hal::TxPriority::kEvent
                                      : hal::TxPriority::kRoutine;
}

// The sink every packer and command handler sends through (telemetry_sink.hpp),
// and HK's tlm_* fields.
class TelemetryOutput final : public TelemetrySink, public HousekeepingContributor {
public:
    TelemetryOutput(const core::Clock& clock, core::EventLog& events, const GroundLinks& links)
        : clock_(clock), events_(events), links_(links) {}

    void sendPayload(std::uint16_t apid, const std::uint8_t* payload, std::size_t length) override;
    // Packets of this priority every link offered telemetry would take now
    // (the least txRoom; hal::kTxRoomUnlimited when none limits it).
    std::size_t room(hal::TxPriority priority) const;

    std::uint32_t sent() const { return sent_; }        // packets accepted by a link (counted per link)
    std::uint32_t dropped() const { return dropped_; }  // packets a link refused
    std::uint32_t dropped(hal::TxPriority priority) const {
        const auto i = static_cast<std::size_t>(priority);
        return i < hal::kTxPriorityCount ? droppedBy_[i] : 0;
    }
    void resetCounters();
    void fillHousekeeping(HK_Tlm& hk) const override;

private:
    void reportTooLarge(std::uint16_t apid, std::size_t length) override;

    const core::Clock& clock_;
    core::EventLog& events_;
    const GroundLinks& links_;
    std::uint16_t sequence_[kMaxApid + 1] = {};
    std::uint8_t packet_[kMaxTelemetryPacket] = {};
    std::uint32_t sent_ = 0;
    std::uint32_t dropped_ = 0;
    std::uint32_t droppedBy_[hal::kTxPriorityCount] = {};  // indexed by hal::TxPriority
    std::uint32_t tooLarge_ = 0;
};

}  // namespace rse::cmdtlm
