// ISO-TP (ISO 15765-2) transport over any CanBus: classic CAN, normal addressing,
// 11-bit identifiers, messages of 1..4095 bytes. Carries ground command and
// telemetry packets (docs/icd.md section 2: rover receives on 0x6C0, sends on 0x6C1).
// Written to interoperate with the Linux kernel's can-isotp (can-utils isotpsend /
// isotprecv), but implemented here so it runs on any backend and without Linux.
//
// Frames (byte 0 is the N_PCI):
//   Single Frame      0x0N            N = 1..7 data bytes
//   First Frame       0x1L LL         12-bit length 8..4095, then 6 data bytes
//   Consecutive Frame 0x2S            S = 1, 2, ... 15, 0, 1 ... (the FF counts as 0), 7 data bytes
//   Flow Control      0x3F BS STmin   F = 0 clear to send, 1 wait, 2 overflow
//
// One IsoTpChannel is one full-duplex connection: it sends on txId (SF, FF, CF and
// the FCs for what it receives) and listens on rxId. It never reads the bus: the
// owner demultiplexes by CAN id and calls onFrame() for every frame whose id is
// rxId, and calls poll() every cycle. Non-blocking throughout; no heap; every loop
// is bounded by a documented constant.
//
// Behaviour chosen where the brief or the standard leaves room:
//   - Sending: send() copies the message and transmits the SF or FF at once. CFs go
//     out only from poll(). When the receiver's STmin is 0, one poll sends the rest
//     of the block, at most kIsoTpMaxCfPerPoll CFs; when STmin is not 0, one poll
//     sends at most one CF, and never sooner than STmin after the previous CF of the
//     message (also across a block boundary: conservative, STmin is a minimum). So
//     with a 100 Hz poll any STmin between 100 us and 10 ms means "one CF per poll";
//     only STmin = 0 goes faster. BS and STmin are taken from the first FC.CTS of a
//     message and kept for the whole message; reserved STmin values (0x80-0xF0,
//     0xFA-0xFF) are treated as 0x7F = 127 ms.
//   - Frames the bus refuses (kFull, or kUnavailable while the link is down) are
//     retried on the next poll until N_As (data frames) or N_Ar (our FC) expires,
//     counted in txRefused.
//   - Receiving: the FC we send asks for config.blockSize and config.stMin (the ICD
//     asks for BS 8, STmin 0: the peer sends at most 8 CFs back to back, which
//     bounds the burst the owner must drain in one cycle). We never send FC.WAIT.
//     Completed messages go into a byte FIFO of kIsoTpRxStoreBytes (each message
//     costs its length + 2 bytes): at least two 4095-byte messages, or hundreds of
//     short commands, wait there until receive() takes them. A message that
//     completes when the FIFO has no room is dropped (the newer one; what is queued
//     is kept), counted in rxOverruns and evented.
//   - A peer that was not listening: with resendFirstFrameOnPeerMessage, when the
//     peer starts a message of its own (a valid SF or FF) while our FF still waits
//     for its first FC (no FC.CTS or FC.WAIT yet), poll() sends the FF again and
//     N_Bs restarts, instead of waiting out N_Bs and dropping the message. A
//     listening peer answers an FF at once, so an FF still unanswered when the
//     peer is heard went out before it listened (a ground tool that comes and
//     goes). Checked in poll(), after the owner has handed over every frame of the
//     cycle, so an FC that arrived with the peer's message counts first; a peer
//     message heard before send() began ours does not count for it. Should both
//     FCs still come (the peer did get the first FF), the second is an unexpected
//     FC, ignored. Counted in ffResent.
//   - Padding: with padFrames every frame we send has DLC 8, filled with padByte
//     (0xCC by default, as can-isotp); without it every frame has its natural DLC
//     (FC = 3). Received frames are accepted padded or not, whatever padFrames says.
//   - Malformed frames (DLC too small for the PCI, SF_DL 0 or > 7, unknown N_PCI
//     type, escape FF with a length that fits 12 bits) and FFs with FF_DL < 8 are
//     ignored: they do not disturb a reception in progress (ISO 15765-2: the network
//     layer ignores them). A well-formed SF or FF during a reception aborts it and
//     starts over with the later one. An FC with an unknown flow status aborts our transmission.
//
// Errors: each reason has its own counter in IsoTpStats and its own event id
// (hal/can/can_events.hpp, 350-399). Reasons a peer can provoke frame after frame
// (malformed, unexpected, wrong sequence ...) and misuse of send() are evented on
// their 1st, 2nd, 4th, 8th ... occurrence (core::isReportableOccurrence); timeouts
// and transmissions refused by the peer (at most one per message) are evented every
// time. Every error leaves the affected direction idle, ready for the next message.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/status.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/can/can_frame.hpp"

namespace rse::hal {

// Largest message (12-bit FF_DL, classic CAN). The size of each channel's transmit
// and reassembly buffers.
constexpr std::size_t kIsoTpMaxMessage = 4095;
// Longest message sent as one Single Frame (classic CAN): it needs no flow control.
constexpr std::size_t kIsoTpMaxSingleFrame = 7;
// Completed-message FIFO per channel: two largest messages with their 2-byte length.
constexpr std::size_t kIsoTpRxStoreBytes = 2 * (kIsoTpMaxMessage + 2);
// CFs one poll() may send when the receiver asked for STmin 0 (so a poll never runs
// long, and a peer with a small receive queue is not flooded by BS 0).
constexpr std::size_t kIsoTpMaxCfPerPoll = 32;
constexpr core::TimeNs kIsoTpDefaultTimeout = 1000 * core::kNsPerMs;  // N_As, N_Ar, N_Bs, N_Cr
constexpr std::uint8_t kIsoTpDefaultPadByte = 0xCC;                   // can-isotp's default
constexpr std::uint8_t kIsoTpDefaultMaxWaitFrames = 10;               // N_WFTmax
constexpr std::uint8_t kIsoTpStMinReservedAs = 0x7F;                  // 127 ms

struct IsoTpConfig {
    std::uint32_t txId = 0;       // 11-bit id we send on (data frames and our FCs)
    std::uint32_t rxId = 0;       // 11-bit id we receive on (the owner routes it to onFrame)
    std::uint8_t blockSize = 8;   // BS in the FCs we send (0: the peer sends all CFs without more FC)
    std::uint8_t stMin = 0;       // STmin in the FCs we send: 0x00-0x7F ms or 0xF1-0xF9 (100-900 us)
    bool padFrames = false;       // pad every frame we send to DLC 8 ...
    std::uint8_t padByte = kIsoTpDefaultPadByte;  // ... with this byte
    core::TimeNs nAs = kIsoTpDefaultTimeout;  // a data frame we send must be accepted by the bus within this
    core::TimeNs nAr = kIsoTpDefaultTimeout;  // an FC we send must be accepted by the bus within this
    core::TimeNs nBs = kIsoTpDefaultTimeout;  // sender: FC expected within this after the FF, a block or a WAIT
    core::TimeNs nCr = kIsoTpDefaultTimeout;  // receiver: next CF expected within this
    std::uint8_t maxWaitFrames = kIsoTpDefaultMaxWaitFrames;  // consecutive FC.WAIT accepted (sender side)
    std::uint16_t maxRxLength = kIsoTpMaxMessage;  // longest message we accept (8..4095); longer: FC OVERFLOW
    bool resendFirstFrameOnPeerMessage = false;    // see "A peer that was not listening" above
};

// A configuration the channel can run with: ids <= 0x7FF and different, STmin not
// reserved, every timeout > 0, maxRxLength 8..4095.
bool isValidIsoTpConfig(const IsoTpConfig& config);

// STmin byte -> nanoseconds (reserved values -> 127 ms, per ISO 15765-2).
core::TimeNs isoTpStMinToNs(std::uint8_t stMin);

// How the last transmission ended (or that one is under way).
enum class IsoTpTxResult : std::uint8_t {
    kIdle = 0,           // nothing sent yet
    kInProgress,
    kDone,               // every frame accepted by the bus
    kTimeoutAs,          // the bus did not accept a frame within N_As
    kTimeoutBs,          // no FC within N_Bs
    kPeerOverflow,       // the receiver answered FC OVERFLOW
    kWaitLimit,          // more than maxWaitFrames consecutive FC.WAIT
    kInvalidFlowStatus,  // FC with a flow status other than 0, 1, 2
};
const char* toString(IsoTpTxResult result);

struct IsoTpStats {
    // Traffic.
    std::uint32_t txMessages = 0;     // messages completely sent
    std::uint32_t rxMessages = 0;     // messages completely received and queued for receive()
    std::uint32_t txFrames = 0;       // frames accepted by the bus (SF, FF, CF, FC)
    std::uint32_t rxFrames = 0;       // frames handed to onFrame with our rxId
    std::uint32_t txRefused = 0;      // bus refused a frame; retried next poll (N_As / N_Ar running)
    std::uint32_t waitsReceived = 0;  // FC.WAIT frames accepted
    std::uint32_t ffResent = 0;       // unanswered FFs sent again when the peer was heard
    std::uint32_t foreignFrames = 0;  // onFrame with another id, extended or remote frame: ignored
    // Error reasons: one event id each (can_events.hpp).
    std::uint32_t wrongSequence = 0;      // CF with the wrong SN: reception aborted
    std::uint32_t unexpectedCf = 0;       // CF with no reception in progress: ignored
    std::uint32_t unexpectedFc = 0;       // FC with no transmission waiting for one: ignored
    std::uint32_t rxAbortedByNew = 0;     // SF or FF during a reception: old one abandoned, the later one taken
    std::uint32_t timeoutAs = 0;          // transmission aborted
    std::uint32_t timeoutAr = 0;          // reception aborted (our FC could not be sent)
    std::uint32_t timeoutBs = 0;          // transmission aborted
    std::uint32_t timeoutCr = 0;          // reception aborted
    std::uint32_t peerOverflow = 0;       // FC OVERFLOW received: transmission aborted
    std::uint32_t waitLimit = 0;          // too many FC.WAIT: transmission aborted
    std::uint32_t rxTooLong = 0;          // FF_DL > maxRxLength: FC OVERFLOW sent
    std::uint32_t ffTooShort = 0;         // FF with FF_DL < 8: ignored
    std::uint32_t malformed = 0;          // DLC too small, SF_DL 0 or > 7, unknown N_PCI, bad escape FF: ignored
    std::uint32_t invalidFlowStatus = 0;  // FC with flow status 3..15: transmission aborted
    std::uint32_t rxOverruns = 0;         // completed message dropped: receive FIFO full
    std::uint32_t sendBusy = 0;           // send() during a transmission: kBusy
    std::uint32_t sendInvalid = 0;        // send() of 0 or > 4095 bytes (or null data): kInvalidArgument
};

class IsoTpChannel {
public:
    // An invalid config (isValidIsoTpConfig) is evented (kIsoTpConfigInvalid) and
    // leaves the channel inert: send() returns kNotInitialized, frames are ignored.
    IsoTpChannel(CanBus& bus, const core::Clock& clock, core::EventLog& events, const IsoTpConfig& config);

    IsoTpChannel(const IsoTpChannel&) = delete;
    IsoTpChannel& operator=(const IsoTpChannel&) = delete;

    // Starts sending a message of 1..kIsoTpMaxMessage bytes (copied; the caller's
    // buffer is free on return). kOk: under way (the SF or FF may still be waiting
    // for room on the bus); kBusy: a transmission is in progress; kInvalidArgument:
    // null data or a length outside 1..4095; kNotInitialized: invalid config.
    core::Status send(const std::uint8_t* data, std::size_t length);

    // A frame the owner received with id == config.rxId.
    void onFrame(const CanFrame& frame);

    // Every cycle: sends due CFs (STmin, BS, kIsoTpMaxCfPerPoll), retries frames the
    // bus refused, checks N_As / N_Ar / N_Bs / N_Cr.
    void poll();

    // The oldest completed message: kOk with *length bytes in out; kEmpty when none;
    // kTooLarge when it is longer than capacity (*length says how long; it stays
    // queued); kInvalidArgument for a null length (or null out with capacity > 0).
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length);

    bool txBusy() const { return txState_ != TxState::kIdle; }
    bool rxBusy() const { return rxState_ != RxState::kIdle; }
    IsoTpTxResult txResult() const { return txResult_; }
    std::size_t pendingMessages() const { return storeCount_; }
    bool configValid() const { return configValid_; }
    const IsoTpConfig& config() const { return config_; }
    const IsoTpStats& stats() const { return stats_; }

private:
    enum class TxState : std::uint8_t { kIdle, kSendSf, kSendFf, kWaitFc, kSendCf };
    enum class RxState : std::uint8_t { kIdle, kReceiving };

    bool transmit(const std::uint8_t* bytes, std::size_t count);
    bool transmitFirstFrame();
    bool awaitingFirstFc() const;
    void resendFirstFrame(core::TimeNs now);
    void firstFrameSent(core::TimeNs now);
    void armAs(core::TimeNs now);
    void pollTx(core::TimeNs now);
    void pollRx(core::TimeNs now);
    void sendConsecutiveFrames(core::TimeNs now);
    void finishTx(IsoTpTxResult result);
    void failTx(IsoTpTxResult result, unsigned detail);

    void handleSingle(const CanFrame& frame);
    void handleFirst(const CanFrame& frame, core::TimeNs now);
    void handleConsecutive(const CanFrame& frame, core::TimeNs now);
    void handleFlowControl(const CanFrame& frame, core::TimeNs now);
    bool transmitFlowControl(std::uint8_t flowStatus);
    void queueFlowControl(std::uint8_t flowStatus, core::TimeNs now);
    void refuseTooLong(std::uint32_t length, core::TimeNs now);
    void abortReceptionForNew(const char* what);
    void malformed(const char* why, const CanFrame& frame);
    void deliver(const std::uint8_t* data, std::size_t length);

    void storeWrite(std::size_t position, const std::uint8_t* src, std::size_t count);
    void storeRead(std::size_t position, std::uint8_t* dst, std::size_t count) const;

    CanBus& bus_;
    const core::Clock& clock_;
    core::EventLog& events_;
    IsoTpConfig config_;
    bool configValid_;
    IsoTpStats stats_;

    // Transmit direction.
    TxState txState_ = TxState::kIdle;
    IsoTpTxResult txResult_ = IsoTpTxResult::kIdle;
    std::size_t txLength_ = 0;
    std::size_t txOffset_ = 0;       // bytes accepted by the bus so far
    std::uint8_t txSn_ = 0;          // SN of the next CF
    bool txHaveFcParams_ = false;    // BS / STmin taken from the first FC.CTS
    std::uint8_t txPeerBs_ = 0;
    core::TimeNs txPeerStMin_ = 0;
    std::size_t txBlockCount_ = 0;   // CFs sent in the current block
    std::uint32_t txWaits_ = 0;      // consecutive FC.WAIT
    core::TimeNs txNextCfAt_ = 0;
    core::TimeNs txBsDeadline_ = 0;
    bool txAsArmed_ = false;         // a frame was refused: N_As running
    core::TimeNs txAsDeadline_ = 0;
    bool peerStartedMessage_ = false;  // a valid SF or FF arrived since the last poll()
    std::uint8_t txBuf_[kIsoTpMaxMessage] = {};

    // Receive direction.
    RxState rxState_ = RxState::kIdle;
    std::size_t rxLength_ = 0;
    std::size_t rxOffset_ = 0;
    std::uint8_t rxSn_ = 0;          // SN expected in the next CF
    std::size_t rxBlockCount_ = 0;   // CFs received since our last FC
    core::TimeNs rxCrDeadline_ = 0;
    bool rxFcPending_ = false;       // an FC the bus refused: retried until N_Ar
    std::uint8_t rxFcStatus_ = 0;
    core::TimeNs rxArDeadline_ = 0;
    std::uint8_t rxBuf_[kIsoTpMaxMessage] = {};

    // Completed messages: [length hi][length lo][bytes...] records in a byte ring.
    std::uint8_t store_[kIsoTpRxStoreBytes] = {};
    std::size_t storeHead_ = 0;   // first byte of the oldest record
    std::size_t storeUsed_ = 0;   // bytes in use
    std::size_t storeCount_ = 0;  // records
};

}  // namespace rse::hal
