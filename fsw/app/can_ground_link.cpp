#include "fsw/app/can_ground_link.hpp"

#include "hal/link/link_events.hpp"

namespace rse::app {

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
    if (!channel_.configValid()) {
        ++stats_.txDropped;
        return Status::kUnavailable;
    }
    const Status s = txQueue_.push(data, length);
    if (core::isOk(s)) {
        ++stats_.txPackets;
        return s;
    }
    ++stats_.txDropped;
    if (s == Status::kFull) {
        ++txFull_;
        if (core::isReportableOccurrence(txFull_)) {
            events_.report(hal::events::kLinkTxFull, Severity::kWarning,
                           "can-isotp: transmit queue full (%zu packets), %zu-byte packet dropped (%u times)",
                           kGroundLinkTxQueueDepth, length, u(txFull_));
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

void CanGroundLink::finishTransmission() {
    if (inFlight_ && !channel_.txBusy()) {
        inFlight_ = false;
        if (channel_.txResult() == hal::IsoTpTxResult::kDone) {
            ++txCompleted_;
        } else {
            ++txAborted_;  // the channel evented the reason
        }
    }
}

void CanGroundLink::service() {
    channel_.poll();
    // Each pass finishes the packet in flight and starts the next one; a single
    // frame packet finishes at once, so several can go in one frame. Bounded: the
    // queue holds kGroundLinkTxQueueDepth packets, one more pass sees the last finish.
    for (std::size_t pass = 0; pass <= kGroundLinkTxQueueDepth; ++pass) {
        if (channel_.txBusy()) {
            break;
        }
        finishTransmission();
        std::size_t length = 0;
        const std::uint8_t* packet = txQueue_.front(&length);
        if (packet == nullptr) {
            break;
        }
        // Cannot be kBusy (idle transmitter) nor kInvalidArgument (1..512 bytes
        // queued); kNotInitialized is refused in send(). Counted all the same.
        if (core::isOk(channel_.send(packet, length))) {
            inFlight_ = true;
        } else {
            ++txAborted_;
        }
        txQueue_.pop();
    }
    refreshStats();
}

void CanGroundLink::refreshStats() {
    const hal::IsoTpStats& c = channel_.stats();
    stats_.rxDropped = rxTooLarge_ + c.rxOverruns + c.rxTooLong;
    stats_.errors = txAborted_ + c.wrongSequence + c.timeoutCr + c.timeoutAr;
}

}  // namespace rse::app
