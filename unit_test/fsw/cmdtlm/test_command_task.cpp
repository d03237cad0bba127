// The command service: one test per rejection reason, each asserting the
// counter, the specific event and the CMD_ACK in telemetry; plus acceptance,
// the anti-replay window, the lab setting and the allocation rule.
#include <cmath>
#include <cstring>
#include <vector>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/core/byte_codec.hpp"
#include "hal/link/packet_link.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

// A ground link with fixed storage: packets the test queues for the flight
// side, and the telemetry the flight side sends.
class ScriptedLink final : public hal::PacketLink {
public:
    static constexpr std::size_t kSlots = 64;
    struct Packet {
        std::uint8_t bytes[600];
        std::size_t length;
    };

    void push(const std::uint8_t* data, std::size_t length) {
        Packet& p = rx_[(rxHead_ + rxCount_++) % kSlots];
        std::memcpy(p.bytes, data, length);
        p.length = length;
    }
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override {
        if (rxCount_ == 0) {
            return core::Status::kEmpty;
        }
        const Packet& p = rx_[rxHead_];
        rxHead_ = (rxHead_ + 1) % kSlots;
        --rxCount_;
        if (p.length > capacity) {
            return core::Status::kTooLarge;
        }
        std::memcpy(out, p.bytes, p.length);
        *length = p.length;
        return core::Status::kOk;
    }
    core::Status send(const std::uint8_t* data, std::size_t length) override {
        Packet& p = tx_[txCount_ % kSlots];
        std::memcpy(p.bytes, data, length);
        p.length = length;
        ++txCount_;
        return core::Status::kOk;
    }
    const char* name() const override { return "scripted"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }
    void service() override { ++serviced; }

    std::size_t serviced = 0;  // service() calls
    std::size_t sentCount() const { return txCount_; }
    const Packet& sent(std::size_t i) const { return tx_[i % kSlots]; }

private:
    Packet rx_[kSlots] = {};
    std::size_t rxHead_ = 0, rxCount_ = 0;
    Packet tx_[kSlots] = {};
    std::size_t txCount_ = 0;
    hal::PacketLinkStats stats_;
};

class FakeHandler final : public CommandHandler {
public:
    Mode mode() const override { return mode_; }
    CommandOutcome execute(const CommandVerdict& verdict) override {
        ++executed;
        last = verdict.command->code;
        return outcome;
    }
    Mode mode_ = Mode::kSafe;
    CommandOutcome outcome{};
    int executed = 0;
    CommandCode last = CommandCode::kCount;
};

struct Ack {
    std::uint16_t apid, ccsdsSequence, keyId;
    std::uint8_t functionCode, reason;
    std::uint32_t authSequence, accepted, rejected;
    std::int16_t detail;
};

Ack decodeAck(const ScriptedLink::Packet& p) {
    const PrimaryHeader h = decodePrimaryHeader(p.bytes);
    CHECK_EQUAL(CMD_ACK_Tlm::kApid, h.apid);
    core::BeReader r(p.bytes + kTelemetryHeaderSize, p.length - kTelemetryHeaderSize);
    Ack a{};
    a.apid = r.u16();
    a.functionCode = r.u8();
    a.ccsdsSequence = r.u16();
    a.keyId = r.u16();
    a.authSequence = r.u32();
    a.reason = r.u8();
    a.detail = r.i16();
    a.accepted = r.u32();
    a.rejected = r.u32();
    CHECK(r.ok());
    return a;
}

}  // namespace

TEST_GROUP(CommandTask) {
    core::VirtualClock clock;
    core::EventLog* events = nullptr;
    GroundLinks* links = nullptr;
    TelemetryOutput* output = nullptr;
    ScriptedLink* link = nullptr;
    FakeHandler* handler = nullptr;
    CommandTask* task = nullptr;
    HmacSha256 hmac;
    std::uint32_t nextAuth = 1;
    std::uint64_t frame = 0;

    void setup() override {
        events = new core::EventLog(clock);
        links = new GroundLinks;
        output = new TelemetryOutput(clock, *events, *links);
        link = new ScriptedLink;
        handler = new FakeHandler;
        task = new CommandTask(clock, *events, *links, *output, *handler);
        CHECK(core::isOk(task->keys().add(kLabKeyId, kLabKey)));
        CHECK(core::isOk(links->add(link)));
        CHECK(core::isOk(task->init()));
        CHECK(core::isOk(hmac.init()));
        while (core::isOk(events->pop(nullptr))) {
        }
    }
    void teardown() override {
        delete task;
        delete handler;
        delete link;
        delete output;
        delete links;
        delete events;
    }

    std::vector<std::uint8_t> packet(const char* name, const std::vector<std::uint8_t>& args,
                                     std::uint32_t authSequence, const std::uint8_t* key = kLabKey,
                                     std::uint16_t keyId = kLabKeyId) {
        const CommandDesc* c = findCommand(name);
        CHECK(c != nullptr);
        std::vector<std::uint8_t> out(kMaxCommandPacket);
        CommandFields f;
        f.apid = c->apid;
        f.functionCode = c->functionCode;
        f.sequenceCount = static_cast<std::uint16_t>(authSequence);
        f.keyId = keyId;
        f.authSequence = authSequence;
        const std::size_t n =
            encodeCommandPacket(f, args.data(), args.size(), key, hmac, out.data(), out.size());
        CHECK(n > 0);
        out.resize(n);
        return out;
    }
    std::vector<std::uint8_t> packet(const char* name, const std::vector<std::uint8_t>& args = {}) {
        return packet(name, args, nextAuth++);
    }
    void runFrame() {
        core::FrameContext fc;
        fc.frame = frame++;
        clock.advance(10 * core::kNsPerMs);
        task->run(fc);
    }
    Ack submit(const std::vector<std::uint8_t>& bytes) {
        const std::size_t before = link->sentCount();
        link->push(bytes.data(), bytes.size());
        runFrame();
        CHECK_EQUAL(before + 1, link->sentCount());
        return decodeAck(link->sent(link->sentCount() - 1));
    }
    // Checks the reason in the ack, the counter and exactly one event of its id.
    void expectRejected(const Ack& ack, CommandReject reason) {
        STRCMP_EQUAL(toString(reason), toString(static_cast<CommandReject>(ack.reason)));
        LONGS_EQUAL(1, task->counters().byReason[static_cast<std::size_t>(reason)]);
        LONGS_EQUAL(1, task->counters().rejected);
        LONGS_EQUAL(1, test::drainEventsWithId(*events, events::rejectEvent(reason)));
        LONGS_EQUAL(0, handler->executed);
    }
    static void refreshChecksum(std::vector<std::uint8_t>& p) { p[kChecksumOffset] = commandChecksum(p.data(), p.size()); }
};

static std::vector<std::uint8_t> u8Arg(std::uint8_t v) { return {v}; }
static std::vector<std::uint8_t> f64Args(std::initializer_list<double> values) {
    std::vector<std::uint8_t> out(values.size() * 8);
    core::BeWriter w(out.data(), out.size());
    for (double v : values) {
        w.f64(v);
    }
    return out;
}

TEST(CommandTask, AuthenticatedCommandIsExecutedAndAcknowledged) {
    const Ack ack = submit(packet("SET_MODE", u8Arg(1), 41));
    LONGS_EQUAL(0, ack.reason);
    LONGS_EQUAL(0x180, ack.apid);
    LONGS_EQUAL(3, ack.functionCode);
    LONGS_EQUAL(kLabKeyId, ack.keyId);
    LONGS_EQUAL(41, ack.authSequence);
    LONGS_EQUAL(1, ack.accepted);
    LONGS_EQUAL(1, handler->executed);
    CHECK(handler->last == CommandCode::SET_MODE);
    LONGS_EQUAL(1, task->counters().accepted);
    LONGS_EQUAL(0, task->counters().rejected);
    LONGS_EQUAL(1, test::drainEventsWithId(*events, events::kCommandExecuted));
}

TEST(CommandTask, ServicesEachLinkOnceAFrameButThoseItsOwnerServices) {
    // A UDP link's ICMP reports wait for service() (hal/link/udp_packet_link.hpp);
    // the CAN link's transport is the CAN I/O task's, so not serviced twice.
    ScriptedLink owned;
    CHECK(core::isOk(links->add(&owned, GroundLinks::Service::kByOwner)));
    for (int i = 0; i < 3; ++i) {
        runFrame();
    }
    LONGS_EQUAL(3, link->serviced);
    LONGS_EQUAL(0, owned.serviced);
}

TEST(CommandTask, TruncatedPacketIsRejectedForLength) {
    std::vector<std::uint8_t> p = packet("NOOP");
    p.resize(p.size() - 3);  // the length field now disagrees with the bytes
    expectRejected(submit(p), CommandReject::kBadLength);
}

TEST(CommandTask, ArgumentBytesOfTheWrongSizeAreRejectedForLength) {
    expectRejected(submit(packet("SET_MODE", {1, 0})), CommandReject::kBadLength);
}

TEST(CommandTask, PacketLongerThanAnyCommandIsRejectedForLength) {
    std::vector<std::uint8_t> p(kMaxCommandPacket + 40, 0);
    PrimaryHeader h;
    h.type = PacketType::kCommand;
    h.apid = 0x180;
    h.dataLength = static_cast<std::uint16_t>(p.size() - 7);
    encodePrimaryHeader(h, p.data());
    expectRejected(submit(p), CommandReject::kBadLength);
}

TEST(CommandTask, WrongVersionOrTelemetryTypeIsRejectedAsBadHeader) {
    std::vector<std::uint8_t> p = packet("NOOP");
    p[0] = static_cast<std::uint8_t>(p[0] | 0x20);  // version 1
    refreshChecksum(p);
    expectRejected(submit(p), CommandReject::kBadHeader);
}

TEST(CommandTask, FlippedBitIsRejectedForChecksum) {
    std::vector<std::uint8_t> p = packet("SET_MODE", u8Arg(1));
    p[kCommandHeaderSize] ^= 0x01;
    expectRejected(submit(p), CommandReject::kBadChecksum);
}

TEST(CommandTask, UnknownApidIsRejected) {
    std::vector<std::uint8_t> p = packet("NOOP");
    p[1] = 0xFF;  // APID 0x1FF
    refreshChecksum(p);
    const Ack ack = submit(p);
    LONGS_EQUAL(0x1FF, ack.apid);
    expectRejected(ack, CommandReject::kUnknownApid);
}

TEST(CommandTask, UnknownFunctionCodeIsRejected) {
    std::vector<std::uint8_t> p = packet("NOOP");
    p[6] = 0x55;
    refreshChecksum(p);
    const Ack ack = submit(p);
    LONGS_EQUAL(0x55, ack.functionCode);
    expectRejected(ack, CommandReject::kUnknownFunction);
}

TEST(CommandTask, UnauthenticatedCommandIsRejectedAsMacMissing) {
    expectRejected(submit(packet("NOOP", {}, 7, nullptr, kNoKey)), CommandReject::kMacMissing);
}

TEST(CommandTask, LabSettingAcceptsUnauthenticatedCommands) {
    task->setAuthRequired(false);
    const Ack ack = submit(packet("NOOP", {}, 7, nullptr, kNoKey));
    LONGS_EQUAL(0, ack.reason);
    LONGS_EQUAL(1, handler->executed);
}

// Issue 14 item 4: on the link an unknown key id reads exactly as a bad MAC
// (ack reason, detail and event), so a sender without a key learns nothing about
// which ids exist; the per-reason counter (HK) still says unknown_key.
TEST(CommandTask, UnknownKeyIdIsAcknowledgedAndEventedAsBadMacButCountedApart) {
    const Ack ack = submit(packet("NOOP", {}, 7, kLabKey, 9));
    STRCMP_EQUAL("bad_mac", toString(static_cast<CommandReject>(ack.reason)));
    LONGS_EQUAL(-1, ack.detail);
    LONGS_EQUAL(9, ack.keyId);
    LONGS_EQUAL(1, task->counters().byReason[static_cast<std::size_t>(CommandReject::kUnknownKey)]);
    LONGS_EQUAL(0, task->counters().byReason[static_cast<std::size_t>(CommandReject::kBadMac)]);
    LONGS_EQUAL(1, task->counters().rejected);
    CHECK(CommandReject::kBadMac == task->counters().lastResult);
    unsigned unknownKeyEvents = 0;
    unsigned badMacEvents = 0;
    core::Event e;
    while (core::isOk(events->pop(&e))) {
        unknownKeyEvents += e.id == events::rejectEvent(CommandReject::kUnknownKey) ? 1U : 0U;
        badMacEvents += e.id == events::rejectEvent(CommandReject::kBadMac) ? 1U : 0U;
        if (e.id == events::rejectEvent(CommandReject::kBadMac)) {
            CHECK(std::strstr(e.text, "bad_mac") != nullptr);
            CHECK(std::strstr(e.text, "unknown_key") == nullptr);
        }
    }
    LONGS_EQUAL(0, unknownKeyEvents);
    LONGS_EQUAL(1, badMacEvents);
    LONGS_EQUAL(0, handler->executed);
}

TEST(CommandTask, UnknownKeyAndBadMacAcknowledgementsAreIdenticalButForTheEchoedKeyId) {
    std::uint8_t otherKey[kKeySize];
    std::memcpy(otherKey, kLabKey, kKeySize);
    otherKey[0] ^= 1;
    const Ack unknown = submit(packet("NOOP", {}, 7, kLabKey, 9));
    const Ack badMac = submit(packet("NOOP", {}, 8, otherKey, kLabKeyId));
    LONGS_EQUAL(badMac.reason, unknown.reason);
    LONGS_EQUAL(badMac.detail, unknown.detail);
    LONGS_EQUAL(badMac.apid, unknown.apid);
    LONGS_EQUAL(badMac.functionCode, unknown.functionCode);
}

TEST(CommandTask, UnknownKeyWithNoRoomForAMacIsBadLengthLikeAKnownKey) {
    std::vector<std::uint8_t> known = packet("NOOP", {}, 7);
    std::vector<std::uint8_t> unknown = packet("NOOP", {}, 8, kLabKey, 9);
    for (std::vector<std::uint8_t>* p : {&known, &unknown}) {
        p->resize(kCommandHeaderSize + kMacSize - 1);
        (*p)[4] = 0;
        (*p)[5] = static_cast<std::uint8_t>(p->size() - 7);
        refreshChecksum(*p);
    }
    const Ack a = submit(known);
    const Ack b = submit(unknown);
    STRCMP_EQUAL("bad_length", toString(static_cast<CommandReject>(a.reason)));
    STRCMP_EQUAL("bad_length", toString(static_cast<CommandReject>(b.reason)));
}

TEST(CommandTask, WrongKeyIsRejectedAsBadMac) {
    std::uint8_t otherKey[kKeySize];
    std::memcpy(otherKey, kLabKey, kKeySize);
    otherKey[0] ^= 1;
    expectRejected(submit(packet("NOOP", {}, 7, otherKey, kLabKeyId)), CommandReject::kBadMac);
}

TEST(CommandTask, AlteredArgumentWithRecomputedChecksumIsRejectedAsBadMac) {
    std::vector<std::uint8_t> p = packet("SET_MODE", u8Arg(1));
    p[kCommandHeaderSize] = 3;  // an attacker changes the mode and fixes the checksum
    refreshChecksum(p);
    expectRejected(submit(p), CommandReject::kBadMac);
}

TEST(CommandTask, ReplayedCommandIsRejected) {
    const std::vector<std::uint8_t> p = packet("NOOP", {}, 100);
    LONGS_EQUAL(0, submit(p).reason);
    (void)test::drainEventsWithId(*events, 0);
    handler->executed = 0;
    task->resetCounters();
    expectRejected(submit(p), CommandReject::kReplayedSequence);
}

TEST(CommandTask, SequenceOlderThanTheWindowIsStale) {
    LONGS_EQUAL(0, submit(packet("NOOP", {}, 1000)).reason);
    LONGS_EQUAL(0, submit(packet("NOOP", {}, 990)).reason);  // out of order within the window: fresh once
    (void)test::drainEventsWithId(*events, 0);
    handler->executed = 0;
    task->resetCounters();
    expectRejected(submit(packet("NOOP", {}, 1000 - kReplayWindow)), CommandReject::kStaleSequence);
}

TEST(CommandTask, ForgedPacketDoesNotAdvanceTheReplayWindow) {
    std::uint8_t otherKey[kKeySize] = {};
    LONGS_EQUAL(static_cast<int>(CommandReject::kBadMac),
                submit(packet("NOOP", {}, 5000, otherKey, kLabKeyId)).reason);
    LONGS_EQUAL(0, submit(packet("NOOP", {}, 50)).reason);  // 5000 was never recorded
}

TEST(CommandTask, ArgumentOutOfRangeIsRejectedNamingTheArgument) {
    const Ack ack = submit(packet("SET_MODE", u8Arg(7)));
    LONGS_EQUAL(0, ack.detail);
    expectRejected(ack, CommandReject::kArgumentOutOfRange);
}

TEST(CommandTask, NonFiniteArgumentIsRejectedAsOutOfRange) {
    handler->mode_ = Mode::kStandby;
    const Ack ack = submit(packet("GOTO", f64Args({1.0, 2.0, std::nan("")})));
    LONGS_EQUAL(2, ack.detail);  // risk
    expectRejected(ack, CommandReject::kArgumentOutOfRange);
}

TEST(CommandTask, CommandNotAllowedInTheModeIsRejected) {
    std::vector<std::uint8_t> args(12);
    core::BeWriter w(args.data(), args.size());
    w.f32(0.1F);
    w.f32(0.0F);
    w.f32(1.0F);
    handler->mode_ = Mode::kSafe;  // DRIVE needs MANUAL
    expectRejected(submit(packet("DRIVE", args)), CommandReject::kWrongMode);
}

TEST(CommandTask, QueueOverflowIsRejectedAndCountedNotLost) {
    const std::size_t extra = 4;
    for (std::size_t i = 0; i < kCommandQueueDepth + extra; ++i) {
        const std::vector<std::uint8_t> p = packet("NOOP");
        link->push(p.data(), p.size());
    }
    runFrame();
    LONGS_EQUAL(extra, task->counters().byReason[static_cast<std::size_t>(CommandReject::kQueueOverflow)]);
    LONGS_EQUAL(extra, test::drainEventsWithId(*events, events::rejectEvent(CommandReject::kQueueOverflow)));
    LONGS_EQUAL(kCommandQueueDepth, task->counters().queueHighWater);
    // The queued ones all run in the frames that follow; each packet got one ack.
    for (int f = 0; f < 10; ++f) {
        runFrame();
    }
    LONGS_EQUAL(kCommandQueueDepth, task->counters().accepted);
    LONGS_EQUAL(kCommandQueueDepth + extra, link->sentCount());
    LONGS_EQUAL(static_cast<int>(CommandReject::kQueueOverflow), decodeAck(link->sent(0)).reason);
}

TEST(CommandTask, HandlerFailureIsRejectedAsExecutionFailed) {
    handler->outcome = CommandOutcome{false, 3};
    const Ack ack = submit(packet("NOOP"));
    LONGS_EQUAL(3, ack.detail);
    STRCMP_EQUAL("execution_failed", toString(static_cast<CommandReject>(ack.reason)));
    LONGS_EQUAL(1, task->counters().byReason[static_cast<std::size_t>(CommandReject::kExecutionFailed)]);
    LONGS_EQUAL(1, test::drainEventsWithId(*events, events::rejectEvent(CommandReject::kExecutionFailed)));
}

TEST(CommandTask, RejectionFloodIsEventedAtABoundedRateButCountedInFull) {
    std::vector<std::uint8_t> bad = packet("NOOP");
    bad[kCommandHeaderSize - 1] ^= 0xFF;  // bad checksum
    for (int i = 0; i < 40; ++i) {
        link->push(bad.data(), bad.size());
        runFrame();
    }
    LONGS_EQUAL(40, task->counters().byReason[static_cast<std::size_t>(CommandReject::kBadChecksum)]);
    LONGS_EQUAL(kRejectEventsPerSecond,
                test::drainEventsWithId(*events, events::rejectEvent(CommandReject::kBadChecksum)));
    LONGS_EQUAL(40 - kRejectEventsPerSecond, task->counters().rejectEventsSuppressed);
}

TEST(CommandTask, NoHeapUseWhileCommandsFlow) {
    std::vector<std::vector<std::uint8_t>> packets;
    for (int i = 0; i < 200; ++i) {
        packets.push_back(packet(i % 3 == 0 ? "NOOP" : "SET_MODE", i % 3 == 0 ? std::vector<std::uint8_t>{} : u8Arg(1)));
    }
    std::vector<std::uint8_t> bad = packets[1];
    bad[3] ^= 1;
    test::AllocationWatch watch;
    for (const auto& p : packets) {
        link->push(p.data(), p.size());
        link->push(bad.data(), bad.size());
        runFrame();
        (void)test::drainEventsWithId(*events, 0);
    }
    LONGS_EQUAL(0, watch.count());
    LONGS_EQUAL(200, task->counters().accepted);
}

// ---- Floods (docs/icd.md, "Floods") ------------------------------------------------

namespace {

// A ground link that hands out garbage - endless, or a given number of packets -
// with one valid command at a chosen position, optionally charging each receive
// some time on the virtual clock; it counts the acknowledgements it is sent.
class FloodLink final : public hal::PacketLink {
public:
    static constexpr std::size_t kEndless = static_cast<std::size_t>(-1);

    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override {
        if (clock != nullptr) {
            clock->advance(costPerReceive + (handed == stallAt ? stall : 0));
        }
        if (handed == validAt) {
            ++handed;
            CHECK(valid.size() <= capacity);
            std::memcpy(out, valid.data(), valid.size());
            *length = valid.size();
            ++stats_.rxPackets;
            return core::Status::kOk;
        }
        if (garbageLeft == 0) {
            return core::Status::kEmpty;
        }
        if (garbageLeft != kEndless) {
            --garbageLeft;
        }
        if (!forged.empty()) {
            std::memcpy(out, forged.data(), forged.size());
            *length = forged.size();
            ++handed;
            ++stats_.rxPackets;
            return core::Status::kOk;
        }
        // Random bytes, 1 to 40 of them: the length field never matches.
        const std::size_t n = 1 + (handed * 7919U) % 40U;
        for (std::size_t i = 0; i < n; ++i) {
            seed = seed * 1103515245U + 12345U;
            out[i] = static_cast<std::uint8_t>(seed >> 16);
        }
        if (n >= 6) {
            out[4] = 0xFF;  // length field 0xFFxx: never this packet's
        }
        *length = n;
        ++handed;
        ++stats_.rxPackets;
        return core::Status::kOk;
    }
    core::Status send(const std::uint8_t* data, std::size_t length) override {
        if (decodePrimaryHeader(data).apid == CMD_ACK_Tlm::kApid) {
            ++acks;
            const std::size_t reasonOffset = kTelemetryHeaderSize + 2 + 1 + 2 + 2 + 4;
            CHECK(length > reasonOffset);
            acceptedAcks += data[reasonOffset] == 0 ? 1U : 0U;
        }
        return core::Status::kOk;
    }
    const char* name() const override { return "flood"; }
    const hal::PacketLinkStats& stats() const override { return stats_; }

    std::size_t garbageLeft = 0;
    std::size_t validAt = kEndless;
    std::vector<std::uint8_t> valid;
    std::vector<std::uint8_t> forged;  // when set, the flood is copies of it instead of random bytes
    std::size_t handed = 0;
    core::VirtualClock* clock = nullptr;
    core::TimeNs costPerReceive = 0;
    std::size_t stallAt = kEndless;  // this receive also takes `stall` (the VM paused, say)
    core::TimeNs stall = 0;
    std::uint32_t seed = 1;
    std::size_t acks = 0;
    std::size_t acceptedAcks = 0;

private:
    hal::PacketLinkStats stats_;
};

}  // namespace

TEST_GROUP_BASE(CommandFlood, TEST_GROUP_CppUTestGroupCommandTask) {
    FloodLink* flood = nullptr;
    void setup() override {
        TEST_GROUP_CppUTestGroupCommandTask::setup();
        flood = new FloodLink;
        CHECK(core::isOk(links->add(flood)));
    }
    void teardown() override {
        TEST_GROUP_CppUTestGroupCommandTask::teardown();
        delete flood;
    }
};

// Old ingest read 16 packets a link a frame and queued every one: a valid
// command behind 1000 garbage packets waited (and mostly drowned in the socket).
TEST(CommandFlood, AValidCommandBehindAThousandGarbagePacketsIsExecutedInThatFrame) {
    flood->garbageLeft = 2000;
    flood->validAt = 1000;
    flood->valid = packet("NOOP");
    runFrame();
    LONGS_EQUAL(1, handler->executed);
    LONGS_EQUAL(1, task->counters().accepted);
    LONGS_EQUAL(2000, task->counters().rejected);
    LONGS_EQUAL(2000, task->counters().byReason[static_cast<std::size_t>(CommandReject::kBadLength)]);
    LONGS_EQUAL(0, task->counters().byReason[static_cast<std::size_t>(CommandReject::kQueueOverflow)]);
    LONGS_EQUAL(2001, task->counters().linkRxPackets);
    LONGS_EQUAL(0, task->counters().ingestLimited);  // the link was emptied
    LONGS_EQUAL(1, flood->acceptedAcks);
}

// A well-formed packet under a loaded key id with a wrong MAC passes the cheap
// screen. Old ingest queued it (the MAC waited for dispatch, 2 a frame): a flood
// of them filled the queue and the valid command met queue_overflow.
TEST(CommandFlood, AFloodWithAKnownKeyIdButAWrongMacTakesNoQueueSlot) {
    std::uint8_t otherKey[kKeySize];
    std::memcpy(otherKey, kLabKey, kKeySize);
    otherKey[5] ^= 0x10;
    flood->forged = packet("NOOP", {}, 900, otherKey, kLabKeyId);
    flood->garbageLeft = 300;
    flood->validAt = 150;
    flood->valid = packet("NOOP");
    runFrame();
    LONGS_EQUAL(1, handler->executed);
    LONGS_EQUAL(300, task->counters().byReason[static_cast<std::size_t>(CommandReject::kBadMac)]);
    LONGS_EQUAL(0, task->counters().byReason[static_cast<std::size_t>(CommandReject::kQueueOverflow)]);
    LONGS_EQUAL(1, task->counters().queueHighWater);
    LONGS_EQUAL(1, flood->acceptedAcks);
}

TEST(CommandFlood, RejectionAcksAreRateLimitedAndCountedWhileAcceptancesAlwaysGo) {
    flood->garbageLeft = 200;
    runFrame();
    LONGS_EQUAL(200, task->counters().rejected);
    LONGS_EQUAL(kRejectAckBurst, flood->acks);
    LONGS_EQUAL(200 - kRejectAckBurst, task->counters().acksSuppressed);
    // The bucket is empty; a valid command is still acknowledged, and so is an
    // authenticated rejection (wrong mode).
    const std::size_t acksBefore = flood->acks;
    const Ack accepted = submit(packet("NOOP"));
    LONGS_EQUAL(0, accepted.reason);
    std::vector<std::uint8_t> drive(12);
    core::BeWriter w(drive.data(), drive.size());
    w.f32(0.1F);
    w.f32(0.0F);
    w.f32(1.0F);
    const Ack wrongMode = submit(packet("DRIVE", drive));
    STRCMP_EQUAL("wrong_mode", toString(static_cast<CommandReject>(wrongMode.reason)));
    LONGS_EQUAL(acksBefore + 2, flood->acks);
    // The bucket refills at kRejectAcksPerSecond: one second later as many go again.
    for (int f = 0; f < 100; ++f) {
        runFrame();
    }
    flood->garbageLeft = 200;
    runFrame();
    LONGS_EQUAL(acksBefore + 2 + kRejectAcksPerSecond, flood->acks);
    LONGS_EQUAL(400 - kRejectAckBurst - kRejectAcksPerSecond, task->counters().acksSuppressed);
    LONGS_EQUAL(401, task->counters().rejected);
}

// A run over budget because ingest's thread stopped (a gap between two looks at
// the clock that 32 packets cannot take) is told from one over budget by its
// own work.
TEST(CommandFlood, AStalledRunIsToldFromARunOverBudgetByItsOwnWork) {
    task->setRunBudget(500 * core::kNsPerUs);
    flood->clock = &clock;
    flood->garbageLeft = 300;
    flood->stallAt = 100;
    flood->stall = 3 * core::kNsPerMs;
    runFrame();
    // The stall used the allowance up: ingest stopped at its next look at the clock.
    LONGS_EQUAL(128, task->counters().rejected);
    LONGS_EQUAL(1, task->counters().ingestLimited);
    LONGS_EQUAL(1, task->counters().stalledRuns);
    LONGS_EQUAL(0, task->counters().overBudgetLessStalls);
    CHECK(task->counters().longestRunLessStallsUs <= kIngestStallGap / core::kNsPerUs);

    // 2 us a packet, no stall: ingest works its whole 1.2 ms allowance, over this budget.
    flood->garbageLeft = FloodLink::kEndless;
    flood->costPerReceive = 2 * core::kNsPerUs;
    runFrame();
    LONGS_EQUAL(1, task->counters().stalledRuns);
    LONGS_EQUAL(1, task->counters().overBudgetLessStalls);
    CHECK(task->counters().longestRunLessStallsUs >= kIngestAllowance / core::kNsPerUs);
}

TEST(CommandFlood, IngestReadsAtMostItsPacketLimitPerFrameAndLeavesTheRestInTheLink) {
    flood->garbageLeft = FloodLink::kEndless;
    runFrame();
    LONGS_EQUAL(kMaxPacketsPerLink, flood->handed);
    LONGS_EQUAL(1, task->counters().ingestLimited);
    runFrame();
    LONGS_EQUAL(2 * kMaxPacketsPerLink, flood->handed);
    LONGS_EQUAL(2, task->counters().ingestLimited);
}

TEST(CommandFlood, IngestStopsAtItsTimeAllowanceWhenPacketsAreSlowToRead) {
    flood->garbageLeft = FloodLink::kEndless;
    flood->clock = &clock;
    flood->costPerReceive = 2 * core::kNsPerUs;  // 2 us a packet: 1.2 ms buys 600
    const core::TimeNs before = clock.now() + 10 * core::kNsPerMs;  // runFrame() advances 10 ms first
    runFrame();
    const core::TimeNs spent = clock.now() - before;
    CHECK(spent >= kIngestAllowance);  // the flooded link is the last: all of the allowance
    CHECK(spent <= kIngestAllowance + static_cast<core::TimeNs>(kIngestCheckEvery) * 2 * core::kNsPerUs);
    CHECK(flood->handed < kMaxPacketsPerLink);
    LONGS_EQUAL(0, flood->handed % kIngestCheckEvery);
    LONGS_EQUAL(1, task->counters().ingestLimited);
    // A link after the flooded one keeps its reserve of the allowance.
    ScriptedLink* late = new ScriptedLink;
    CHECK(core::isOk(links->add(late)));
    const std::vector<std::uint8_t> p = packet("NOOP");
    late->push(p.data(), p.size());
    const std::size_t handedBefore = flood->handed;
    const core::TimeNs start = clock.now() + 10 * core::kNsPerMs;
    runFrame();
    LONGS_EQUAL(1, handler->executed);
    LONGS_EQUAL(2, task->counters().ingestLimited);
    const core::TimeNs floodTime = static_cast<core::TimeNs>(flood->handed - handedBefore) * 2 * core::kNsPerUs;
    CHECK(floodTime >= kIngestAllowance - kIngestLinkReserve);
    CHECK(floodTime < kIngestAllowance);
    CHECK(clock.now() - start < kIngestAllowance + static_cast<core::TimeNs>(kIngestCheckEvery) * 2 * core::kNsPerUs);
    delete late;
}

TEST(CommandFlood, AFloodIsSummarisedByOneEventASecond) {
    flood->garbageLeft = FloodLink::kEndless;
    (void)test::drainEventsWithId(*events, 0);
    for (int f = 0; f < 250; ++f) {  // 2.5 s
        runFrame();
    }
    LONGS_EQUAL(2, test::drainEventsWithId(*events, events::kIngestFlood));
    // A quiet second raises none.
    flood->garbageLeft = 0;
    for (int f = 0; f < 200; ++f) {
        runFrame();
    }
    LONGS_EQUAL(1, test::drainEventsWithId(*events, events::kIngestFlood));  // the tail of the flood's last second
}

TEST(CommandFlood, ResetCountersStartsTheLinkCountsAgain) {
    flood->garbageLeft = 50;
    runFrame();
    LONGS_EQUAL(50, task->counters().linkRxPackets);
    task->resetCounters();
    flood->garbageLeft = 5;
    runFrame();
    LONGS_EQUAL(5, task->counters().linkRxPackets);
    LONGS_EQUAL(5, task->counters().rejected);
}

// The screen is check()'s first half: whatever it refuses, check() refuses for
// the same reason; whatever it passes, check() refuses (if at all) only for the
// MAC or later. Every single-byte corruption and every truncation of valid packets.
TEST(CommandFlood, TheIngestScreenAgreesWithTheFullCheck) {
    KeyStore keys;
    CHECK(core::isOk(keys.add(kLabKeyId, kLabKey)));
    HmacSha256 engine;
    CHECK(core::isOk(engine.init()));
    CommandValidator validator(keys, engine);
    std::vector<std::vector<std::uint8_t>> originals = {packet("NOOP"), packet("SET_MODE", u8Arg(1)),
                                                        packet("GOTO", f64Args({1.0, 2.0, 1e-3}))};
    std::size_t screened = 0, unauthentic = 0, passed = 0;
    for (const auto& original : originals) {
        for (std::size_t cut = 0; cut <= original.size(); ++cut) {
            for (std::size_t at = 0; at < original.size(); ++at) {
                for (const std::uint8_t flip : {0x00, 0x01, 0x80, 0xFF}) {
                    std::vector<std::uint8_t> p = original;
                    p[at] = static_cast<std::uint8_t>(p[at] ^ flip);
                    p.resize(cut);
                    if (at % 2 == 1 && p.size() > kChecksumOffset) {
                        refreshChecksum(p);  // an attacker's edit with a valid checksum: the MAC's turn
                    }
                    for (const bool authRequired : {true, false}) {
                        validator.setAuthRequired(authRequired);
                        const CommandVerdict s = validator.screen(p.data(), p.size());
                        const CommandVerdict a = validator.authenticate(p.data(), p.size());
                        const CommandVerdict c = validator.check(p.data(), p.size(), Mode::kSafe);
                        if (s.reason != CommandReject::kAccepted) {
                            ++screened;
                            STRCMP_EQUAL(toString(c.reason), toString(s.reason));
                            STRCMP_EQUAL(toString(a.reason), toString(s.reason));
                        } else if (a.reason != CommandReject::kAccepted) {
                            ++unauthentic;
                            STRCMP_EQUAL(toString(c.reason), toString(a.reason));
                        } else {
                            ++passed;
                            CHECK(c.reason == CommandReject::kAccepted || c.reason > CommandReject::kBadMac ||
                                  (c.reason == CommandReject::kBadLength && c.args != nullptr));
                        }
                    }
                }
            }
        }
    }
    CHECK(screened > 1000);
    CHECK(unauthentic > 100);
    CHECK(passed > 10);
}
