// A ground link as the flight software sees it: whole packets in, whole packets
// out, never blocking. Transports (UDP, ISO-TP over CAN, in-memory for tests and
// lockstep) carry the same CCSDS bytes; command ingest and telemetry output do
// not know which one they talk to.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"

namespace rse::hal {

// How urgent a downlink packet is; telemetry output decides by packet type
// (fsw/cmdtlm/telemetry_output.hpp). A link that queues its downlink (ISO-TP on
// CAN) keeps a queue per priority, so routine telemetry can never take the room
// an acknowledgement needs, and sends the more urgent first. A link that sends at
// once (UDP, in-memory) treats them all alike.
enum class TxPriority : std::uint8_t {
    kRoutine = 0,  // scheduled and requested telemetry (HK, TASK_TIMING, DRIVES, TABLE_DUMP ...)
    kEvent = 1,    // EVENT packets
    kAck = 2,      // CMD_ACK: a ground is waiting for it
};
constexpr std::size_t kTxPriorityCount = 3;
inline const char* toString(TxPriority priority) {
    switch (priority) {
        case TxPriority::kRoutine: return "routine";
        case TxPriority::kEvent: return "event";
        case TxPriority::kAck: return "acknowledgement";
    }
    return "?";
}

// txRoom() of a link that sends at once (UDP, in-memory with room to spare).
constexpr std::size_t kTxRoomUnlimited = static_cast<std::size_t>(-1);

struct PacketLinkStats {
    std::uint32_t rxPackets = 0;   // handed to the caller
    std::uint32_t rxDropped = 0;   // lost before the caller read them (queue full, too large, truncated)
    std::uint32_t rxKernelDropped = 0;  // lost in the OS before the link could read them (UDP receive
                                        // buffer full: SO_RXQ_OVFL); not part of rxDropped
    std::uint32_t txPackets = 0;   // accepted for sending
    std::uint32_t txDropped = 0;   // refused: queue full, too large, link down
    std::uint32_t errors = 0;      // OS or protocol errors
};

class PacketLink {
public:
    // The oldest received packet: kOk, kEmpty when none is waiting, kTooLarge when
    // it did not fit capacity (it is dropped and counted). Never blocks.
    virtual core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) = 0;
    // Queues or sends one packet: kOk, kFull (queue full, counted), kTooLarge,
    // kUnavailable (link not open or down). Never blocks.
    virtual core::Status send(const std::uint8_t* data, std::size_t length) = 0;
    // send() with a priority (see TxPriority); the same results. send() is
    // sendWithPriority(..., kRoutine) on a link that distinguishes them.
    virtual core::Status sendWithPriority(const std::uint8_t* data, std::size_t length, TxPriority priority) {
        (void)priority;
        return send(data, length);
    }
    // How many more packets of this priority send would take now without
    // refusing one. A sender that can wait (telemetry output's events, which
    // stay in the event log) offers no more than this, so a burst is sent
    // late rather than lost. A link that sends at once: kTxRoomUnlimited.
    virtual std::size_t txRoom(TxPriority priority) const {
        (void)priority;
        return kTxRoomUnlimited;
    }
    // Advances the transport once per minor frame (segmentation, retries).
    virtual void service() {}
    // Whether telemetry should be offered now. A link whose transport needs a
    // listening peer (ISO-TP waits for flow control) holds its downlink back
    // until the ground has been heard on it, like cFS TO_LAB's "enable output";
    // packets not offered are not drops.
    virtual bool downlinkActive() const { return true; }
    virtual const char* name() const = 0;
    virtual const PacketLinkStats& stats() const = 0;

protected:
    ~PacketLink() = default;
};

}  // namespace rse::hal
