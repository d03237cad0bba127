// libFuzzer target: the command packet decoder and validator, and the command
// task's whole ingest -> validate -> dispatch -> acknowledge path
// (unit_test/fuzz/README.md).
//
// An input is one command packet, exactly the bytes a ground link delivers (so
// the seed corpus holds real packets and the unit tests replay it as is). Each
// input is tried twice:
//   raw       the bytes as they are: length, header and checksum checks;
//   repaired  the length field and checksum recomputed and, for key id 1, the
//             MAC recomputed with the lab key, so mutated headers, key ids,
//             sequences and arguments reach checks 4 to 10 instead of dying at
//             the checksum or the MAC.
// and each of those in both configurations (authentication required with the
// lab key loaded; the lab setting, where key id 0 is accepted) and every mode,
// through CommandValidator::check directly and through a CommandTask fed by a
// fake link. The key store is reset before every check so a verdict depends
// on the bytes alone (an accepted sequence would otherwise be a replay the
// next time) and the two paths can be compared.
//
// Invariants (a broken one traps, which libFuzzer reports as a crash):
//   - a verdict's reason is one the validator can give; an argument index is
//     an argument of the command; accepted verdicts name a command allowed in
//     the mode, with argument bytes inside the packet and of the dictionary's
//     size, a MAC that recomputes (key id != 0) and key id != 0 when
//     authentication is required;
//   - the generated decodeArgs consumes exactly the argument bytes and every
//     decoded argument lies within the dictionary's [min, max];
//   - the command task sends exactly one CMD_ACK per packet, its reason is the
//     validator's verdict, and the handler runs exactly for accepted packets.
#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_handler.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "hal/link/packet_link.hpp"
#include "unit_test/support/decoded_args_check.hpp"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

// Packets longer than this are cut: the link refuses anything over
// kMaxCommandPacket anyway, a little beyond it is enough to reach that path.
constexpr std::size_t kMaxInput = kMaxCommandPacket + 64;

#define FUZZ_REQUIRE(condition) \
    do {                        \
        if (!(condition)) {     \
            __builtin_trap();   \
        }                       \
    } while (0)

// A ground link with a few packets waiting at most and a counter of what the
// flight side sends (only the last packet sent is kept: the acknowledgement).
class FuzzLink final : public hal::PacketLink {
public:
    static constexpr std::size_t kSlots = kCommandQueueDepth + 4;

    void push(const std::uint8_t* data, std::size_t length) {
        FUZZ_REQUIRE(length <= kMaxInput && rxCount_ < kSlots);
        Slot& slot = rx_[(rxHead_ + rxCount_) % kSlots];
        if (length > 0) {
            std::memcpy(slot.bytes, data, length);
        }
        slot.length = length;
        ++rxCount_;
    }
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override {
        if (rxCount_ == 0) {
            return core::Status::kEmpty;
        }
        const Slot& slot = rx_[rxHead_];
        rxHead_ = (rxHead_ + 1) % kSlots;
        --rxCount_;
        if (slot.length > capacity) {
            return core::Status::kTooLarge;
        }
        if (slot.length > 0) {
            std::memcpy(out, slot.bytes, slot.length);
        }
        *length = slot.length;
        return core::Status::kOk;
    }
    core::Status send(const std::uint8_t* data, std::size_t length) override {
        FUZZ_REQUIRE(length <= sizeof tx_);
        std::memcpy(tx_, data, length);
        txLength_ = length;
        ++txCount_;
        return core::Status::kOk;
    }
    const char* name() const override { return "fuzz"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }

    std::size_t waiting() const { return rxCount_; }
    std::size_t sentCount() const { return txCount_; }
    const std::uint8_t* lastSent() const { return tx_; }
    std::size_t lastSentLength() const { return txLength_; }

private:
    struct Slot {
        std::uint8_t bytes[kMaxInput];
        std::size_t length;
    };
    Slot rx_[kSlots] = {};
    std::size_t rxHead_ = 0;
    std::size_t rxCount_ = 0;
    std::uint8_t tx_[kMaxTelemetryPacket] = {};
    std::size_t txLength_ = 0;
    std::size_t txCount_ = 0;
    hal::PacketLinkStats stats_;
};

// A handler that accepts everything, and decodes the arguments as the real
// handlers do (from the task's queue slot, not from the fuzzer's buffer).
class AcceptingHandler final : public CommandHandler {
public:
    Mode mode() const override { return mode_; }
    CommandOutcome execute(const CommandVerdict& verdict) override {
        FUZZ_REQUIRE(verdict.reason == CommandReject::kAccepted);
        FUZZ_REQUIRE(verdict.command != nullptr && verdict.args != nullptr);
        FUZZ_REQUIRE(modeAllows(verdict.command->modes, mode_));
        FUZZ_REQUIRE(test::decodesInRange(verdict));
        ++executed_;
        return CommandOutcome{};
    }
    void setMode(Mode mode) { mode_ = mode; }
    std::size_t executed() const { return executed_; }

private:
    Mode mode_ = Mode::kSafe;
    std::size_t executed_ = 0;
};

// Byte offset of a field in a telemetry payload, found by name so the harness
// follows the dictionary.
std::size_t payloadOffset(const char* packet, const char* field) {
    const TelemetryDesc* tlm = findTelemetry(packet);
    FUZZ_REQUIRE(tlm != nullptr);
    std::size_t offset = 0;
    for (std::size_t i = 0; i < tlm->fieldCount; ++i) {
        if (std::strcmp(tlm->fields[i].name, field) == 0) {
            return offset;
        }
        offset += wireSize(tlm->fields[i].type) * tlm->fields[i].count;
    }
    __builtin_trap();
}

struct Rig {
    core::VirtualClock clock;
    core::EventLog events{clock};
    GroundLinks links;
    TelemetryOutput output{clock, events, links};
    FuzzLink link;
    AcceptingHandler handler;
    CommandTask task{clock, events, links, output, handler};
    HmacSha256 hmac;
    KeyStore keys;
    CommandValidator validator{keys, hmac};
    std::size_t ackReasonOffset = 0;
    std::uint64_t frame = 0;

    void init() {
        FUZZ_REQUIRE(core::isOk(hmac.init()));
        FUZZ_REQUIRE(core::isOk(task.keys().add(kLabKeyId, kLabKey)));
        FUZZ_REQUIRE(core::isOk(links.add(&link)));
        FUZZ_REQUIRE(core::isOk(task.init()));
        ackReasonOffset = kTelemetryHeaderSize + payloadOffset("CMD_ACK", "reason");
        drainEvents();
    }
    void drainEvents() {
        while (core::isOk(events.pop(nullptr))) {
        }
    }
    void runFrame() {
        core::FrameContext fc;
        fc.frame = frame++;
        clock.advance(10 * core::kNsPerMs);
        task.run(fc);
    }
};

Rig& rig() {
    static Rig r;
    return r;
}

void resetKeys(KeyStore& keys) {
    keys.clear();
    FUZZ_REQUIRE(core::isOk(keys.add(kLabKeyId, kLabKey)));
}

bool reasonValidatorMayGive(CommandReject reason) {
    return reason != CommandReject::kQueueOverflow && reason != CommandReject::kExecutionFailed &&
           reason < CommandReject::kCount;
}

CommandVerdict checkDirect(Rig& rig, const std::uint8_t* packet, std::size_t length, bool authRequired,
                           Mode mode) {
    resetKeys(rig.keys);
    rig.validator.setAuthRequired(authRequired);
    const CommandVerdict v = rig.validator.check(packet, length, mode);
    FUZZ_REQUIRE(reasonValidatorMayGive(v.reason));
    if (v.reason == CommandReject::kArgumentOutOfRange) {
        FUZZ_REQUIRE(v.command != nullptr && v.detail >= 0 && v.detail < v.command->argCount);
    }
    if (v.reason != CommandReject::kAccepted) {
        return v;
    }
    const CommandDesc* c = v.command;
    FUZZ_REQUIRE(c != nullptr);
    FUZZ_REQUIRE(c->apid == v.header.apid && c->functionCode == v.functionCode);
    FUZZ_REQUIRE(modeAllows(c->modes, mode));
    FUZZ_REQUIRE(!authRequired || v.keyId != kNoKey);
    const std::size_t macBytes = v.keyId != kNoKey ? kMacSize : 0;
    FUZZ_REQUIRE(v.args == packet + kCommandHeaderSize);
    FUZZ_REQUIRE(kCommandHeaderSize + v.argLength + macBytes == length);
    if (c->maxBlobBytes == 0) {
        FUZZ_REQUIRE(v.argLength == c->fixedArgBytes);
    } else {
        FUZZ_REQUIRE(v.argLength > c->fixedArgBytes && v.argLength <= c->fixedArgBytes + c->maxBlobBytes);
    }
    if (v.keyId != kNoKey) {
        FUZZ_REQUIRE(v.keyId == kLabKeyId);
        std::uint8_t mac[kMacSize];
        FUZZ_REQUIRE(core::isOk(rig.hmac.packetMac(kLabKey, packet, length - kMacSize, mac)));
        FUZZ_REQUIRE(std::memcmp(mac, packet + length - kMacSize, kMacSize) == 0);
    }
    FUZZ_REQUIRE(test::decodesInRange(v));
    return v;
}

// One packet through the command task; returns the CMD_ACK reason.
CommandReject throughTask(Rig& rig, const std::uint8_t* packet, std::size_t length, bool authRequired, Mode mode) {
    resetKeys(rig.task.keys());
    rig.task.setAuthRequired(authRequired);
    rig.handler.setMode(mode);
    const std::size_t sentBefore = rig.link.sentCount();
    const std::size_t executedBefore = rig.handler.executed();
    rig.clock.advance(core::kNsPerSec);  // refills the rejection-ack bucket: this packet is acknowledged
    rig.link.push(packet, length);
    rig.runFrame();
    FUZZ_REQUIRE(rig.link.sentCount() == sentBefore + 1);  // exactly one CMD_ACK
    FUZZ_REQUIRE(rig.task.counters().queueDepth == 0);
    const std::uint8_t* ack = rig.link.lastSent();
    FUZZ_REQUIRE(rig.link.lastSentLength() > rig.ackReasonOffset);
    FUZZ_REQUIRE(decodePrimaryHeader(ack).apid == CMD_ACK_Tlm::kApid);
    const auto reason = static_cast<CommandReject>(ack[rig.ackReasonOffset]);
    FUZZ_REQUIRE(reason < CommandReject::kCount);
    FUZZ_REQUIRE(rig.handler.executed() == executedBefore + (reason == CommandReject::kAccepted ? 1U : 0U));
    return reason;
}

// A burst longer than the queue, all in one frame: every packet still gets
// exactly one CMD_ACK (the burst fits the rejection-ack bucket, refilled by a
// second first); a packet the ingest screen refuses takes no queue slot, of the
// others those that found the queue full say queue_overflow and the rest are
// dispatched over the following frames.
void burst(Rig& rig, const std::uint8_t* packet, std::size_t length) {
    static_assert(FuzzLink::kSlots <= kRejectAckBurst, "a burst must fit the rejection-ack bucket");
    resetKeys(rig.task.keys());
    rig.task.setAuthRequired(false);
    resetKeys(rig.keys);
    rig.validator.setAuthRequired(false);
    const bool screenedOut =
        length > kMaxCommandPacket || rig.validator.screen(packet, length).reason != CommandReject::kAccepted;
    rig.clock.advance(core::kNsPerSec);
    const std::size_t sentBefore = rig.link.sentCount();
    const CommandCounters before = rig.task.counters();
    constexpr std::size_t kBurst = FuzzLink::kSlots;
    for (std::size_t i = 0; i < kBurst; ++i) {
        rig.link.push(packet, length);
    }
    for (std::size_t frames = 0; frames < kBurst && (rig.link.waiting() > 0 || rig.task.counters().queueDepth > 0);
         ++frames) {
        rig.runFrame();
    }
    FUZZ_REQUIRE(rig.link.waiting() == 0 && rig.task.counters().queueDepth == 0);
    FUZZ_REQUIRE(rig.link.sentCount() == sentBefore + kBurst);
    const CommandCounters& after = rig.task.counters();
    FUZZ_REQUIRE((after.accepted - before.accepted) + (after.rejected - before.rejected) == kBurst);
    const auto overflow = static_cast<std::size_t>(CommandReject::kQueueOverflow);
    // Packets too long for any command, or refused by the screen, never take a slot.
    const std::size_t expectedOverflow = screenedOut ? 0 : kBurst - kCommandQueueDepth;
    FUZZ_REQUIRE(after.acksSuppressed == before.acksSuppressed);
    FUZZ_REQUIRE(after.byReason[overflow] - before.byReason[overflow] == expectedOverflow);
}

// The packet with its length field and checksum made consistent and, for the
// lab key id, a MAC that verifies. Returns false when nothing can be repaired.
bool repair(Rig& rig, const std::uint8_t* data, std::size_t size, std::uint8_t* out) {
    if (size < kCommandHeaderSize || size > kMaxCommandPacket) {
        return false;
    }
    std::memcpy(out, data, size);
    const auto dataLength = static_cast<std::uint16_t>(size - 7);
    out[4] = static_cast<std::uint8_t>(dataLength >> 8);
    out[5] = static_cast<std::uint8_t>(dataLength & 0xFF);
    const auto keyId = static_cast<std::uint16_t>((out[8] << 8) | out[9]);
    if (keyId == kLabKeyId && size >= kCommandHeaderSize + kMacSize) {
        FUZZ_REQUIRE(core::isOk(rig.hmac.packetMac(kLabKey, out, size - kMacSize, out + size - kMacSize)));
    }
    out[kChecksumOffset] = commandChecksum(out, size);
    return true;
}

// The anti-replay window on a packet the lab key authenticates: the same
// sequence twice is a replay; after a jump two windows ahead the original is
// stale; inside the window an unseen sequence passes once; exactly one window
// behind the highest is stale.
void setSequenceAndSign(Rig& rig, std::uint8_t* packet, std::size_t length, std::uint32_t sequence) {
    for (std::size_t i = 0; i < 4; ++i) {
        packet[10 + i] = static_cast<std::uint8_t>(sequence >> (24 - 8 * i));
    }
    FUZZ_REQUIRE(core::isOk(rig.hmac.packetMac(kLabKey, packet, length - kMacSize, packet + length - kMacSize)));
    packet[kChecksumOffset] = commandChecksum(packet, length);
}

void replayLadder(Rig& rig, const std::uint8_t* packet, std::size_t length, Mode mode) {
    const CommandVerdict first = checkDirect(rig, packet, length, true, mode);
    if (first.reason != CommandReject::kAccepted || first.keyId != kLabKeyId ||
        first.authSequence > kMaxUsableSequence - 2 * kReplayWindow) {  // above it: sequence_exhausted
        return;
    }
    const std::uint32_t s = first.authSequence;
    const std::uint32_t top = s + 2 * kReplayWindow;
    std::uint8_t p[kMaxCommandPacket];
    std::memcpy(p, packet, length);
    resetKeys(rig.keys);
    rig.validator.setAuthRequired(true);
    const auto expect = [&](std::uint32_t sequence, CommandReject reason) {
        setSequenceAndSign(rig, p, length, sequence);
        const CommandVerdict v = rig.validator.check(p, length, mode);
        FUZZ_REQUIRE(v.reason == reason && v.authSequence == sequence);
    };
    expect(s, CommandReject::kAccepted);
    expect(s, CommandReject::kReplayedSequence);
    expect(top, CommandReject::kAccepted);
    expect(s, CommandReject::kStaleSequence);
    expect(top - kReplayWindow, CommandReject::kStaleSequence);
    expect(top - kReplayWindow + 1, CommandReject::kAccepted);
    expect(top - kReplayWindow + 1, CommandReject::kReplayedSequence);
    expect(top, CommandReject::kReplayedSequence);
    FUZZ_REQUIRE(rig.keys.lastSequence(kLabKeyId) == top);
}

constexpr Mode kModes[kModeCount] = {Mode::kSafe, Mode::kStandby, Mode::kAutonomous, Mode::kManual};

void exercise(Rig& rig, const std::uint8_t* packet, std::size_t length) {
    bool laddered = false;
    for (const bool authRequired : {true, false}) {
        for (const Mode mode : kModes) {
            const CommandVerdict direct = checkDirect(rig, packet, length, authRequired, mode);
            const CommandReject viaTask = throughTask(rig, packet, length, authRequired, mode);
            FUZZ_REQUIRE(viaTask == linkReason(direct.reason));  // unknown_key reads as bad_mac on the link
            if (!laddered && authRequired && direct.reason == CommandReject::kAccepted) {
                replayLadder(rig, packet, length, mode);
                laddered = true;
            }
        }
    }
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
    rig().init();
    return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
    if (size > kMaxInput) {
        return -1;  // not added to the corpus
    }
    Rig& r = rig();
    exercise(r, data, size);
    std::uint8_t repaired[kMaxCommandPacket];
    if (repair(r, data, size, repaired) && std::memcmp(repaired, data, size) != 0) {
        exercise(r, repaired, size);
    }
    if (size % 8 == 0) {
        burst(r, data, size);
    }
    r.drainEvents();
    return 0;
}
