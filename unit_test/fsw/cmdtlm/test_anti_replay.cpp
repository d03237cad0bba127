// The anti-replay state across restarts (issue 14 items 1, 2 and 6;
// fsw/cmdtlm/anti_replay_state.hpp, docs/icd.md "Anti-replay"). A "restart" is
// a new CommandTask (new KeyStore, new window) over the same MemoryRecordStore,
// which is what survives a restart or a power cycle on the rover.
#include <cstring>
#include <memory>
#include <vector>

#include "fsw/cmdtlm/anti_replay_state.hpp"
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/core/byte_codec.hpp"
#include "hal/link/packet_link.hpp"
#include "hal/nvm/record_store.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

using Bytes = std::vector<std::uint8_t>;

class QueueLink final : public hal::PacketLink {
public:
    void push(const Bytes& p) { rx_.push_back(p); }
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override {
        if (rx_.empty()) {
            return core::Status::kEmpty;
        }
        const Bytes p = rx_.front();
        rx_.erase(rx_.begin());
        if (p.size() > capacity) {
            return core::Status::kTooLarge;
        }
        std::memcpy(out, p.data(), p.size());
        *length = p.size();
        return core::Status::kOk;
    }
    core::Status send(const std::uint8_t* data, std::size_t length) override {
        tx_.assign(data, data + length);
        ++sent_;
        return core::Status::kOk;
    }
    const char* name() const override { return "queue"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }
    const Bytes& lastSent() const { return tx_; }
    std::size_t sentCount() const { return sent_; }

private:
    std::vector<Bytes> rx_;
    Bytes tx_;
    std::size_t sent_ = 0;
    hal::PacketLinkStats stats_;
};

struct Ack {
    std::uint32_t authSequence = 0;
    std::uint8_t reason = 0xFF;
    std::int16_t detail = 0;
};

// Records what the store held each time a command was acted on.
class RecordingHandler final : public CommandHandler {
public:
    explicit RecordingHandler(const hal::MemoryRecordStore& store) : store_(store) {}
    Mode mode() const override { return mode_; }
    CommandOutcome execute(const CommandVerdict& verdict) override {
        ++executed;
        lastSequence = verdict.authSequence;
        AuthStoreEntry entries[kMaxStoredKeys];
        std::size_t n = 0;
        storedAtExecute = 0;
        if (store_.present() && core::isOk(decodeAuthStore(store_.bytes(), store_.length(), entries, &n))) {
            for (std::size_t i = 0; i < n; ++i) {
                storedAtExecute = entries[i].keyId == verdict.keyId ? entries[i].reserved : storedAtExecute;
            }
        }
        return {};
    }
    Mode mode_ = Mode::kSafe;
    int executed = 0;
    std::uint32_t lastSequence = 0;
    std::uint32_t storedAtExecute = 0;

private:
    const hal::MemoryRecordStore& store_;
};

// A command signed with the lab key.
Bytes signedPacket(HmacSha256& hmac, const char* name, const Bytes& args, std::uint32_t sequence) {
    const CommandDesc* c = findCommand(name);
    CHECK(c != nullptr);
    Bytes out(kMaxCommandPacket);
    CommandFields f;
    f.apid = c->apid;
    f.functionCode = c->functionCode;
    f.keyId = kLabKeyId;
    f.authSequence = sequence;
    const std::size_t n = encodeCommandPacket(f, args.data(), args.size(), kLabKey, hmac, out.data(), out.size());
    CHECK(n > 0);
    out.resize(n);
    return out;
}

// AUTH_RESYNC's arguments: the nonce, high word first.
Bytes nonceArgs(std::uint64_t nonce) {
    Bytes args(8);
    core::BeWriter w(args.data(), args.size());
    w.u32(static_cast<std::uint32_t>(nonce >> 32));
    w.u32(static_cast<std::uint32_t>(nonce));
    return args;
}

// A writer that finishes a posted write only when the test says so: a file
// store's fsync, which takes frames, in slow motion.
class ManualWriter final : public hal::RecordWriter {
public:
    explicit ManualWriter(hal::RecordStore& store) : store_(store) {}
    core::Status post(const std::uint8_t* data, std::size_t length) override {
        if (queued_ || done_) {
            return core::Status::kBusy;
        }
        bytes_.assign(data, data + length);
        queued_ = true;
        ++posts;
        return core::Status::kOk;
    }
    bool takeResult(core::Status* result) override {
        if (!done_) {
            return false;
        }
        done_ = false;
        *result = result_;
        return true;
    }
    // The medium finishes the write posted last.
    void finish() {
        CHECK(queued_);
        result_ = store_.write(bytes_.data(), bytes_.size());
        queued_ = false;
        done_ = true;
    }
    bool queued() const { return queued_; }
    int posts = 0;

private:
    hal::RecordStore& store_;
    Bytes bytes_;
    bool queued_ = false;
    bool done_ = false;
    core::Status result_ = core::Status::kOk;
};

// One boot of the command service.
struct Boot {
    core::VirtualClock clock;
    core::EventLog events{clock};
    GroundLinks links;
    TelemetryOutput output{clock, events, links};
    QueueLink link;
    RecordingHandler handler;
    CommandTask task{clock, events, links, output, handler};
    std::uint64_t frame = 0;

    Boot(hal::MemoryRecordStore* store, bool provision, std::uint64_t nonce, bool seeded = true,
         hal::RecordWriter* writer = nullptr)
        : handler(*store) {
        CHECK(core::isOk(task.keys().add(kLabKeyId, kLabKey)));
        CHECK(core::isOk(links.add(&link)));
        task.attachAuthStore(store, provision, writer);
        if (seeded) {
            task.setAuthChallengeSeed(nonce);
        }
        CHECK(core::isOk(task.init()));
    }
    // One frame; true when it sent an acknowledgement.
    bool step() {
        const std::size_t before = link.sentCount();
        core::FrameContext fc;
        fc.frame = frame++;
        clock.advance(10 * core::kNsPerMs);
        task.run(fc);
        return link.sentCount() > before;
    }
    Ack submit(const Bytes& p) {
        link.push(p);
        CHECK(step());
        return lastAck();
    }
    Ack lastAck() const {
        const Bytes& t = link.lastSent();
        core::BeReader r(t.data() + kTelemetryHeaderSize, t.size() - kTelemetryHeaderSize);
        Ack a;
        (void)r.u16();  // apid
        (void)r.u8();   // function code
        (void)r.u16();  // ccsds sequence
        (void)r.u16();  // key id
        a.authSequence = r.u32();
        a.reason = r.u8();
        a.detail = r.i16();
        CHECK(r.ok());
        return a;
    }
};

}  // namespace

TEST_GROUP(AntiReplay) {
    hal::MemoryRecordStore store;
    HmacSha256 hmac;
    std::unique_ptr<Boot> rover;

    void setup() override { CHECK(core::isOk(hmac.init())); }
    void teardown() override { rover.reset(); }

    // A power cycle: the old instance is gone, only the store remains.
    Boot& boot(bool provision = false, std::uint64_t nonce = 0x1122334455667788ULL) {
        rover.reset();
        rover = std::make_unique<Boot>(&store, provision, nonce);
        return *rover;
    }
    Bytes packet(const char* name, const Bytes& args, std::uint32_t sequence) {
        return signedPacket(hmac, name, args, sequence);
    }
    Bytes resync(std::uint64_t nonce, std::uint32_t sequence) {
        return packet("AUTH_RESYNC", nonceArgs(nonce), sequence);
    }
    static int reason(CommandReject r) { return static_cast<int>(r); }
    static Bytes driveArgs() {
        Bytes args(12);
        core::BeWriter w(args.data(), args.size());
        w.f32(0.2F);
        w.f32(0.0F);
        w.f32(2.0F);
        return args;
    }
};

// Item 1: the wheels moved again after a restart. Old code: the new window
// accepted every captured command.
TEST(AntiReplay, CapturedCommandsAreRefusedAfterARestart) {
    boot(true);
    const Bytes manual = packet("SET_MODE", {3}, 7);
    const Bytes drive = packet("DRIVE", driveArgs(), 8);
    LONGS_EQUAL(0, rover->submit(manual).reason);
    rover->handler.mode_ = Mode::kManual;
    LONGS_EQUAL(0, rover->submit(drive).reason);
    LONGS_EQUAL(2, rover->handler.executed);

    boot();  // restart: no provisioning, the store is read
    const Ack a = rover->submit(manual);
    const Ack b = rover->submit(drive);
    CHECK(a.reason == reason(CommandReject::kReplayedSequence) || a.reason == reason(CommandReject::kStaleSequence));
    CHECK(b.reason == reason(CommandReject::kReplayedSequence) || b.reason == reason(CommandReject::kStaleSequence));
    LONGS_EQUAL(0, rover->handler.executed);
    // A fresh number above the reservation is accepted.
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 8 + kReserveBlock + 1)).reason);
}

TEST(AntiReplay, TheReservationIsDurableBeforeTheCommandActsAndWrittenOncePerBlock) {
    boot(true);
    const std::uint32_t writesAfterProvisioning = store.writes();
    for (std::uint32_t s = 1; s <= kReserveBlock + 2; ++s) {
        LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, s)).reason);
        CHECK(rover->handler.storedAtExecute >= s);  // persisted before it acted
    }
    // 1 reserved up to 1025; 514, within kRenewMargin of it, renewed to 1538
    // ahead of need, which 1026 then found durable.
    LONGS_EQUAL(writesAfterProvisioning + 2, store.writes());
    LONGS_EQUAL(3, rover->task.antiReplay().writes());  // provisioning, then two reservations
}

// A crash between writes can only skip numbers: after a restart the floor is
// the reservation, above every number accepted before.
TEST(AntiReplay, ACrashBetweenWritesSkipsNumbersAndNeverReopensThem) {
    boot(true);
    std::vector<Bytes> captured;
    for (std::uint32_t s = 1; s <= 10; ++s) {
        captured.push_back(packet("NOOP", {}, s));
        LONGS_EQUAL(0, rover->submit(captured.back()).reason);
    }
    boot();  // crashed: nothing written since the reservation 1 + kReserveBlock
    for (const Bytes& p : captured) {
        CHECK(rover->submit(p).reason != 0);
    }
    CHECK(rover->submit(packet("NOOP", {}, 1 + kReserveBlock)).reason != 0);  // skipped
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 2 + kReserveBlock)).reason);
    LONGS_EQUAL(1, rover->handler.executed);
}

TEST(AntiReplay, AMissingStoreRefusesEveryCommandWithItsReason) {
    boot(false);
    LONGS_EQUAL(1, test::drainEventsWithId(rover->events, events::kAuthStoreUnusable));
    CHECK(AuthStoreState::kMissing == rover->task.antiReplay().state());
    LONGS_EQUAL(1, rover->task.keysUnsynced());
    const Ack a = rover->submit(packet("NOOP", {}, 1));
    LONGS_EQUAL(reason(CommandReject::kSequenceUnsynchronised), a.reason);
    LONGS_EQUAL(static_cast<int>(Unsynced::kStoreMissing), a.detail);
    LONGS_EQUAL(0, rover->handler.executed);
    LONGS_EQUAL(1, rover->task.counters().byReason[reason(CommandReject::kSequenceUnsynchronised)]);
    LONGS_EQUAL(1, test::drainEventsWithId(rover->events, events::rejectEvent(CommandReject::kSequenceUnsynchronised)));
    CHECK_FALSE(store.present());  // not created behind the operator's back
}

TEST(AntiReplay, ACorruptStoreIsRefusedAndNeverOverwrittenByProvisioning) {
    boot(true);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 1)).reason);
    std::uint8_t bytes[hal::MemoryRecordStore::kCapacity];
    const std::size_t n = store.length();
    std::memcpy(bytes, store.bytes(), n);
    bytes[n - 6] ^= 0x01;  // a bit of the reservation flips: the CRC no longer checks
    store.replace(bytes, n);

    boot(true);  // provisioning must not paper over it
    CHECK(AuthStoreState::kCorrupt == rover->task.antiReplay().state());
    MEMCMP_EQUAL(bytes, store.bytes(), n);
    const Ack a = rover->submit(packet("NOOP", {}, 5000));
    LONGS_EQUAL(reason(CommandReject::kSequenceUnsynchronised), a.reason);
    LONGS_EQUAL(static_cast<int>(Unsynced::kStoreCorrupt), a.detail);
    LONGS_EQUAL(0, rover->handler.executed);
}

TEST(AntiReplay, ResyncWithTheCurrentNonceSetsTheFloorToItsOwnNumber) {
    const std::uint64_t nonce = 0xA5A5A5A500000001ULL;
    boot(false, nonce);
    LONGS_EQUAL(0, rover->submit(resync(nonce, 5000)).reason);
    LONGS_EQUAL(1, rover->handler.executed);
    LONGS_EQUAL(0, rover->task.keysUnsynced());
    CHECK(AuthStoreState::kOk == rover->task.antiReplay().state());
    CHECK(rover->submit(packet("NOOP", {}, 4999)).reason != 0);  // below the floor: never fresh
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 5001)).reason);
    // The floor holds across the next restart.
    boot(false, nonce + 100);
    CHECK(rover->submit(packet("NOOP", {}, 5001)).reason != 0);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 5000 + kReserveBlock + 1)).reason);
}

// A captured AUTH_RESYNC must not lower the floor: its nonce is old.
TEST(AntiReplay, ACapturedResyncIsRefused) {
    const std::uint64_t first = 0x0102030405060708ULL;
    boot(false, first);
    const Bytes captured = resync(first, 100);
    LONGS_EQUAL(0, rover->submit(captured).reason);
    // Same boot: the nonce moved on after it was used.
    Ack a = rover->submit(captured);
    LONGS_EQUAL(reason(CommandReject::kSequenceUnsynchronised), a.reason);
    LONGS_EQUAL(static_cast<int>(Unsynced::kChallengeMismatch), a.detail);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 9000)).reason);

    store.erase();  // the store is lost; the next boot draws a new nonce
    boot(false, 0x99AABBCCDDEEFF00ULL);
    a = rover->submit(captured);
    LONGS_EQUAL(reason(CommandReject::kSequenceUnsynchronised), a.reason);
    LONGS_EQUAL(static_cast<int>(Unsynced::kChallengeMismatch), a.detail);
    a = rover->submit(packet("NOOP", {}, 9000));  // still refused: not synchronised
    LONGS_EQUAL(static_cast<int>(Unsynced::kStoreMissing), a.detail);
    LONGS_EQUAL(0, rover->handler.executed);
}

TEST(AntiReplay, ResyncNeverLowersTheFloorOfASynchronisedKey) {
    const std::uint64_t nonce = 77;
    boot(true, nonce);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 3000)).reason);
    LONGS_EQUAL(0, rover->submit(resync(nonce, 10)).reason);
    CHECK(rover->submit(packet("NOOP", {}, 2999)).reason != 0);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 3001)).reason);
    CHECK(store.present());
    CHECK(rover->task.antiReplay().reserved(kLabKeyId) >= 3000 + kReserveBlock);
}

TEST(AntiReplay, ResyncWithoutANonceSourceIsRefused) {
    rover = std::make_unique<Boot>(&store, false, 0, false);
    CHECK_FALSE(rover->task.antiReplay().challengeReady());
    const Ack a = rover->submit(resync(0, 10));  // 0: what an unseeded nonce reads as
    LONGS_EQUAL(reason(CommandReject::kSequenceUnsynchronised), a.reason);
    LONGS_EQUAL(static_cast<int>(Unsynced::kNoChallenge), a.detail);
    LONGS_EQUAL(0, rover->handler.executed);
}

// Item 2: 0xFFFFFFFF was accepted and then locked the key out.
TEST(AntiReplay, NumbersNearTheTopAreRefusedAsExhausted) {
    boot(true);
    Ack a = rover->submit(packet("NOOP", {}, 0xFFFFFFFFu));
    LONGS_EQUAL(reason(CommandReject::kSequenceExhausted), a.reason);
    a = rover->submit(packet("NOOP", {}, kMaxUsableSequence + 1));
    LONGS_EQUAL(reason(CommandReject::kSequenceExhausted), a.reason);
    LONGS_EQUAL(0, rover->handler.executed);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, kMaxUsableSequence)).reason);
    CHECK(rover->task.antiReplay().reserved(kLabKeyId) == 0xFFFFFFFFu);  // no overflow
    LONGS_EQUAL(2, rover->task.counters().byReason[reason(CommandReject::kSequenceExhausted)]);
}

TEST(AntiReplay, NumbersNearTheTopAreRefusedWithoutAStoreToo) {
    core::VirtualClock clock;
    core::EventLog log{clock};
    GroundLinks links;
    TelemetryOutput output{clock, log, links};
    QueueLink link;
    RecordingHandler handler{store};
    CommandTask task{clock, log, links, output, handler};
    CHECK(core::isOk(task.keys().add(kLabKeyId, kLabKey)));
    CHECK(core::isOk(links.add(&link)));
    CHECK(core::isOk(task.init()));
    LONGS_EQUAL(1, test::drainEventsWithId(log, events::kAuthStoreVolatile));
    link.push(packet("NOOP", {}, 0xFFFFFFFFu));
    link.push(packet("NOOP", {}, 5));
    core::FrameContext fc;
    task.run(fc);
    LONGS_EQUAL(1, task.counters().byReason[reason(CommandReject::kSequenceExhausted)]);
    LONGS_EQUAL(1, handler.executed);  // the key is not locked out: 5 is accepted
}

TEST(AntiReplay, AFailedReservationWriteRefusesTheCommandWithoutUsingItsNumber) {
    boot(true);
    store.setFailWrites(true);
    const Bytes p = packet("NOOP", {}, 1);
    const Ack a = rover->submit(p);
    LONGS_EQUAL(reason(CommandReject::kSequenceStoreFailed), a.reason);
    LONGS_EQUAL(0, rover->handler.executed);
    LONGS_EQUAL(1, rover->task.antiReplay().writeFailures());
    LONGS_EQUAL(1, test::drainEventsWithId(rover->events, events::kAuthStoreWriteFailed));
    store.setFailWrites(false);
    LONGS_EQUAL(0, rover->submit(p).reason);  // never recorded, so not a replay
    LONGS_EQUAL(1, rover->handler.executed);
}

// Item 6: a signed command refused for its arguments or its mode has used its number.
TEST(AntiReplay, ACommandRefusedForArgumentsOrModeUsesUpItsNumber) {
    boot(true);
    LONGS_EQUAL(reason(CommandReject::kArgumentOutOfRange), rover->submit(packet("SET_MODE", {7}, 10)).reason);
    LONGS_EQUAL(reason(CommandReject::kReplayedSequence), rover->submit(packet("SET_MODE", {1}, 10)).reason);
    LONGS_EQUAL(reason(CommandReject::kWrongMode), rover->submit(packet("DRIVE", driveArgs(), 11)).reason);
    rover->handler.mode_ = Mode::kManual;
    LONGS_EQUAL(reason(CommandReject::kReplayedSequence), rover->submit(packet("DRIVE", driveArgs(), 11)).reason);
    LONGS_EQUAL(0, rover->handler.executed);
}

TEST(AntiReplay, ProvisioningAddsMissingKeysButNeverResetsAStoredReservation) {
    boot(true);
    LONGS_EQUAL(0, rover->submit(packet("NOOP", {}, 2000)).reason);
    const std::uint32_t reserved = rover->task.antiReplay().reserved(kLabKeyId);
    boot(true);
    LONGS_EQUAL(reserved, rover->task.antiReplay().reserved(kLabKeyId));
    CHECK(rover->submit(packet("NOOP", {}, 2001)).reason != 0);
}

// The write is not in the command task: a command past the reservation waits,
// queued and unacknowledged, until the reservation is durable, then acts.
TEST_GROUP(AntiReplayDeferred) {
    hal::MemoryRecordStore store;
    ManualWriter writer{store};
    HmacSha256 hmac;
    std::unique_ptr<Boot> rover;

    void setup() override {
        CHECK(core::isOk(hmac.init()));
        rover = std::make_unique<Boot>(&store, true, 42, true, &writer);
    }
    void teardown() override { rover.reset(); }
    Bytes noop(std::uint32_t sequence) { return signedPacket(hmac, "NOOP", {}, sequence); }
    std::uint32_t stored() const {
        AuthStoreEntry entries[kMaxStoredKeys];
        std::size_t n = 0;
        CHECK(core::isOk(decodeAuthStore(store.bytes(), store.length(), entries, &n)));
        return n == 1 ? entries[0].reserved : 0;
    }
};

TEST(AntiReplayDeferred, ACommandPastTheReservationActsOnlyOnceItIsDurable) {
    LONGS_EQUAL(0, stored());  // provisioned at 0 (written at start-up, not through the writer)
    rover->link.push(noop(1));
    rover->link.push(noop(2));
    CHECK_FALSE(rover->step());  // posted, not durable: no acknowledgement, not acted on
    CHECK_FALSE(rover->step());
    LONGS_EQUAL(0, rover->handler.executed);
    LONGS_EQUAL(2, rover->task.counters().storeWaitFrames);
    LONGS_EQUAL(2, rover->task.counters().queueDepth);  // both kept, in order
    LONGS_EQUAL(1, writer.posts);
    writer.finish();
    CHECK(rover->step());
    LONGS_EQUAL(2, rover->handler.executed);  // 1 and 2: the reservation covers both
    LONGS_EQUAL(1 + kReserveBlock, stored());
    LONGS_EQUAL(1 + kReserveBlock, rover->handler.storedAtExecute);
    LONGS_EQUAL(0, rover->lastAck().reason);
}

TEST(AntiReplayDeferred, TheNextReservationIsWrittenAheadOfNeed) {
    rover->link.push(noop(1));
    CHECK_FALSE(rover->step());
    writer.finish();
    CHECK(rover->step());
    // Within kRenewMargin of 1 + kReserveBlock: accepted at once, the next block posted.
    const std::uint32_t near = 1 + kReserveBlock - kRenewMargin + 1;
    LONGS_EQUAL(0, rover->submit(noop(near)).reason);
    CHECK(writer.queued());
    writer.finish();
    CHECK_FALSE(rover->step());
    LONGS_EQUAL(near + kReserveBlock, stored());
    // So the number after the old reservation does not wait.
    LONGS_EQUAL(0, rover->submit(noop(2 + kReserveBlock)).reason);
    LONGS_EQUAL(3, rover->handler.executed);
    LONGS_EQUAL(1, rover->task.counters().storeWaitFrames);
}

TEST(AntiReplayDeferred, AWriteThatNeverFinishesRefusesTheCommandAfterTheWaitLimit) {
    rover->link.push(noop(1));
    for (std::uint32_t i = 0; i < kMaxStoreWaitFrames; ++i) {
        CHECK_FALSE(rover->step());
    }
    CHECK(rover->step());
    const Ack a = rover->lastAck();
    LONGS_EQUAL(static_cast<int>(CommandReject::kSequenceStoreFailed), a.reason);
    LONGS_EQUAL(1, a.detail);
    LONGS_EQUAL(0, rover->handler.executed);
    LONGS_EQUAL(kMaxStoreWaitFrames, rover->task.counters().storeWaitFrames);
}

TEST(AntiReplayDeferred, AFailedWriteRefusesTheWaitingCommandAndTheNextOneTriesAgain) {
    rover->link.push(noop(1));
    CHECK_FALSE(rover->step());
    store.setFailWrites(true);
    writer.finish();
    CHECK(rover->step());
    LONGS_EQUAL(static_cast<int>(CommandReject::kSequenceStoreFailed), rover->lastAck().reason);
    LONGS_EQUAL(1, rover->task.antiReplay().writeFailures());
    LONGS_EQUAL(1, test::drainEventsWithId(rover->events, events::kAuthStoreWriteFailed));
    store.setFailWrites(false);
    rover->link.push(noop(1));  // never recorded: not a replay
    CHECK_FALSE(rover->step());
    writer.finish();
    CHECK(rover->step());
    LONGS_EQUAL(0, rover->lastAck().reason);
    LONGS_EQUAL(1, rover->handler.executed);
}

TEST(AntiReplayDeferred, AuthResyncIsAcknowledgedOnlyOnceItsFloorIsDurable) {
    store.erase();
    rover = std::make_unique<Boot>(&store, false, 42, true, &writer);
    rover->link.push(signedPacket(hmac, "AUTH_RESYNC", nonceArgs(42), 700));
    CHECK_FALSE(rover->step());
    LONGS_EQUAL(1, rover->task.keysUnsynced());
    CHECK(rover->task.antiReplay().challenge() == 42);  // the nonce is not used up yet
    writer.finish();
    CHECK(rover->step());
    LONGS_EQUAL(0, rover->lastAck().reason);
    LONGS_EQUAL(0, rover->task.keysUnsynced());
    CHECK(rover->task.antiReplay().challenge() != 42);
    LONGS_EQUAL(700 + kReserveBlock, stored());
}

TEST_GROUP(AuthStoreCodec){};

TEST(AuthStoreCodec, RoundTripsAndRefusesEveryDamage) {
    const AuthStoreEntry in[2] = {{1, 1025}, {7, 0xFFFFFFFFu}};
    std::uint8_t bytes[kAuthStoreMaxBytes];
    const std::size_t n = encodeAuthStore(in, 2, bytes, sizeof bytes);
    LONGS_EQUAL(kAuthStoreHeaderBytes + 2 * kAuthStoreEntryBytes + 4, n);
    AuthStoreEntry out[kMaxStoredKeys];
    std::size_t count = 0;
    CHECK(core::isOk(decodeAuthStore(bytes, n, out, &count)));
    LONGS_EQUAL(2, count);
    LONGS_EQUAL(7, out[1].keyId);
    CHECK(out[1].reserved == 0xFFFFFFFFu);
    for (std::size_t i = 0; i < n; ++i) {  // any single flipped byte is refused
        std::uint8_t damaged[kAuthStoreMaxBytes];
        std::memcpy(damaged, bytes, n);
        damaged[i] ^= 0x40;
        CHECK_FALSE(core::isOk(decodeAuthStore(damaged, n, out, &count)));
    }
    CHECK_FALSE(core::isOk(decodeAuthStore(bytes, n - 1, out, &count)));  // truncated
    CHECK_FALSE(core::isOk(decodeAuthStore(bytes, 0, out, &count)));
    const AuthStoreEntry twice[2] = {{3, 1}, {3, 2}};
    const std::size_t m = encodeAuthStore(twice, 2, bytes, sizeof bytes);
    CHECK_FALSE(core::isOk(decodeAuthStore(bytes, m, out, &count)));  // one entry per key
}
