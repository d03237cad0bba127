#include "fsw/io/can_ground_link.hpp"

#include "hal/link/link_events.hpp"

namespace rse::io {

using core::Severity;
using core::Status;

namespace {
unsigned u(std::uint32_t v) { return static_cast<unsigned>(v); }
}  // namespace

static_assert(cmdtlm::kMaxCommandPacket >= 8 && cmdtlm::kMaxCommandPacket <= hal::kIsoTpMaxMessage,
              "the uplink limit must be a valid IsoTpConfig::maxRxLength");
static_assert(cmdtlm::kMaxTelemetryPacket <= hal::kIsoTpMaxMessage, "a telemetry packet must fit one ISO-TP message");

hal::IsoTpConfig CanGroundLink::config() {
    hal::IsoTpConfig c;
    c.txId = kGroundDownlinkCobId;
    c.rxId = kGroundUplinkCobId;
    c.blockSize = 8;  // docs/icd.md §2
    c.stMin = 0;
    // Longer uploads are refused with FC OVERFLOW; it also bounds what receive()
    // may have to drop to sizeof discard_.
    c.maxRxLength = static_cast<std::uint16_t>(cmdtlm::kMaxCommandPacket);
    // A ground tool that was not listening when our FF went out is heard when it
    // commands: the FF goes again at once instead of after N_Bs.
    c.resendFirstFrameOnPeerMessage = true;
    return c;
}

CanGroundLink::CanGroundLink(hal::CanBus& can, const core::Clock& clock, core::EventLog& events)
    : events_(events), channel_(can, clock, events, config()) {}

Status CanGroundLink::receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) {
    if (length == nullptr || (out == nullptr && capacity > 0)) {
        return Status::kInvalidArgument;
    }
    const Status s = channel_.receive(out, capacity, length);
    if (core::isOk(s) || s == Status::kTooLarge) {
        groundHeard_ = true;
        groundAnswering_ = true;
    }
    if (core::isOk(s)) {
        ++stats_.rxPackets;
    } else if (s == Status::kTooLarge) {
        // The channel keeps a message that does not fit; the PacketLink contract is
        // to drop it. It fits discard_ (maxRxLength), so this always succeeds.
        std::size_t dropped = 0;
        (void)channel_.receive(discard_, sizeof discard_, &dropped);
        ++rxTooLarge_;
        if (core::isReportableOccurrence(rxTooLarge_)) {
            events_.report(hal::events::kLinkRxTooLarge, Severity::kWarning,
                           "can-isotp: %zu-byte packet dropped, longer than %zu (%u times)", *length, capacity,
                           u(rxTooLarge_));
        }
    }
    refreshStats();
    return s;
}

Status CanGroundLink::send(const std::uint8_t* data, std::size_t length) {
    return sendWithPriority(data, length, hal::TxPriority::kRoutine);
}

Status CanGroundLink::sendWithPriority(const std::uint8_t* data, std::size_t length, hal::TxPriority priority) {
    if (!channel_.configValid()) {
        ++stats_.txDropped;
        return Status::kUnavailable;
    }
    const std::size_t p = index(priority);
    const Status s = txQueues_[p].push(data, length);
    if (core::isOk(s)) {
        ++stats_.txPackets;
        return s;
    }
    ++stats_.txDropped;
    if (s == Status::kFull) {
        ++txFull_[p];
        if (core::isReportableOccurrence(txFull_[p])) {
            events_.report(hal::events::kLinkTxFull, Severity::kWarning,
                           "can-isotp: %s queue full (%zu packets), %zu-byte packet dropped (%u times)",
                           hal::toString(static_cast<hal::TxPriority>(p)), kGroundLinkTxQueueDepth, length,
                           u(txFull_[p]));
        }
    } else {
        ++txInvalid_;
        if (core::isReportableOccurrence(txInvalid_)) {
            events_.report(hal::events::kLinkTxInvalid, Severity::kError,
                           "can-isotp: %zu-byte packet refused: 1..%zu bytes (%u times)", length,
                           cmdtlm::kMaxTelemetryPacket, u(txInvalid_));
        }
    }
    return s;
}

std::size_t CanGroundLink::txRoom(hal::TxPriority priority) const {
    if (!groundAnswering_) {
        return hal::kTxRoomUnlimited;
    }
    return kGroundLinkTxQueueDepth - queue(priority).size();
}

std::size_t CanGroundLink::txQueued() const {
    std::size_t n = 0;
    for (const TxQueue& q : txQueues_) {
        n += q.size();
    }
    return n;
}

// The queue whose oldest packet goes next (nullptr: all empty): acknowledgements
// first, then events, then routine telemetry, with routine taking every
// kGroundLinkRoutineShare-th turn while it waits behind events.
CanGroundLink::TxQueue* CanGroundLink::nextQueue() {
    TxQueue& acks = txQueues_[index(hal::TxPriority::kAck)];
    TxQueue& events = txQueues_[index(hal::TxPriority::kEvent)];
    TxQueue& routine = txQueues_[index(hal::TxPriority::kRoutine)];
    if (!acks.empty()) {
        return &acks;
    }
    if (!events.empty() && (routine.empty() || eventsInARow_ + 1 < kGroundLinkRoutineShare)) {
        eventsInARow_ = routine.empty() ? 0 : eventsInARow_ + 1;
        return &events;
    }
    eventsInARow_ = 0;
    return routine.empty() ? nullptr : &routine;
}

void CanGroundLink::finishTransmission() {
    if (inFlight_ && !channel_.txBusy()) {
        inFlight_ = false;
        if (channel_.txResult() == hal::IsoTpTxResult::kDone) {
            ++txCompleted_;
            groundAnswering_ = groundAnswering_ || inFlightNeedsAnswer_;
        } else {
            if (channel_.txResult() == hal::IsoTpTxResult::kTimeoutBs) {
                groundAnswering_ = false;
            }
            ++txAborted_;  // the channel evented the reason
        }
    }
}

void CanGroundLink::service() {
    channel_.poll();
    // Each pass finishes the packet in flight and starts the next one; a single
    // frame packet finishes at once, so several can go in one frame. Bounded: the
    // queues hold kTxPriorityCount * kGroundLinkTxQueueDepth packets, one more
    // pass sees the last finish.
    for (std::size_t pass = 0; pass <= hal::kTxPriorityCount * kGroundLinkTxQueueDepth; ++pass) {
        if (channel_.txBusy()) {
            break;
        }
        finishTransmission();
        TxQueue* queue = nextQueue();
        if (queue == nullptr) {
            break;
        }
        std::size_t length = 0;
        const std::uint8_t* packet = queue->front(&length);
        // Cannot be kBusy (idle transmitter) nor kInvalidArgument (1..512 bytes
        // queued); kNotInitialized is refused in send(). Counted all the same.
        if (core::isOk(channel_.send(packet, length))) {
            inFlight_ = true;
            inFlightNeedsAnswer_ = length > hal::kIsoTpMaxSingleFrame;
        } else {
            ++txAborted_;
        }
        queue->pop();
    }
    refreshStats();
}

void CanGroundLink::refreshStats() {
    const hal::IsoTpStats& c = channel_.stats();
    stats_.rxDropped = rxTooLarge_ + c.rxOverruns + c.rxTooLong;
    stats_.errors = txAborted_ + c.wrongSequence + c.timeoutCr + c.timeoutAr;
}

}  // namespace rse::io
