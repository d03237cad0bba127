#include "hal/can/isotp.hpp"

#include <cstring>

#include "hal/can/can_events.hpp"

namespace rse::hal {

using core::Severity;
using core::Status;
using core::TimeNs;

namespace {

// N_PCI types (high nibble of byte 0).
constexpr std::uint8_t kPciSingle = 0x0;
constexpr std::uint8_t kPciFirst = 0x1;
constexpr std::uint8_t kPciConsecutive = 0x2;
constexpr std::uint8_t kPciFlowControl = 0x3;
// Flow status (low nibble of an FC's byte 0).
constexpr std::uint8_t kFsClearToSend = 0x0;
constexpr std::uint8_t kFsWait = 0x1;
constexpr std::uint8_t kFsOverflow = 0x2;

constexpr std::size_t kSfMaxData = kIsoTpMaxSingleFrame;  // SF_DL 1..7 (classic CAN)
constexpr std::size_t kFfData = 6;        // data bytes in a FF with a 12-bit FF_DL
constexpr std::size_t kCfMaxData = 7;     // data bytes in a CF
constexpr std::size_t kFfMinLength = 8;   // FF_DLmin for classic CAN
constexpr std::size_t kFcLength = 3;      // FS, BS, STmin
constexpr std::size_t kStoreHeader = 2;   // big-endian length before each stored message

std::uint8_t highNibble(std::uint8_t byte) { return static_cast<std::uint8_t>(byte >> 4); }
std::uint8_t lowNibble(std::uint8_t byte) { return static_cast<std::uint8_t>(byte & 0x0F); }
bool isValidStMin(std::uint8_t stMin) { return stMin <= 0x7F || (stMin >= 0xF1 && stMin <= 0xF9); }
unsigned u(std::size_t value) { return static_cast<unsigned>(value); }
long long ms(TimeNs t) { return static_cast<long long>(t / core::kNsPerMs); }

}  // namespace

bool isValidIsoTpConfig(const IsoTpConfig& config) {
    return config.txId <= kCanMaxStandardId && config.rxId <= kCanMaxStandardId && config.txId != config.rxId &&
           isValidStMin(config.stMin) && config.nAs > 0 && config.nAr > 0 && config.nBs > 0 && config.nCr > 0 &&
           config.maxRxLength >= kFfMinLength && config.maxRxLength <= kIsoTpMaxMessage;
}

TimeNs isoTpStMinToNs(std::uint8_t stMin) {
    if (stMin <= 0x7F) {
        return static_cast<TimeNs>(stMin) * core::kNsPerMs;
    }
    if (stMin >= 0xF1 && stMin <= 0xF9) {
        return static_cast<TimeNs>(stMin - 0xF0) * 100 * core::kNsPerUs;
    }
    return static_cast<TimeNs>(kIsoTpStMinReservedAs) * core::kNsPerMs;  // reserved values
}

const char* toString(IsoTpTxResult result) {
    switch (result) {
        case IsoTpTxResult::kIdle: return "idle";
        case IsoTpTxResult::kInProgress: return "in-progress";
        case IsoTpTxResult::kDone: return "done";
        case IsoTpTxResult::kTimeoutAs: return "timeout-As";
        case IsoTpTxResult::kTimeoutBs: return "timeout-Bs";
        case IsoTpTxResult::kPeerOverflow: return "peer-overflow";
        case IsoTpTxResult::kWaitLimit: return "wait-limit";
        case IsoTpTxResult::kInvalidFlowStatus: return "invalid-flow-status";
    }
    return "?";
}

IsoTpChannel::IsoTpChannel(CanBus& bus, const core::Clock& clock, core::EventLog& events,
                           const IsoTpConfig& config)
    : bus_(bus), clock_(clock), events_(events), config_(config), configValid_(isValidIsoTpConfig(config)) {
    if (!configValid_) {
        events_.report(events::kIsoTpConfigInvalid, Severity::kError,
                       "isotp tx 0x%X rx 0x%X: invalid config (ids, STmin 0x%02X, timeouts, max rx %u): inert",
                       static_cast<unsigned>(config.txId), static_cast<unsigned>(config.rxId),
                       static_cast<unsigned>(config.stMin), static_cast<unsigned>(config.maxRxLength));
    }
}

// ---------------------------------------------------------------------------
// Transmit direction.

Status IsoTpChannel::send(const std::uint8_t* data, std::size_t length) {
    if (!configValid_) {
        return Status::kNotInitialized;
    }
    if (data == nullptr || length == 0 || length > kIsoTpMaxMessage) {
        ++stats_.sendInvalid;
        if (core::isReportableOccurrence(stats_.sendInvalid)) {
            events_.report(events::kIsoTpSendInvalid, Severity::kError,
                           "isotp tx 0x%03X: send of %u bytes refused (1..%u) (%u times)",
                           static_cast<unsigned>(config_.txId), data == nullptr ? 0U : u(length),
                           u(kIsoTpMaxMessage), static_cast<unsigned>(stats_.sendInvalid));
        }
        return Status::kInvalidArgument;
    }
    if (txState_ != TxState::kIdle) {
        ++stats_.sendBusy;
        if (core::isReportableOccurrence(stats_.sendBusy)) {
            events_.report(events::kIsoTpSendBusy, Severity::kWarning,
                           "isotp tx 0x%03X: send while %u of %u bytes under way: busy (%u times)",
                           static_cast<unsigned>(config_.txId), u(txOffset_), u(txLength_),
                           static_cast<unsigned>(stats_.sendBusy));
        }
        return Status::kBusy;
    }
    std::memcpy(txBuf_, data, length);
    txLength_ = length;
    txOffset_ = 0;
    txSn_ = 1;  // the FF counts as 0
    txHaveFcParams_ = false;
    txPeerBs_ = 0;
    txPeerStMin_ = 0;
    txBlockCount_ = 0;
    txWaits_ = 0;
    txNextCfAt_ = 0;
    txAsArmed_ = false;
    peerStartedMessage_ = false;  // heard before this message began: no reason to send its FF twice
    txState_ = length <= kSfMaxData ? TxState::kSendSf : TxState::kSendFf;
    txResult_ = IsoTpTxResult::kInProgress;
    const TimeNs now = clock_.now();
    if (!transmitFirstFrame()) {
        armAs(now);  // retried by poll() until N_As
        return Status::kOk;
    }
    firstFrameSent(now);
    return Status::kOk;
}

// An SF completes the message; after an FF the peer's flow control is due within N_Bs.
void IsoTpChannel::firstFrameSent(TimeNs now) {
    if (txState_ == TxState::kSendSf) {
        txOffset_ = txLength_;
        finishTx(IsoTpTxResult::kDone);
    } else {
        txOffset_ = kFfData;
        txState_ = TxState::kWaitFc;
        txBsDeadline_ = now + config_.nBs;
    }
}

bool IsoTpChannel::transmit(const std::uint8_t* bytes, std::size_t count) {
    CanFrame frame;
    frame.id = config_.txId;
    std::memcpy(frame.data, bytes, count);
    if (config_.padFrames) {
        for (std::size_t i = count; i < kCanMaxDlc; ++i) {
            frame.data[i] = config_.padByte;
        }
        frame.dlc = kCanMaxDlc;
    } else {
        frame.dlc = static_cast<std::uint8_t>(count);
    }
    if (!core::isOk(bus_.send(frame))) {
        ++stats_.txRefused;
        return false;
    }
    ++stats_.txFrames;
    return true;
}

bool IsoTpChannel::transmitFirstFrame() {
    std::uint8_t b[kCanMaxDlc] = {};
    if (txState_ == TxState::kSendSf) {
        b[0] = static_cast<std::uint8_t>((kPciSingle << 4) | txLength_);
        std::memcpy(&b[1], txBuf_, txLength_);
        return transmit(b, 1 + txLength_);
    }
    b[0] = static_cast<std::uint8_t>((kPciFirst << 4) | (txLength_ >> 8));
    b[1] = static_cast<std::uint8_t>(txLength_ & 0xFF);
    std::memcpy(&b[2], txBuf_, kFfData);
    return transmit(b, kCanMaxDlc);
}

// After our FF, before the peer answered it with any FC.
bool IsoTpChannel::awaitingFirstFc() const {
    return txState_ == TxState::kWaitFc && !txHaveFcParams_ && txWaits_ == 0 && txOffset_ == kFfData;
}

void IsoTpChannel::resendFirstFrame(TimeNs now) {
    ++stats_.ffResent;
    txState_ = TxState::kSendFf;
    txOffset_ = 0;
    txAsArmed_ = false;
    if (!transmitFirstFrame()) {
        armAs(now);  // retried by pollTx() until N_As
        return;
    }
    firstFrameSent(now);
}

void IsoTpChannel::armAs(TimeNs now) {
    if (!txAsArmed_) {
        txAsArmed_ = true;
        txAsDeadline_ = now + config_.nAs;
    }
}

void IsoTpChannel::pollTx(TimeNs now) {
    switch (txState_) {
        case TxState::kIdle:
            return;
        case TxState::kSendSf:
        case TxState::kSendFf:
            if (transmitFirstFrame()) {
                txAsArmed_ = false;
                firstFrameSent(now);
            } else if (now >= txAsDeadline_) {
                failTx(IsoTpTxResult::kTimeoutAs, 0);
            }
            return;
        case TxState::kWaitFc:
            if (now >= txBsDeadline_) {
                failTx(IsoTpTxResult::kTimeoutBs, 0);
            }
            return;
        case TxState::kSendCf:
            sendConsecutiveFrames(now);
            return;
    }
}

void IsoTpChannel::sendConsecutiveFrames(TimeNs now) {
    for (std::size_t i = 0; i < kIsoTpMaxCfPerPoll; ++i) {
        if (now < txNextCfAt_) {
            return;  // STmin not yet elapsed since the previous CF
        }
        const std::size_t remaining = txLength_ - txOffset_;
        const std::size_t n = remaining < kCfMaxData ? remaining : kCfMaxData;
        std::uint8_t b[kCanMaxDlc] = {};
        b[0] = static_cast<std::uint8_t>((kPciConsecutive << 4) | txSn_);
        std::memcpy(&b[1], &txBuf_[txOffset_], n);
        if (!transmit(b, 1 + n)) {
            armAs(now);
            if (now >= txAsDeadline_) {
                failTx(IsoTpTxResult::kTimeoutAs, 0);
            }
            return;  // retried next poll
        }
        txAsArmed_ = false;
        txOffset_ += n;
        txSn_ = static_cast<std::uint8_t>((txSn_ + 1) & 0x0F);
        ++txBlockCount_;
        txNextCfAt_ = now + txPeerStMin_;
        if (txOffset_ >= txLength_) {
            finishTx(IsoTpTxResult::kDone);
            return;
        }
        if (txPeerBs_ != 0 && txBlockCount_ >= txPeerBs_) {
            txState_ = TxState::kWaitFc;  // block done: wait for the next FC
            txBlockCount_ = 0;
            txBsDeadline_ = now + config_.nBs;
            return;
        }
        if (txPeerStMin_ != 0) {
            return;  // at most one CF per poll when the receiver asked for a gap
        }
    }
}

void IsoTpChannel::finishTx(IsoTpTxResult result) {
    txState_ = TxState::kIdle;
    txResult_ = result;
    txAsArmed_ = false;
    if (result == IsoTpTxResult::kDone) {
        ++stats_.txMessages;
    }
}

void IsoTpChannel::failTx(IsoTpTxResult result, unsigned detail) {
    const unsigned id = static_cast<unsigned>(config_.txId);
    switch (result) {
        case IsoTpTxResult::kTimeoutAs:
            ++stats_.timeoutAs;
            events_.report(events::kIsoTpTimeoutAs, Severity::kError,
                           "isotp tx 0x%03X: N_As: bus refused frames for %lld ms; %u of %u bytes sent, dropped",
                           id, ms(config_.nAs), u(txOffset_), u(txLength_));
            break;
        case IsoTpTxResult::kTimeoutBs:
            ++stats_.timeoutBs;
            events_.report(events::kIsoTpTimeoutBs, Severity::kError,
                           "isotp tx 0x%03X: N_Bs: no FC in %lld ms after %u of %u bytes, dropped", id,
                           ms(config_.nBs), u(txOffset_), u(txLength_));
            break;
        case IsoTpTxResult::kPeerOverflow:
            ++stats_.peerOverflow;
            events_.report(events::kIsoTpPeerOverflow, Severity::kError,
                           "isotp tx 0x%03X: receiver answered FC OVERFLOW to %u bytes, dropped", id,
                           u(txLength_));
            break;
        case IsoTpTxResult::kWaitLimit:
            ++stats_.waitLimit;
            events_.report(events::kIsoTpWaitLimit, Severity::kError,
                           "isotp tx 0x%03X: %u consecutive FC.WAIT (max %u) after %u of %u bytes, dropped", id,
                           detail, static_cast<unsigned>(config_.maxWaitFrames), u(txOffset_), u(txLength_));
            break;
        case IsoTpTxResult::kInvalidFlowStatus:
            ++stats_.invalidFlowStatus;
            events_.report(events::kIsoTpInvalidFlowStatus, Severity::kError,
                           "isotp tx 0x%03X: FC with flow status %u after %u of %u bytes, dropped", id, detail,
                           u(txOffset_), u(txLength_));
            break;
        case IsoTpTxResult::kIdle:
        case IsoTpTxResult::kInProgress:
        case IsoTpTxResult::kDone:
            break;
    }
    finishTx(result);
}

void IsoTpChannel::handleFlowControl(const CanFrame& frame, TimeNs now) {
    if (frame.dlc < kFcLength) {
        malformed("FC with DLC < 3", frame);
        return;
    }
    if (txState_ != TxState::kWaitFc) {
        ++stats_.unexpectedFc;
        if (core::isReportableOccurrence(stats_.unexpectedFc)) {
            events_.report(events::kIsoTpUnexpectedFc, Severity::kWarning,
                           "isotp rx 0x%03X: FC 0x%02X with no transmission waiting, ignored (%u times)",
                           static_cast<unsigned>(config_.rxId), static_cast<unsigned>(frame.data[0]),
                           static_cast<unsigned>(stats_.unexpectedFc));
        }
        return;
    }
    const std::uint8_t flowStatus = lowNibble(frame.data[0]);
    switch (flowStatus) {
        case kFsClearToSend:
            if (!txHaveFcParams_) {  // BS and STmin of the first FC.CTS hold for the whole message
                txHaveFcParams_ = true;
                txPeerBs_ = frame.data[1];
                txPeerStMin_ = isoTpStMinToNs(frame.data[2]);
            }
            txWaits_ = 0;
            txBlockCount_ = 0;
            txState_ = TxState::kSendCf;  // CFs go out from poll()
            return;
        case kFsWait:
            ++stats_.waitsReceived;
            ++txWaits_;
            if (txWaits_ > config_.maxWaitFrames) {
                failTx(IsoTpTxResult::kWaitLimit, static_cast<unsigned>(txWaits_));
                return;
            }
            txBsDeadline_ = now + config_.nBs;  // each WAIT restarts N_Bs
            return;
        case kFsOverflow:
            failTx(IsoTpTxResult::kPeerOverflow, 0);
            return;
        default:
            failTx(IsoTpTxResult::kInvalidFlowStatus, static_cast<unsigned>(flowStatus));
            return;
    }
}

// ---------------------------------------------------------------------------
// Receive direction.

void IsoTpChannel::onFrame(const CanFrame& frame) {
    if (!configValid_) {
        return;
    }
    if (frame.id != config_.rxId || frame.extended() || frame.remote()) {
        ++stats_.foreignFrames;
        return;
    }
    ++stats_.rxFrames;
    if (frame.dlc == 0 || frame.dlc > kCanMaxDlc) {
        malformed("no N_PCI byte (or DLC > 8)", frame);
        return;
    }
    const TimeNs now = clock_.now();
    switch (highNibble(frame.data[0])) {
        case kPciSingle: handleSingle(frame); return;
        case kPciFirst: handleFirst(frame, now); return;
        case kPciConsecutive: handleConsecutive(frame, now); return;
        case kPciFlowControl: handleFlowControl(frame, now); return;
        default: malformed("unknown N_PCI type", frame); return;
    }
}

void IsoTpChannel::malformed(const char* why, const CanFrame& frame) {
    ++stats_.malformed;
    if (core::isReportableOccurrence(stats_.malformed)) {
        events_.report(events::kIsoTpMalformed, Severity::kWarning,
                       "isotp rx 0x%03X: %s (byte0 0x%02X, DLC %u), ignored (%u times)",
                       static_cast<unsigned>(config_.rxId), why,
                       frame.dlc > 0 ? static_cast<unsigned>(frame.data[0]) : 0U,
                       static_cast<unsigned>(frame.dlc), static_cast<unsigned>(stats_.malformed));
    }
}

void IsoTpChannel::abortReceptionForNew(const char* what) {
    ++stats_.rxAbortedByNew;
    if (core::isReportableOccurrence(stats_.rxAbortedByNew)) {
        events_.report(events::kIsoTpRxAbortedByNew, Severity::kWarning,
                       "isotp rx 0x%03X: %s during a reception: %u of %u bytes abandoned (%u times)",
                       static_cast<unsigned>(config_.rxId), what, u(rxOffset_), u(rxLength_),
                       static_cast<unsigned>(stats_.rxAbortedByNew));
    }
    rxState_ = RxState::kIdle;
    rxFcPending_ = false;
}

void IsoTpChannel::handleSingle(const CanFrame& frame) {
    const std::size_t length = lowNibble(frame.data[0]);
    if (length == 0 || length > kSfMaxData) {
        malformed("SF_DL 0 or > 7", frame);
        return;
    }
    if (length + 1 > frame.dlc) {
        malformed("SF shorter than its SF_DL", frame);
        return;
    }
    peerStartedMessage_ = true;
    if (rxState_ == RxState::kReceiving) {
        abortReceptionForNew("SF");
    }
    deliver(&frame.data[1], length);
}

void IsoTpChannel::handleFirst(const CanFrame& frame, TimeNs now) {
    if (frame.dlc < kCanMaxDlc) {
        malformed("FF with DLC < 8", frame);
        return;
    }
    const std::size_t length = (static_cast<std::size_t>(lowNibble(frame.data[0])) << 8) | frame.data[1];
    if (length == 0) {
        // FF_DL escape: a 32-bit length in bytes 2..5, only for messages > 4095 bytes
        // (ISO 15765-2:2016). Never one we can take.
        const std::uint32_t length32 = (static_cast<std::uint32_t>(frame.data[2]) << 24) |
                                       (static_cast<std::uint32_t>(frame.data[3]) << 16) |
                                       (static_cast<std::uint32_t>(frame.data[4]) << 8) |
                                       static_cast<std::uint32_t>(frame.data[5]);
        if (length32 <= kIsoTpMaxMessage) {
            malformed("escape FF with FF_DL <= 4095", frame);
            return;
        }
        peerStartedMessage_ = true;
        if (rxState_ == RxState::kReceiving) {
            abortReceptionForNew("FF");
        }
        refuseTooLong(length32, now);
        return;
    }
    if (length < kFfMinLength) {
        ++stats_.ffTooShort;
        if (core::isReportableOccurrence(stats_.ffTooShort)) {
            events_.report(events::kIsoTpFfTooShort, Severity::kWarning,
                           "isotp rx 0x%03X: FF with FF_DL %u < 8, ignored (%u times)",
                           static_cast<unsigned>(config_.rxId), u(length),
                           static_cast<unsigned>(stats_.ffTooShort));
        }
        return;
    }
    peerStartedMessage_ = true;
    if (rxState_ == RxState::kReceiving) {
        abortReceptionForNew("FF");
    }
    if (length > config_.maxRxLength) {
        refuseTooLong(static_cast<std::uint32_t>(length), now);
        return;
    }
    std::memcpy(rxBuf_, &frame.data[2], kFfData);
    rxLength_ = length;
    rxOffset_ = kFfData;
    rxSn_ = 1;
    rxBlockCount_ = 0;
    rxState_ = RxState::kReceiving;
    queueFlowControl(kFsClearToSend, now);
}

void IsoTpChannel::refuseTooLong(std::uint32_t length, TimeNs now) {
    ++stats_.rxTooLong;
    if (core::isReportableOccurrence(stats_.rxTooLong)) {
        events_.report(events::kIsoTpRxTooLong, Severity::kWarning,
                       "isotp rx 0x%03X: FF announces %u bytes (max %u): FC OVERFLOW (%u times)",
                       static_cast<unsigned>(config_.rxId), static_cast<unsigned>(length),
                       static_cast<unsigned>(config_.maxRxLength), static_cast<unsigned>(stats_.rxTooLong));
    }
    queueFlowControl(kFsOverflow, now);
}

void IsoTpChannel::handleConsecutive(const CanFrame& frame, TimeNs now) {
    if (frame.dlc < 2) {
        malformed("CF without data", frame);
        return;
    }
    if (rxState_ != RxState::kReceiving || rxFcPending_) {
        ++stats_.unexpectedCf;
        if (core::isReportableOccurrence(stats_.unexpectedCf)) {
            events_.report(events::kIsoTpUnexpectedCf, Severity::kWarning,
                           "isotp rx 0x%03X: CF SN %u with no reception in progress, ignored (%u times)",
                           static_cast<unsigned>(config_.rxId), static_cast<unsigned>(lowNibble(frame.data[0])),
                           static_cast<unsigned>(stats_.unexpectedCf));
        }
        return;
    }
    const std::size_t remaining = rxLength_ - rxOffset_;
    const std::size_t n = remaining < kCfMaxData ? remaining : kCfMaxData;
    if (static_cast<std::size_t>(frame.dlc) - 1 < n) {
        malformed("CF shorter than the data still due", frame);
        return;
    }
    const std::uint8_t sn = lowNibble(frame.data[0]);
    if (sn != rxSn_) {
        ++stats_.wrongSequence;
        if (core::isReportableOccurrence(stats_.wrongSequence)) {
            events_.report(events::kIsoTpWrongSequence, Severity::kWarning,
                           "isotp rx 0x%03X: CF SN %u, expected %u: %u of %u bytes dropped (%u times)",
                           static_cast<unsigned>(config_.rxId), static_cast<unsigned>(sn),
                           static_cast<unsigned>(rxSn_), u(rxOffset_), u(rxLength_),
                           static_cast<unsigned>(stats_.wrongSequence));
        }
        rxState_ = RxState::kIdle;
        return;
    }
    std::memcpy(&rxBuf_[rxOffset_], &frame.data[1], n);
    rxOffset_ += n;
    rxSn_ = static_cast<std::uint8_t>((rxSn_ + 1) & 0x0F);
    if (rxOffset_ >= rxLength_) {
        rxState_ = RxState::kIdle;
        deliver(rxBuf_, rxLength_);
        return;
    }
    ++rxBlockCount_;
    if (config_.blockSize != 0 && rxBlockCount_ >= config_.blockSize) {
        rxBlockCount_ = 0;
        queueFlowControl(kFsClearToSend, now);
        return;
    }
    rxCrDeadline_ = now + config_.nCr;
}

bool IsoTpChannel::transmitFlowControl(std::uint8_t flowStatus) {
    std::uint8_t b[kFcLength] = {};
    b[0] = static_cast<std::uint8_t>((kPciFlowControl << 4) | flowStatus);
    if (flowStatus == kFsClearToSend) {
        b[1] = config_.blockSize;
        b[2] = config_.stMin;
    }
    return transmit(b, kFcLength);
}

void IsoTpChannel::queueFlowControl(std::uint8_t flowStatus, TimeNs now) {
    rxFcStatus_ = flowStatus;
    if (transmitFlowControl(flowStatus)) {
        rxFcPending_ = false;
        rxCrDeadline_ = now + config_.nCr;
    } else {
        rxFcPending_ = true;  // retried by poll() until N_Ar
        rxArDeadline_ = now + config_.nAr;
    }
}

void IsoTpChannel::pollRx(TimeNs now) {
    if (rxFcPending_) {
        if (transmitFlowControl(rxFcStatus_)) {
            rxFcPending_ = false;
            rxCrDeadline_ = now + config_.nCr;
        } else if (now >= rxArDeadline_) {
            ++stats_.timeoutAr;
            events_.report(events::kIsoTpTimeoutAr, Severity::kWarning,
                           "isotp rx 0x%03X: N_Ar: bus refused our FC for %lld ms; %u of %u bytes dropped",
                           static_cast<unsigned>(config_.rxId), ms(config_.nAr),
                           rxState_ == RxState::kReceiving ? u(rxOffset_) : 0U,
                           rxState_ == RxState::kReceiving ? u(rxLength_) : 0U);
            rxFcPending_ = false;
            rxState_ = RxState::kIdle;
        }
        return;
    }
    if (rxState_ == RxState::kReceiving && now >= rxCrDeadline_) {
        ++stats_.timeoutCr;
        events_.report(events::kIsoTpTimeoutCr, Severity::kWarning,
                       "isotp rx 0x%03X: N_Cr: no CF in %lld ms; %u of %u bytes dropped",
                       static_cast<unsigned>(config_.rxId), ms(config_.nCr), u(rxOffset_), u(rxLength_));
        rxState_ = RxState::kIdle;
    }
}

void IsoTpChannel::poll() {
    if (!configValid_) {
        return;
    }
    const TimeNs now = clock_.now();
    pollRx(now);
    if (peerStartedMessage_) {
        peerStartedMessage_ = false;
        if (config_.resendFirstFrameOnPeerMessage && awaitingFirstFc()) {
            resendFirstFrame(now);
        }
    }
    pollTx(now);
}

// ---------------------------------------------------------------------------
// Completed messages.

void IsoTpChannel::storeWrite(std::size_t position, const std::uint8_t* src, std::size_t count) {
    const std::size_t first = count < kIsoTpRxStoreBytes - position ? count : kIsoTpRxStoreBytes - position;
    std::memcpy(&store_[position], src, first);
    if (count > first) {
        std::memcpy(store_, src + first, count - first);
    }
}

void IsoTpChannel::storeRead(std::size_t position, std::uint8_t* dst, std::size_t count) const {
    const std::size_t first = count < kIsoTpRxStoreBytes - position ? count : kIsoTpRxStoreBytes - position;
    std::memcpy(dst, &store_[position], first);
    if (count > first) {
        std::memcpy(dst + first, store_, count - first);
    }
}

void IsoTpChannel::deliver(const std::uint8_t* data, std::size_t length) {
    const std::size_t need = kStoreHeader + length;
    if (need > kIsoTpRxStoreBytes - storeUsed_) {
        ++stats_.rxOverruns;
        if (core::isReportableOccurrence(stats_.rxOverruns)) {
            events_.report(events::kIsoTpRxOverrun, Severity::kWarning,
                           "isotp rx 0x%03X: %u-byte message dropped, %u messages unread (%u times)",
                           static_cast<unsigned>(config_.rxId), u(length), u(storeCount_),
                           static_cast<unsigned>(stats_.rxOverruns));
        }
        return;
    }
    const std::uint8_t header[kStoreHeader] = {static_cast<std::uint8_t>(length >> 8),
                                               static_cast<std::uint8_t>(length & 0xFF)};
    const std::size_t tail = (storeHead_ + storeUsed_) % kIsoTpRxStoreBytes;
    storeWrite(tail, header, kStoreHeader);
    storeWrite((tail + kStoreHeader) % kIsoTpRxStoreBytes, data, length);
    storeUsed_ += need;
    ++storeCount_;
    ++stats_.rxMessages;
}

Status IsoTpChannel::receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) {
    if (length == nullptr || (out == nullptr && capacity > 0)) {
        return Status::kInvalidArgument;
    }
    if (storeCount_ == 0) {
        return Status::kEmpty;
    }
    std::uint8_t header[kStoreHeader] = {};
    storeRead(storeHead_, header, kStoreHeader);
    const std::size_t size = (static_cast<std::size_t>(header[0]) << 8) | header[1];
    *length = size;
    if (size > capacity) {
        return Status::kTooLarge;
    }
    storeRead((storeHead_ + kStoreHeader) % kIsoTpRxStoreBytes, out, size);
    storeHead_ = (storeHead_ + kStoreHeader + size) % kIsoTpRxStoreBytes;
    storeUsed_ -= kStoreHeader + size;
    --storeCount_;
    if (storeCount_ == 0) {
        storeHead_ = 0;
        storeUsed_ = 0;
    }
    return Status::kOk;
}

}  // namespace rse::hal
