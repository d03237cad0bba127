#include "fsw/cmdtlm/command_task.hpp"

#include <cstring>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

CommandTask::CommandTask(const core::Clock& clock, core::EventLog& events, const GroundLinks& links,
                         TelemetryOutput& telemetry, CommandHandler& handler)
    : clock_(clock),
      events_(events),
      telemetry_(telemetry),
      handler_(handler),
      validator_(keys_, hmac_),
      links_(links) {}

core::Status CommandTask::init() {
    const core::Status status = hmac_.init();
    if (!core::isOk(status)) {
        events_.report(events::kCmdInitFailed, core::Severity::kCritical,
                       "cmd: HMAC-SHA-256 engine unavailable (%s)", core::toString(status));
        return status;
    }
    reportAntiReplayState();
    if (keys_.labKeyInUse()) {
        events_.report(events::kLabKeyInUse, core::Severity::kWarning,
                       "cmd: the public lab key (id %u) authenticates commands: not for flight",
                       static_cast<unsigned>(keys_.labKeyId()));
    }
    if (!validator_.authRequired()) {
        events_.report(events::kAuthDisabled, core::Severity::kWarning,
                       "cmd: lab setting: unauthenticated commands (key id 0) accepted");
    }
    return core::Status::kOk;
}

void CommandTask::reportAntiReplayState() {
    AntiReplayState& replay = validator_.replay();
    replay.load(keys_, provisionAuthStore_);
    switch (replay.state()) {
        case AuthStoreState::kVolatile:
            events_.report(events::kAuthStoreVolatile, core::Severity::kWarning,
                           "cmd: anti-replay state in RAM only (no store): a restart forgets it");
            return;
        case AuthStoreState::kOk:
            break;
        case AuthStoreState::kMissing:
        case AuthStoreState::kCorrupt:
        case AuthStoreState::kUnreadable:
            events_.report(events::kAuthStoreUnusable, core::Severity::kCritical,
                           "cmd: anti-replay store %s: commands refused until AUTH_RESYNC (nonce in HK)",
                           toString(replay.state()));
            break;
    }
    if (!core::isOk(replay.lastWriteStatus())) {
        events_.report(events::kAuthStoreWriteFailed, core::Severity::kError,
                       "cmd: anti-replay store could not be created (%s)", core::toString(replay.lastWriteStatus()));
    }
    for (std::size_t i = 0; i < keys_.size(); ++i) {
        const std::uint16_t id = keys_.idAt(i);
        const Unsynced why = replay.unsynced(id);
        if (why == Unsynced::kSynced) {
            events_.report(events::kAuthStoreLoaded, core::Severity::kInfo,
                           "cmd: key %u: anti-replay numbers up to %u refused (stored reservation)",
                           static_cast<unsigned>(id), static_cast<unsigned>(replay.reserved(id)));
        } else if (why == Unsynced::kKeyNotStored) {
            events_.report(events::kAuthKeyUnsynced, core::Severity::kError,
                           "cmd: key %u has no anti-replay reservation in the store: refused until AUTH_RESYNC",
                           static_cast<unsigned>(id));
        }
    }
    storeFailuresReported_ = replay.writeFailures();  // the creation failure is evented above
    if (!replay.challengeReady()) {
        events_.report(events::kAuthNoChallenge, core::Severity::kWarning,
                       "cmd: no AUTH_RESYNC nonce (no random source): a key out of sync stays refused");
    }
}

std::uint8_t CommandTask::keysUnsynced() const {
    std::uint8_t n = 0;
    for (std::size_t i = 0; i < keys_.size(); ++i) {
        n = static_cast<std::uint8_t>(n + (validator_.replay().unsynced(keys_.idAt(i)) != Unsynced::kSynced ? 1 : 0));
    }
    return n;
}

void CommandTask::run(const core::FrameContext&) {
    const core::TimeNs start = clock_.now();
    now_ = start;
    stalledNs_ = 0;
    handler_.serviceOnboardRequests();
    links_.serviceCommandTaskLinks();  // before ingest: a UDP link's error reports leave room for commands
    ingest();
    now_ = clock_.now();
    validator_.replay().service();
    for (std::size_t i = 0; i < kCommandsPerFrame && count_ > 0; ++i) {
        if (!dispatchOne()) {
            break;
        }
    }
    reportStoreWriteFailures();
    accountRun(start);
    counters_.queueDepth = static_cast<std::uint8_t>(count_);
    updateLinkCounters();
    reportFlood(clock_.now());
}

// Every link in turn, within kIngestAllowance for all of them: link i (of n)
// stops at kIngestAllowance - (n - 1 - i) * kIngestLinkReserve, so a flooded
// link leaves each link after it at least kIngestLinkReserve of the frame.
void CommandTask::ingest() {
    bool limited = false;
    now_ = clock_.now();  // stalls are looked for from here on
    const core::TimeNs start = now_;
    const std::size_t n = links_.size();
    for (std::size_t l = 0; l < n; ++l) {
        hal::PacketLink* link = links_.at(l);
        const core::TimeNs deadline =
            start + kIngestAllowance - static_cast<core::TimeNs>(n - 1 - l) * kIngestLinkReserve;
        if (link != nullptr && ingestFrom(*link, deadline)) {
            limited = true;
        }
    }
    if (limited) {
        ++counters_.ingestLimited;  // what is left waits in the link for the next frame
    }
}

// One link until it is empty (false), or its packet limit or deadline is reached
// (true). The clock is read every kIngestCheckEvery packets; rejections between
// two reads are timed with the last one.
bool CommandTask::ingestFrom(hal::PacketLink& link, core::TimeNs deadline) {
    for (std::size_t n = 0; n < kMaxPacketsPerLink; ++n) {
        if (n % kIngestCheckEvery == 0) {
            readIngestClock();
            if (n > 0 && now_ >= deadline) {  // every link gets one round at least
                return true;
            }
        }
        std::size_t length = 0;
        const core::Status status = link.receive(scratch_, sizeof scratch_, &length);
        if (status == core::Status::kEmpty) {
            return false;
        }
        if (status == core::Status::kTooLarge || (core::isOk(status) && length > kMaxCommandPacket)) {
            // Longer than any command: refused before it takes a queue slot.
            CommandVerdict v;
            addClaimedFields(&v, scratch_, core::isOk(status) ? length : 0);
            v.reason = CommandReject::kBadLength;
            reject(v);
            continue;
        }
        if (!core::isOk(status)) {
            return false;  // the link counts its own errors
        }
        takePacket(length);
    }
    return true;
}

void CommandTask::readIngestClock() {
    const core::TimeNs t = clock_.now();
    if (t - now_ > kIngestStallGap) {
        stalledNs_ += t - now_ - kIngestStallGap;
    }
    now_ = t;
}

void CommandTask::accountRun(core::TimeNs start) {
    const core::TimeNs elapsed = clock_.now() - start;
    const core::TimeNs own = elapsed > stalledNs_ ? elapsed - stalledNs_ : 0;
    if (stalledNs_ > 0) {
        ++counters_.stalledRuns;
    }
    if (runBudget_ > 0 && own > runBudget_) {
        ++counters_.overBudgetLessStalls;
    }
    const auto ownUs = static_cast<std::uint32_t>(own / core::kNsPerUs);
    if (ownUs > counters_.longestRunLessStallsUs) {
        counters_.longestRunLessStallsUs = ownUs;
    }
}

// Cheap rejection first: a packet that fails the screen never reaches the MAC,
// and one that fails either never reaches the queue.
void CommandTask::takePacket(std::size_t length) {
    CommandVerdict screened = validator_.authenticate(scratch_, length);
    if (screened.reason != CommandReject::kAccepted) {
        if (screened.reason <= CommandReject::kBadHeader) {
            addClaimedFields(&screened, scratch_, length);
        }
        reject(screened);
        return;
    }
    if (count_ >= kCommandQueueDepth) {
        CommandVerdict v;
        addClaimedFields(&v, scratch_, length);
        v.reason = CommandReject::kQueueOverflow;
        v.detail = static_cast<std::int16_t>(kCommandQueueDepth);
        reject(v);
        return;
    }
    QueuedPacket& slot = queue_[(head_ + count_) % kCommandQueueDepth];
    std::memcpy(slot.bytes, scratch_, length);
    slot.length = static_cast<std::uint16_t>(length);
    ++count_;
    if (count_ > counters_.queueHighWater) {
        counters_.queueHighWater = static_cast<std::uint8_t>(count_);
    }
}

bool CommandTask::dispatchOne() {
    const QueuedPacket& packet = queue_[head_];
    CommandVerdict verdict = validator_.check(packet.bytes, packet.length, handler_.mode());
    if (verdict.deferred && headWaitFrames_ < kMaxStoreWaitFrames) {
        ++headWaitFrames_;  // in order: the commands behind it wait too
        ++counters_.storeWaitFrames;
        return false;
    }
    if (verdict.deferred) {
        verdict.detail = 1;  // waited kMaxStoreWaitFrames: refused as if the write had failed
    }
    headWaitFrames_ = 0;
    head_ = (head_ + 1) % kCommandQueueDepth;
    --count_;
    if (verdict.reason != CommandReject::kAccepted) {
        if (verdict.command == nullptr && verdict.reason <= CommandReject::kBadHeader) {
            addClaimedFields(&verdict, packet.bytes, packet.length);
        }
        reject(verdict);
        return true;
    }
    const CommandOutcome outcome = handler_.execute(verdict);
    if (!outcome.ok) {
        verdict.reason = CommandReject::kExecutionFailed;
        verdict.detail = outcome.detail;
        reject(verdict);
        return true;
    }
    ++counters_.accepted;
    counters_.lastApid = verdict.header.apid;
    counters_.lastFunctionCode = verdict.functionCode;
    counters_.lastResult = CommandReject::kAccepted;
    if (verdict.command->code != CommandCode::NOOP && verdict.command->code != CommandCode::RESET_COUNTERS) {
        events_.report(events::kCommandExecuted, core::Severity::kDebug, "cmd: %s executed (key %u, seq %u)",
                       verdict.command->name, static_cast<unsigned>(verdict.keyId),
                       static_cast<unsigned>(verdict.authSequence));
    }
    acknowledge(verdict);
    return true;
}

// Failed reservation writes (a command's or an early renewal's): evented on the
// 1st, 2nd, 4th ... failure, whatever the rejection throttle does.
void CommandTask::reportStoreWriteFailures() {
    const AntiReplayState& replay = validator_.replay();
    const std::uint32_t failures = replay.writeFailures();
    if (failures == storeFailuresReported_) {
        return;
    }
    storeFailuresReported_ = failures;
    if ((failures & (failures - 1)) == 0) {
        events_.report(events::kAuthStoreWriteFailed, core::Severity::kError,
                       "cmd: anti-replay reservation write failed (%s), %u failures: a command past the reservation is refused",
                       core::toString(replay.lastWriteStatus()), static_cast<unsigned>(failures));
    }
}

void CommandTask::reject(const CommandVerdict& found) {
    ++counters_.rejected;
    const auto reason = static_cast<std::size_t>(found.reason);
    if (reason < kRejectReasonCount) {
        ++counters_.byReason[reason];  // the true reason: HK keeps unknown_key apart
    }
    // From here on what the link sees: an unknown key id reads as bad_mac.
    CommandVerdict verdict = found;
    verdict.reason = linkReason(found.reason);
    counters_.lastApid = verdict.header.apid;
    counters_.lastFunctionCode = verdict.functionCode;
    counters_.lastResult = verdict.reason;

    // A flood of bad packets must not wash the event log out: at most
    // kRejectEventsPerSecond rejection events a second, the rest counted.
    const core::TimeNs now = now_;
    if (now - rejectWindowStart_ >= core::kNsPerSec) {
        if (rejectEventsInWindow_ > kRejectEventsPerSecond) {
            events_.report(events::kRejectEventsSuppressed, core::Severity::kWarning,
                           "cmd: %u rejection events suppressed in the last second (%u suppressed in all)",
                           static_cast<unsigned>(rejectEventsInWindow_ - kRejectEventsPerSecond),
                           static_cast<unsigned>(counters_.rejectEventsSuppressed));
        }
        rejectWindowStart_ = now;
        rejectEventsInWindow_ = 0;
    }
    ++rejectEventsInWindow_;
    if (rejectEventsInWindow_ <= kRejectEventsPerSecond) {
        events_.report(events::rejectEvent(verdict.reason), core::Severity::kError,
                       "cmd: rejected %s: %s (APID 0x%03x fc %u, key %u seq %u, detail %d)",
                       verdict.command != nullptr ? verdict.command->name : "packet", toString(verdict.reason),
                       static_cast<unsigned>(verdict.header.apid), static_cast<unsigned>(verdict.functionCode),
                       static_cast<unsigned>(verdict.keyId), static_cast<unsigned>(verdict.authSequence),
                       static_cast<int>(verdict.detail));
    } else {
        ++counters_.rejectEventsSuppressed;
    }
    if (mayAcknowledgeRejection(verdict)) {
        acknowledge(verdict);
    } else {
        ++counters_.acksSuppressed;
    }
}

bool CommandTask::mayAcknowledgeRejection(const CommandVerdict& verdict) {
    // Authenticated: the MAC verified and the sequence was fresh (argument,
    // mode and execution failures, and an argument block of the wrong size).
    const bool authenticated = verdict.reason >= CommandReject::kArgumentOutOfRange ||
                               (verdict.reason == CommandReject::kBadLength && verdict.args != nullptr);
    if (authenticated) {
        return true;
    }
    constexpr core::TimeNs kFull = static_cast<core::TimeNs>(kRejectAckBurst) * core::kNsPerSec;
    const core::TimeNs now = now_;
    if (!ackBucketStarted_) {
        ackBucketStarted_ = true;
        ackRefilledAt_ = now;
    }
    const core::TimeNs elapsed = now - ackRefilledAt_;
    ackRefilledAt_ = now;
    if (elapsed > 0) {
        // Refill at kRejectAcksPerSecond tokens a second (elapsed capped so the product cannot overflow).
        const core::TimeNs capped = elapsed < 100 * core::kNsPerSec ? elapsed : 100 * core::kNsPerSec;
        ackTokens_ += capped * static_cast<core::TimeNs>(kRejectAcksPerSecond);
        if (ackTokens_ > kFull) {
            ackTokens_ = kFull;
        }
    }
    if (ackTokens_ < core::kNsPerSec) {
        return false;
    }
    ackTokens_ -= core::kNsPerSec;
    return true;
}

void CommandTask::acknowledge(const CommandVerdict& verdict) {
    CMD_ACK_Tlm ack{};
    ack.apid = verdict.header.apid;
    ack.function_code = verdict.functionCode;
    ack.ccsds_sequence = verdict.header.sequenceCount;
    ack.key_id = verdict.keyId;
    ack.auth_sequence = verdict.authSequence;
    ack.reason = static_cast<std::uint8_t>(verdict.reason);
    ack.detail = verdict.detail;
    ack.accepted = counters_.accepted;
    ack.rejected = counters_.rejected;
    telemetry_.send(ack);
}

void CommandTask::addClaimedFields(CommandVerdict* verdict, const std::uint8_t* packet, std::size_t length) {
    verdict->header = PrimaryHeader{};
    verdict->functionCode = 0;
    verdict->keyId = kNoKey;
    verdict->authSequence = 0;
    if (length >= kPrimaryHeaderSize) {
        verdict->header = decodePrimaryHeader(packet);
    }
    if (length > kPrimaryHeaderSize) {
        verdict->functionCode = static_cast<std::uint8_t>(packet[kPrimaryHeaderSize] & 0x7F);
    }
    if (length >= kCommandHeaderSize) {
        core::BeReader r(packet + kPrimaryHeaderSize + kCommandSecondaryHeaderSize, kSecurityHeaderSize);
        verdict->keyId = r.u16();
        verdict->authSequence = r.u32();
    }
}

CommandTask::LinkTotals CommandTask::linkTotals() const {
    LinkTotals t;
    for (std::size_t l = 0; l < links_.size(); ++l) {
        const hal::PacketLink* link = links_.at(l);
        if (link != nullptr) {
            const hal::PacketLinkStats& s = link->stats();
            t.packets += s.rxPackets;
            t.dropped += s.rxDropped;
            t.kernelDropped += s.rxKernelDropped;
        }
    }
    return t;
}

void CommandTask::updateLinkCounters() {
    const LinkTotals t = linkTotals();
    counters_.linkRxPackets = t.packets - linkBaseline_.packets;
    counters_.linkRxDropped = t.dropped - linkBaseline_.dropped;
    counters_.linkRxKernelDropped = t.kernelDropped - linkBaseline_.kernelDropped;
}

// At most once a second: one event when the last second saw a flood's marks.
void CommandTask::reportFlood(core::TimeNs now) {
    if (!floodWindowStarted_) {
        floodWindowStarted_ = true;
        floodWindowStart_ = now;
        floodMark_ = counters_;
        return;
    }
    if (now - floodWindowStart_ < core::kNsPerSec) {
        return;
    }
    const CommandCounters& c = counters_;
    const std::uint32_t suppressed = c.acksSuppressed - floodMark_.acksSuppressed;
    const std::uint32_t limited = c.ingestLimited - floodMark_.ingestLimited;
    const std::uint32_t kernel = c.linkRxKernelDropped - floodMark_.linkRxKernelDropped;
    if (suppressed > 0 || limited > 0 || kernel > 0) {
        events_.report(events::kIngestFlood, core::Severity::kWarning,
                       "cmd: flood 1 s: %u read, %u OS drop, %u link drop, %u acks held, %u limited",
                       static_cast<unsigned>(c.linkRxPackets - floodMark_.linkRxPackets), static_cast<unsigned>(kernel),
                       static_cast<unsigned>(c.linkRxDropped - floodMark_.linkRxDropped),
                       static_cast<unsigned>(suppressed), static_cast<unsigned>(limited));
    }
    floodWindowStart_ = now;
    floodMark_ = counters_;
}

void CommandTask::fillHousekeeping(HK_Tlm& hk) const {
    const CommandCounters& c = counters_;
    hk.auth_required = authRequired() ? 1 : 0;
    hk.lab_key_in_use = labKeyInUse() ? 1 : 0;
    hk.cmd_queue_depth = c.queueDepth;
    hk.cmd_accepted = c.accepted;
    hk.cmd_rejected = c.rejected;
    for (std::size_t i = 0; i < kRejectReasonCount; ++i) {
        hk.cmd_rejected_by_reason[i] = c.byReason[i];
    }
    hk.last_cmd_apid = c.lastApid;
    hk.last_cmd_fc = c.lastFunctionCode;
    hk.last_cmd_result = static_cast<std::uint8_t>(c.lastResult);
    const AntiReplayState& replay = antiReplay();
    hk.auth_store_state = static_cast<std::uint8_t>(replay.state());
    hk.auth_keys_unsynced = keysUnsynced();
    hk.auth_challenge_high = static_cast<std::uint32_t>(replay.challenge() >> 32);
    hk.auth_challenge_low = static_cast<std::uint32_t>(replay.challenge());
    hk.auth_store_writes = replay.writes();
    hk.auth_store_write_failures = replay.writeFailures();
    hk.auth_store_wait_frames = c.storeWaitFrames;
    hk.link_rx_packets = c.linkRxPackets;
    hk.link_rx_dropped = c.linkRxDropped;
    hk.link_rx_kernel_drops = c.linkRxKernelDropped;
    hk.cmd_ingest_limited = c.ingestLimited;
    hk.cmd_acks_suppressed = c.acksSuppressed;
}

void CommandTask::resetCounters() {
    counters_ = CommandCounters{};
    counters_.queueDepth = static_cast<std::uint8_t>(count_);
    linkBaseline_ = linkTotals();
    floodMark_ = counters_;
}

}  // namespace rse::cmdtlm
