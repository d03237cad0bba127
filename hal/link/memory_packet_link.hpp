// A ground link inside the process: two fixed packet FIFOs, uplink (ground ->
// flight) and downlink (flight -> ground). The flight side is a PacketLink like
// any other; a test, or the lockstep demo's ground station, is the other end
// through groundSend() / groundReceive(). Lockstep runs are deterministic: a
// packet sent in one frame is readable by the other side at once.
//
// The uplink holds more packets than the flight's command queue (8), so a test can
// push more commands in one frame than command ingest can take and watch that
// overflow be handled there. Packets the link itself cannot hold are refused,
// counted in stats() (uplink: rxDropped, downlink: txDropped) and never evented:
// like MemoryCanBus, this stands in for a wire, and the code on either side
// reports what it sees.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "hal/link/packet_link.hpp"
#include "hal/link/packet_queue.hpp"

namespace rse::hal {

// The largest packet either direction carries: the largest CCSDS packet on any
// link (fsw/cmdtlm/ccsds.hpp, kMaxTelemetryPacket; commands are smaller).
constexpr std::size_t kMemoryLinkMaxPacket = 512;
constexpr std::size_t kMemoryLinkUplinkDepth = 32;    // > the command queue's 8, see above
constexpr std::size_t kMemoryLinkDownlinkDepth = 32;  // a ground that reads every frame never fills it

class MemoryPacketLink final : public PacketLink {
public:
    MemoryPacketLink() = default;
    MemoryPacketLink(const MemoryPacketLink&) = delete;
    MemoryPacketLink& operator=(const MemoryPacketLink&) = delete;

    // Flight side (PacketLink).
    // The oldest uplinked packet. kTooLarge when it is longer than capacity: it is
    // dropped, counted in rxDropped, and *length says how long it was.
    // kInvalidArgument for a null length (or null out with capacity > 0).
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override;
    // kOk, kFull (downlink full), kTooLarge (> kMemoryLinkMaxPacket),
    // kInvalidArgument (empty or null); every refusal counts in txDropped.
    core::Status send(const std::uint8_t* data, std::size_t length) override;
    std::size_t txRoom(TxPriority) const override { return kMemoryLinkDownlinkDepth - downlink_.size(); }
    const char* name() const override { return "memory"; }
    const PacketLinkStats& stats() const override { return stats_; }

    // Ground side.
    // Queues a packet for the flight. kOk, kFull (uplink full), kTooLarge,
    // kInvalidArgument; every refusal counts in the flight's rxDropped (the packet
    // never reached it).
    core::Status groundSend(const std::uint8_t* data, std::size_t length);
    // The oldest downlinked packet. kEmpty when none; kTooLarge when longer than
    // capacity (*length says how long; it stays queued, so the ground can retry
    // with a larger buffer); kInvalidArgument for a null length (or null out with
    // capacity > 0).
    core::Status groundReceive(std::uint8_t* out, std::size_t capacity, std::size_t* length);

    std::size_t uplinkQueued() const { return uplink_.size(); }
    std::size_t downlinkQueued() const { return downlink_.size(); }

private:
    PacketQueue<kMemoryLinkUplinkDepth, kMemoryLinkMaxPacket> uplink_;
    PacketQueue<kMemoryLinkDownlinkDepth, kMemoryLinkMaxPacket> downlink_;
    PacketLinkStats stats_;
};

}  // namespace rse::hal
