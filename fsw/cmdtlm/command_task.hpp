// The command service (cFS's command ingest plus dispatch), every minor frame:
//   1 ingest: read each ground link until it is empty or the per-frame limit is
//     reached: kMaxPacketsPerLink packets per link, or the link's share of
//     kIngestAllowance, whichever comes first (the rest wait in the link for the
//     next frame; such frames are counted, ingestLimited). Every packet is
//     authenticated as it arrives (CommandValidator::authenticate: length,
//     header, checksum, APID, function code, key id, then the MAC): one that
//     fails is rejected at once and never takes a queue slot, so only authentic
//     packets queue. One that passes goes into a fixed queue of kCommandQueueDepth;
//     a packet that finds the queue full is rejected (queue_overflow) - never lost
//     silently. The ingest limit bounds the MAC work per frame.
//   2 dispatch: up to kCommandsPerFrame queued packets are checked in full
//     (CommandValidator::check: again the MAC, then the anti-replay sequence and
//     its persisted reservation, argument ranges, mode) and, when they pass,
//     executed by the application's CommandHandler (the command router,
//     command_router.hpp, which hands each to the application owning its APID).
// HK's cmd_*, auth_* and link_* fields are this task's (fillHousekeeping).
// An unknown key id is acknowledged and evented as bad_mac (linkReason()).
// Every packet yields one CMD_ACK in telemetry (accepted, or the reason), except
// that acknowledgements of rejections that did not authenticate (reasons
// queue_overflow .. stale_sequence) are rate-limited by a token bucket
// (kRejectAcksPerSecond, burst kRejectAckBurst): those beyond it are counted
// (acksSuppressed), so a flood of garbage cannot fill the downlink and starve
// events and housekeeping. Acceptances and authenticated rejections are always
// acknowledged. A second of flood (acknowledgements suppressed, ingest at its
// limit, or packets dropped by the OS) raises one summary event (kIngestFlood).
// docs/icd.md, "Floods".
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_handler.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/ground_links.hpp"
#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kCommandQueueDepth = 8;    // commands waiting between frames
// Ingest bounds per frame (the task's budget is 2 ms, fsw/app/fsw_app.cpp): at most
// kMaxPacketsPerLink packets from a link, and kIngestAllowance of time for all
// links together, of which every link after the first is sure of kIngestLinkReserve.
// A small datagram costs 0.5-0.75 us to read and refuse on the development VM
// (mostly the kernel's recvmmsg), so 1.2 ms drains a 150 000 packet/s flood, and
// leaves 0.8 ms of the budget for dispatch and for the host's hiccups.
constexpr std::size_t kMaxPacketsPerLink = 2048;
constexpr core::TimeNs kIngestAllowance = 1200 * core::kNsPerUs;
constexpr core::TimeNs kIngestLinkReserve = 150 * core::kNsPerUs;
constexpr std::size_t kIngestCheckEvery = 32;    // packets between two looks at the clock
// Two looks at the clock in ingest are at most kIngestCheckEvery packets, some
// 50 us of work, apart. A gap longer than kIngestStallGap is time the thread
// did not spend on ingest (the VM paused, the thread was off the CPU, the kernel
// did other work): a stall. A run's time less its stalls (beyond the gap) is
// what its own work cost, so an overrun can be told from a stalled run
// (CommandCounters::overBudgetLessStalls; docs/icd.md "Floods").
constexpr core::TimeNs kIngestStallGap = 300 * core::kNsPerUs;
constexpr std::size_t kCommandsPerFrame = 2;     // executed per frame (200 commands/s), one MAC each
// A command whose anti-replay reservation is being written waits at the head of
// the queue (AntiReplayState: a write takes a frame or two with a file store);
// after this many frames it is refused, sequence_store_failed detail 1.
constexpr std::uint32_t kMaxStoreWaitFrames = 100;
constexpr std::uint32_t kRejectEventsPerSecond = 8;  // beyond this, rejections are counted, not evented
constexpr std::uint32_t kRejectAcksPerSecond = 20;   // acknowledgements of unauthenticated rejections ...
constexpr std::uint32_t kRejectAckBurst = 20;        // ... a second, and at most this many at once

struct CommandCounters {
    std::uint32_t accepted = 0;
    std::uint32_t rejected = 0;
    std::uint32_t byReason[kRejectReasonCount] = {};
    std::uint32_t rejectEventsSuppressed = 0;
    std::uint16_t lastApid = 0;
    std::uint8_t lastFunctionCode = 0;
    CommandReject lastResult = CommandReject::kAccepted;
    std::uint8_t queueDepth = 0;
    std::uint8_t queueHighWater = 0;
    // Floods (docs/icd.md): what the links saw, summed over them, since the last reset.
    std::uint32_t linkRxPackets = 0;        // packets read from the links
    std::uint32_t linkRxDropped = 0;        // packets a link dropped before ingest saw them (too large, queue full)
    std::uint32_t linkRxKernelDropped = 0;  // packets the OS dropped before a link read them
    std::uint32_t ingestLimited = 0;        // frames in which ingest stopped at its limit on some link
    std::uint32_t acksSuppressed = 0;       // rejection acknowledgements not sent (rate limit)
    std::uint32_t storeWaitFrames = 0;      // frames a command waited for its reservation to be durable
    // Runs of the task (executive clock): how many stalled, how many were over
    // the run budget even with their stalls taken out, and the longest so.
    std::uint32_t stalledRuns = 0;
    std::uint32_t overBudgetLessStalls = 0;
    std::uint32_t longestRunLessStallsUs = 0;
};

class CommandTask final : public core::Task, public HousekeepingContributor {
public:
    CommandTask(const core::Clock& clock, core::EventLog& events, const GroundLinks& links,
                TelemetryOutput& telemetry, CommandHandler& handler);

    // Start-up: the MAC engine (its one allocation) and the events that say how
    // commanding is secured.
    core::Status init();
    KeyStore& keys() { return keys_; }
    void setAuthRequired(bool required) { validator_.setAuthRequired(required); }
    bool authRequired() const { return validator_.authRequired(); }
    // Before init: where the anti-replay reservations persist (none: volatile,
    // RAM only), and whether init may create a missing store / add missing keys
    // at floor 0 (first boot only: rse-fsw --auth-store-create).
    // `writer` (on the same store) takes every write after init, off the task's
    // thread; nullptr: written in the task (hal::ImmediateRecordWriter).
    void attachAuthStore(hal::RecordStore* store, bool provision, hal::RecordWriter* writer = nullptr) {
        validator_.replay().attach(store, writer);
        provisionAuthStore_ = provision;
    }
    // Before or after init: the AUTH_RESYNC nonce's start (a random value per boot).
    void setAuthChallengeSeed(std::uint64_t seed) { validator_.replay().setChallengeSeed(seed); }
    const AntiReplayState& antiReplay() const { return validator_.replay(); }
    const KeyStore& keys() const { return keys_; }
    // Loaded keys refused until AUTH_RESYNC.
    std::uint8_t keysUnsynced() const;
    bool labKeyInUse() const { return keys_.labKeyInUse(); }

    void run(const core::FrameContext& frame) override;
    // The task's budget in the rate-group table, for overBudgetLessStalls (0: not counted).
    void setRunBudget(core::TimeNs budget) { runBudget_ = budget; }

    const CommandCounters& counters() const { return counters_; }
    void resetCounters();
    void fillHousekeeping(HK_Tlm& hk) const override;

private:
    struct QueuedPacket {
        std::uint8_t bytes[kMaxCommandPacket];
        std::uint16_t length;
    };

    void reportAntiReplayState();  // init: reads the store, events what it found
    struct LinkTotals {
        std::uint32_t packets = 0;
        std::uint32_t dropped = 0;
        std::uint32_t kernelDropped = 0;
    };

    void ingest();
    void readIngestClock();  // now_, and a gap longer than kIngestStallGap counted as a stall
    void accountRun(core::TimeNs start);
    bool ingestFrom(hal::PacketLink& link, core::TimeNs deadline);
    void takePacket(std::size_t length);
    // false: the head waits for its reservation (still queued); dispatch stops for this frame.
    bool dispatchOne();
    void reportStoreWriteFailures();
    void acknowledge(const CommandVerdict& verdict);
    void reject(const CommandVerdict& found);
    // Header fields of a packet that was not (fully) validated (too long, bad
    // header, queue overflow), read as far as the bytes allow, for the acknowledgement.
    static void addClaimedFields(CommandVerdict* verdict, const std::uint8_t* packet, std::size_t length);
    // Whether a rejection may be acknowledged now (token bucket for unauthenticated ones).
    bool mayAcknowledgeRejection(const CommandVerdict& verdict);
    LinkTotals linkTotals() const;
    void updateLinkCounters();
    void reportFlood(core::TimeNs now);

    const core::Clock& clock_;
    core::EventLog& events_;
    TelemetryOutput& telemetry_;
    CommandHandler& handler_;
    HmacSha256 hmac_;
    KeyStore keys_;
    CommandValidator validator_;
    const GroundLinks& links_;
    QueuedPacket queue_[kCommandQueueDepth] = {};
    std::size_t head_ = 0;
    std::size_t count_ = 0;
    std::uint32_t headWaitFrames_ = 0;       // frames the head has waited for the store
    std::uint32_t storeFailuresReported_ = 0;
    std::uint8_t scratch_[kMaxCommandPacket + 1] = {};  // one byte more: detects oversize packets
    CommandCounters counters_;
    core::TimeNs now_ = 0;  // the clock as last read in this run (read every kIngestCheckEvery packets)
    core::TimeNs stalledNs_ = 0;  // this run's stalls, beyond kIngestStallGap each
    core::TimeNs runBudget_ = 0;
    core::TimeNs rejectWindowStart_ = 0;
    std::uint32_t rejectEventsInWindow_ = 0;
    bool provisionAuthStore_ = false;
    // Rejection acknowledgements: token bucket, in tokens x kNsPerSec.
    core::TimeNs ackTokens_ = static_cast<core::TimeNs>(kRejectAckBurst) * core::kNsPerSec;
    core::TimeNs ackRefilledAt_ = 0;
    bool ackBucketStarted_ = false;
    // Link counters at the last reset (they are cumulative in the links).
    LinkTotals linkBaseline_;
    // The flood summary: counters at the start of the current second.
    core::TimeNs floodWindowStart_ = 0;
    bool floodWindowStarted_ = false;
    CommandCounters floodMark_;
};

}  // namespace rse::cmdtlm
