// The ground link on CAN: CCSDS packets carried as ISO-TP messages (docs/icd.md
// §2), one packet per message; the rover receives on 0x6C0 and sends on 0x6C1
// (hal/can/ground_link_ids.hpp).
// To command ingest and telemetry output it is a PacketLink like the UDP link.
//
//   Uplink (commands): receive() hands over the next message the ISO-TP channel
//   completed. The channel accepts messages of up to kMaxCommandPacket bytes and
//   answers a longer First Frame with FC OVERFLOW (event 361), so oversized
//   uploads are refused on the wire instead of filling the channel's receive FIFO
//   (8 KB: about 30 commands of the largest size), where completed commands wait
//   until command ingest reads them.
//   Downlink (telemetry): send() / sendWithPriority() copy the packet into a fixed
//   queue of kGroundLinkTxQueueDepth packets per hal::TxPriority and return at once
//   (kFull when that queue is full: counted, evented). service() starts the
//   queued packets one ISO-TP message at a time whenever the channel's transmitter
//   is idle: the oldest acknowledgement first, then events, then routine
//   telemetry, each queue in order. While routine packets wait, every
//   kGroundLinkRoutineShare-th packet started after an event is routine, so an
//   event storm cannot starve housekeeping (which is where the ground reads the
//   drop counters). Telemetry output offers events only as fast as the event
//   queue takes them (txRoom), so a burst waits in the event log instead of
//   being refused here. Routine telemetry can fill only its own queue, never the room
//   of an acknowledgement. Only service(), called once per minor frame by the CAN
//   I/O task, touches the bus, so any task of the frame may send() without racing
//   the CANopen traffic.
//
// A ground tool that comes and goes (rse-ground send exits after the ack) leaves
// the rover's next First Frame unanswered: without help, the transmitter would
// wait N_Bs (1 s) for flow control and then drop the packet. The channel is
// configured to send that FF again as soon as the ground is heard (a command
// arriving), so the command's acknowledgement does not wait behind it
// (hal/can/isotp.hpp, resendFirstFrameOnPeerMessage).
//
// Throughput down is set by the ground's flow control: with its block size 8 the
// rover sends one block (56 bytes) per 10 ms frame, so a 512-byte packet takes
// about 10 frames; single-frame packets (up to 7 bytes) go several per frame.
//
// Counters: stats() (PacketLinkStats) sums what means the same on every link and
// is brought up to date by service() and receive(); channel().stats() keeps each
// ISO-TP reason apart. Events: queue full (each priority counted apart) and
// packets too large for the reader or the queue (hal/link/link_events.hpp, 1st,
// 2nd, 4th ... occurrence); protocol
// errors are evented by the channel (hal/can/can_events.hpp, 350-367).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/ground_link_ids.hpp"
#include "hal/can/isotp.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "hal/link/packet_link.hpp"
#include "hal/link/packet_queue.hpp"

namespace rse::io {

constexpr std::uint32_t kGroundUplinkCobId = hal::kGroundUplinkCanId;      // 0x6C0
constexpr std::uint32_t kGroundDownlinkCobId = hal::kGroundDownlinkCanId;  // 0x6C1
constexpr std::size_t kGroundLinkTxQueueDepth = 16;  // packets waiting for the transmitter, per priority
constexpr std::size_t kGroundLinkRoutineShare = 4;    // at least 1 in 4 packets is routine while some wait

class CanGroundLink final : public hal::canopen::CanFrameSink, public hal::PacketLink {
public:
    CanGroundLink(hal::CanBus& can, const core::Clock& clock, core::EventLog& events);
    CanGroundLink(const CanGroundLink&) = delete;
    CanGroundLink& operator=(const CanGroundLink&) = delete;

    // Frames with id kGroundUplinkCobId (the CANopen master routes them here).
    void onFrame(const hal::CanFrame& frame, core::TimeNs) override { channel_.onFrame(frame); }

    // The oldest completed uplink message: kOk, kEmpty, kTooLarge (longer than
    // capacity: dropped, counted in rxDropped, evented; *length says how long),
    // kInvalidArgument (null length, or null out with capacity > 0).
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override;
    // Queues a copy for the downlink: kOk, kFull (the priority's queue is full),
    // kTooLarge (more than kMaxTelemetryPacket), kInvalidArgument (empty or null),
    // kUnavailable (the channel's configuration was refused). Every refusal counts
    // in txDropped. send() queues as routine telemetry.
    core::Status send(const std::uint8_t* data, std::size_t length) override;
    core::Status sendWithPriority(const std::uint8_t* data, std::size_t length, hal::TxPriority priority) override;
    // Telemetry goes down only once a ground has sent something on 0x6C0: with
    // nobody there every multi-frame packet would wait N_Bs for flow control.
    bool downlinkActive() const override { return groundHeard_; }
    // Room in the priority's queue while the ground answers; a ground that has
    // stopped answering (the last packet went unanswered for N_Bs, nothing heard
    // since) gets kTxRoomUnlimited: holding events back for it would only delay
    // them on the other links, and its queue refuses (counts) what it cannot take.
    std::size_t txRoom(hal::TxPriority priority) const override;
    // Once per minor frame: advances ISO-TP (CFs, flow control, timeouts) and starts
    // the next queued packets while the transmitter is idle.
    void service() override;
    const char* name() const override { return "can-isotp"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }

    std::size_t txQueued() const;                                   // waiting, not yet started, all priorities
    std::size_t txQueued(hal::TxPriority priority) const { return queue(priority).size(); }
    std::uint32_t txFull(hal::TxPriority priority) const { return txFull_[index(priority)]; }  // refused: queue full
    std::uint32_t txCompleted() const { return txCompleted_; }      // every frame accepted by the bus
    std::uint32_t txAborted() const { return txAborted_; }          // ISO-TP gave up (reason in channel().stats())
    const hal::IsoTpChannel& channel() const { return channel_; }

private:
    using TxQueue = hal::PacketQueue<kGroundLinkTxQueueDepth, cmdtlm::kMaxTelemetryPacket>;

    bool groundHeard_ = false;
    bool groundAnswering_ = true;  // false from a packet unanswered (N_Bs) until the ground is heard or answers
    static hal::IsoTpConfig config();
    // An out-of-range value counts as routine.
    static std::size_t index(hal::TxPriority priority) {
        const auto i = static_cast<std::size_t>(priority);
        return i < hal::kTxPriorityCount ? i : 0;
    }
    const TxQueue& queue(hal::TxPriority priority) const { return txQueues_[index(priority)]; }
    TxQueue* nextQueue();
    void finishTransmission();
    void refreshStats();

    core::EventLog& events_;
    hal::IsoTpChannel channel_;
    TxQueue txQueues_[hal::kTxPriorityCount];  // indexed by hal::TxPriority
    std::size_t eventsInARow_ = 0;  // event packets started in a row while routine ones waited
    bool inFlight_ = false;  // a queued packet was handed to the channel and has not finished
    bool inFlightNeedsAnswer_ = false;  // it is multi-frame: only the ground's flow control completes it
    // Where an uplink message too long for the reader's buffer is read to drop it.
    std::uint8_t discard_[cmdtlm::kMaxCommandPacket] = {};
    hal::PacketLinkStats stats_;
    std::uint32_t txCompleted_ = 0;
    std::uint32_t txAborted_ = 0;
    // Occurrences per reason, for the 1, 2, 4, 8 ... event throttle.
    std::uint32_t rxTooLarge_ = 0;
    std::uint32_t txFull_[hal::kTxPriorityCount] = {};
    std::uint32_t txInvalid_ = 0;
};

}  // namespace rse::io
