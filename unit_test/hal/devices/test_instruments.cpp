// The science instruments' protocol codec (both ends use it) and the flight
// client (hal/devices/instrument.hpp): commands checked before they are sent,
// reports checked before they count, refusals, cancel, faults, liveness, and
// the limit on transition events. Every frame here is hand-made (hostile ones
// included); the emulator's own tests are in unit_test/sim_stub/devices.
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "hal/can/memory_can_bus.hpp"
#include "hal/canopen/le_codec.hpp"
#include "hal/devices/device_events.hpp"
#include "hal/devices/instrument.hpp"
#include "hal/devices/instrument_protocol.hpp"
#include "hal/devices/rse_device_ids.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
namespace inst = rse::hal::instrument;
using inst::Action;
using inst::Kind;
using inst::Refusal;
using inst::Report;
using inst::ReportKind;
using inst::Result;
using inst::State;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;

CanFrame frameOf(Kind kind, const Report& report) {
    CanFrame f;
    inst::encodeReport(kind, report, &f);
    return f;
}

CanFrame statusFrame(Kind kind, State state, Action action, std::uint8_t target, std::uint16_t id,
                     std::uint8_t progress, Result result = Result::kNone, std::uint8_t fault = 0) {
    return frameOf(kind, Report{ReportKind::kStatus, state, action, target, id, progress, result, Refusal::kNone, fault});
}

CanFrame idleFrame(Kind kind = Kind::kGrinder) { return statusFrame(kind, State::kIdle, Action::kNone, 0, 0, 0); }

CanFrame refusalFrame(Kind kind, Refusal why, Action action, std::uint8_t target, std::uint16_t id,
                      State state = State::kIdle, std::uint8_t fault = 0) {
    return frameOf(kind, Report{ReportKind::kRefusal, state, action, target, id, 0, Result::kNone, why, fault});
}

// A bus whose controller refuses every frame.
class RefusingBus final : public CanBus {
public:
    core::Status send(const CanFrame&) override { return core::Status::kUnavailable; }
    core::Status receive(CanFrame*) override { return core::Status::kEmpty; }
    core::Status setFilters(const CanFilter*, std::size_t) override { return core::Status::kOk; }
    CanBusState state() const override { return CanBusState::kBusOff; }
    const CanBusStats& stats() const override { return stats_; }

private:
    CanBusStats stats_;
};

}  // namespace

TEST_GROUP(InstrumentProtocol){};

TEST(InstrumentProtocol, IdsNodesAndActionsPerInstrument) {
    LONGS_EQUAL(0x24, inst::idsOf(Kind::kGrinder).node);
    LONGS_EQUAL(0x6A5, inst::idsOf(Kind::kGrinder).statusCobId);
    LONGS_EQUAL(0x6B5, inst::idsOf(Kind::kGrinder).commandCobId);
    LONGS_EQUAL(0x25, inst::idsOf(Kind::kCamera).node);
    LONGS_EQUAL(0x6A6, inst::idsOf(Kind::kCamera).statusCobId);
    LONGS_EQUAL(0x6B6, inst::idsOf(Kind::kCamera).commandCobId);
    CHECK_TRUE(inst::doesWork(Kind::kGrinder, Action::kSample));
    CHECK_TRUE(inst::doesWork(Kind::kGrinder, Action::kDig));
    CHECK_FALSE(inst::doesWork(Kind::kGrinder, Action::kImage));
    CHECK_FALSE(inst::doesWork(Kind::kGrinder, Action::kCancel));
    CHECK_TRUE(inst::doesWork(Kind::kCamera, Action::kImage));
    CHECK_FALSE(inst::doesWork(Kind::kCamera, Action::kSample));
    CHECK_FALSE(inst::doesWork(Kind::kCamera, static_cast<Action>(200)));
    STRCMP_EQUAL("?", inst::toString(static_cast<Action>(200)));
    STRCMP_EQUAL("?", inst::toString(static_cast<Refusal>(200)));
}

TEST(InstrumentProtocol, CommandsRoundTripAndTheMaxDurationRoundsUpToATenth) {
    std::uint16_t field = 0;
    CHECK_TRUE(inst::durationField(0.0, &field));
    LONGS_EQUAL(0, field);
    CHECK_TRUE(inst::durationField(12.31, &field));
    LONGS_EQUAL(124, field);
    CHECK_TRUE(inst::durationField(12.3, &field));
    LONGS_EQUAL(123, field);
    CHECK_TRUE(inst::durationField(inst::kMaxDurationS, &field));
    LONGS_EQUAL(65535, field);
    for (const double bad : {-0.1, 6553.6, std::nan(""), std::numeric_limits<double>::infinity()}) {
        field = 7;
        CHECK_FALSE(inst::durationField(bad, &field));
        LONGS_EQUAL(7, field);
    }
    inst::Command c;
    c.action = Action::kDig;
    c.target = 200;
    c.commandId = 0xBEEF;
    c.maxDurationDs = 3000;
    CanFrame f;
    inst::encodeCommand(Kind::kGrinder, c, &f);
    LONGS_EQUAL(0x6B5, f.id);
    LONGS_EQUAL(8, f.dlc);
    const std::uint8_t expected[8] = {2, 200, 0xEF, 0xBE, 0xB8, 0x0B, 0, 0};
    MEMCMP_EQUAL(expected, f.data, 8);
    inst::Command back;
    Refusal why = Refusal::kNone;
    CHECK_TRUE(inst::decodeCommand(f, &back, &why));
    CHECK(back.action == Action::kDig);
    LONGS_EQUAL(200, back.target);
    LONGS_EQUAL(0xBEEF, back.commandId);
    LONGS_EQUAL(3000, back.maxDurationDs);
    // Malformed: a length other than 8, RTR, command id 0, reserved bytes.
    CanFrame bad = f;
    bad.dlc = 6;
    CHECK_FALSE(inst::decodeCommand(bad, &back, &why));
    CHECK(why == Refusal::kMalformed);
    bad = f;
    bad.flags = CanFrame::kRemote;
    CHECK_FALSE(inst::decodeCommand(bad, &back, &why));
    bad = f;
    bad.data[2] = bad.data[3] = 0;
    CHECK_FALSE(inst::decodeCommand(bad, &back, &why));
    bad = f;
    bad.data[6] = 0x80;
    CHECK_FALSE(inst::decodeCommand(bad, &back, &why));
}

TEST(InstrumentProtocol, AnExtendCarriesTheCommandItContinuesAndItsExtraWork) {
    inst::Command c;
    c.action = Action::kExtend;
    c.target = 3;
    c.commandId = 0x0102;
    c.maxDurationDs = 600;
    c.extendsCommandId = 0x0A0B;
    CanFrame f;
    inst::encodeCommand(Kind::kCamera, c, &f);
    LONGS_EQUAL(0x6B6, f.id);
    const std::uint8_t expected[8] = {5, 3, 0x02, 0x01, 0x58, 0x02, 0x0B, 0x0A};
    MEMCMP_EQUAL(expected, f.data, 8);
    inst::Command back;
    Refusal why = Refusal::kNone;
    CHECK_TRUE(inst::decodeCommand(f, &back, &why));
    CHECK(back.action == Action::kExtend);
    LONGS_EQUAL(0x0A0B, back.extendsCommandId);
    LONGS_EQUAL(600, back.maxDurationDs);
    STRCMP_EQUAL("extend", inst::toString(Action::kExtend));
    // Malformed: continuing nothing, itself, or with no extra work.
    for (const int bad : {0, 1, 2}) {
        CanFrame g = f;
        if (bad == 0) {
            g.data[6] = g.data[7] = 0;
        } else if (bad == 1) {
            g.data[6] = 0x02;
            g.data[7] = 0x01;
        } else {
            g.data[4] = g.data[5] = 0;
        }
        why = Refusal::kNone;
        CHECK_FALSE(inst::decodeCommand(g, &back, &why));
        CHECK(why == Refusal::kMalformed);
    }
    // Bytes 6-7 stay reserved for every other action.
    inst::Command s;
    s.action = Action::kSample;
    s.target = 1;
    s.commandId = 9;
    s.extendsCommandId = 0x0A0B;  // not sent
    inst::encodeCommand(Kind::kGrinder, s, &f);
    LONGS_EQUAL(0, f.data[6]);
    LONGS_EQUAL(0, f.data[7]);
    CHECK_TRUE(inst::decodeCommand(f, &back, &why));
    LONGS_EQUAL(0, back.extendsCommandId);
}

TEST(InstrumentProtocol, ReportsRoundTripByteForByte) {
    const CanFrame s = statusFrame(Kind::kCamera, State::kBusy, Action::kImage, 9, 0x1234, 42);
    LONGS_EQUAL(0x6A6, s.id);
    const std::uint8_t statusBytes[8] = {0x11, 3, 9, 0x34, 0x12, 42, 0, 0};
    MEMCMP_EQUAL(statusBytes, s.data, 8);
    const CanFrame r = refusalFrame(Kind::kGrinder, Refusal::kOutOfReach, Action::kSample, 2, 7, State::kDone);
    const std::uint8_t refusalBytes[8] = {0x22, 1, 2, 7, 0, 4, 0, 0};
    MEMCMP_EQUAL(refusalBytes, r.data, 8);
    Report got;
    const char* why = nullptr;
    CHECK_TRUE(inst::decodeReport(Kind::kCamera, s.data, &got, &why));
    CHECK(got.kind == ReportKind::kStatus && got.state == State::kBusy && got.action == Action::kImage);
    LONGS_EQUAL(0x1234, got.commandId);
    LONGS_EQUAL(42, got.progressPct);
    CHECK_TRUE(inst::decodeReport(Kind::kGrinder, r.data, &got, &why));
    CHECK(got.kind == ReportKind::kRefusal && got.refusal == Refusal::kOutOfReach && got.state == State::kDone);
    // A refusal echoes whatever action the refused frame held.
    const CanFrame echo = refusalFrame(Kind::kGrinder, Refusal::kUnsupportedAction, static_cast<Action>(77), 0, 3);
    CHECK_TRUE(inst::decodeReport(Kind::kGrinder, echo.data, &got, &why));
}

TEST(InstrumentProtocol, ReportsBreakingTheProtocolsInvariantsAreOutOfRange) {
    struct Case {
        CanFrame frame;
        Kind kind;
    };
    auto raw = [](std::initializer_list<std::uint8_t> bytes) {
        CanFrame f;
        f.dlc = 8;
        std::size_t i = 0;
        for (std::uint8_t b : bytes) {
            f.data[i++] = b;
        }
        return f;
    };
    const Case bad[] = {
        {raw({0x31, 1, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // kind 3
        {raw({0x01, 1, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // kind 0
        {raw({0x14, 1, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // state 4
        {raw({0x11, 3, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // the grinder does not image
        {raw({0x11, 1, 1, 1, 0, 10, 0, 0}), Kind::kCamera},    // the camera does not sample
        {raw({0x11, 4, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // cancel is no work
        {raw({0x11, 5, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // nor is extend (the work is the command's)
        {raw({0x11, 1, 1, 0, 0, 10, 0, 0}), Kind::kGrinder},   // busy without a command id
        {raw({0x10, 1, 0, 5, 0, 0, 0, 0}), Kind::kGrinder},    // a command without a target
        {raw({0x10, 0, 0, 0, 0, 0, 1, 0}), Kind::kGrinder},    // idle, no command, with a result
        {raw({0x11, 1, 1, 1, 0, 100, 0, 0}), Kind::kGrinder},  // busy at 100 %
        {raw({0x12, 1, 1, 1, 0, 99, 0, 0}), Kind::kGrinder},   // done below 100 %
        {raw({0x11, 1, 1, 1, 0, 101, 0, 0}), Kind::kGrinder},  // progress over 100
        {raw({0x11, 1, 1, 1, 0, 10, 2, 0}), Kind::kGrinder},   // busy with a result
        {raw({0x11, 1, 1, 1, 0, 10, 5, 0}), Kind::kGrinder},   // result 5
        {raw({0x13, 1, 1, 1, 0, 10, 0, 0}), Kind::kGrinder},   // failed: no fault, no failure result
        {raw({0x13, 1, 1, 1, 0, 10, 1, 0}), Kind::kGrinder},   // failed: cancelled is no failure
        {raw({0x10, 0, 0, 0, 0, 0, 0, 9}), Kind::kGrinder},    // a fault code in idle
        {raw({0x11, 1, 1, 1, 0, 10, 0, 9}), Kind::kGrinder},   // a fault code in busy
        {raw({0x20, 1, 1, 1, 0, 0, 0, 0}), Kind::kGrinder},    // refusal without a reason
        {raw({0x20, 1, 1, 1, 0, 8, 0, 0}), Kind::kGrinder},    // "offline" is the flight side's own
        {raw({0x20, 1, 1, 1, 0, 1, 1, 0}), Kind::kGrinder},    // refusal with byte 6 set
        {raw({0x20, 1, 1, 1, 0, 1, 0, 5}), Kind::kGrinder},    // a fault code outside failed
    };
    for (const Case& c : bad) {
        Report r;
        r.commandId = 0xAAAA;
        const char* why = nullptr;
        CHECK_FALSE(inst::decodeReport(c.kind, c.frame.data, &r, &why));
        CHECK(why != nullptr);
        LONGS_EQUAL(0xAAAA, r.commandId);  // nothing written
    }
    // And the legal corners: failed with a fault and any result, idle after a
    // cancel or an abort, failed by a fault with no command at all.
    const CanFrame good[] = {
        raw({0x13, 2, 1, 1, 0, 30, 1, 9}), raw({0x10, 2, 1, 1, 0, 30, 1, 0}), raw({0x10, 2, 1, 1, 0, 30, 4, 0}),
        raw({0x13, 0, 0, 0, 0, 0, 0, 1}),  raw({0x13, 2, 1, 1, 0, 30, 2, 0}), raw({0x22, 9, 0, 0, 0, 6, 0, 0}),
    };
    for (const CanFrame& f : good) {
        Report r;
        const char* why = "";
        CHECK_TRUE_TEXT(inst::decodeReport(Kind::kGrinder, f.data, &r, &why), why);
    }
}

TEST_GROUP(InstrumentClient) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* fsw = nullptr;
    hal::MemoryCanEndpoint* device = nullptr;
    unsigned counts[1000] = {};

    void setup() override {
        fsw = wire.attach("fsw");
        device = wire.attach("instrument");
    }
    void drainEvents() {
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            counts[e.id < 1000 ? e.id : 0] += 1;
        }
    }
    std::vector<CanFrame> sent() {
        std::vector<CanFrame> out;
        CanFrame f;
        while (core::isOk(device->receive(&f))) {
            out.push_back(f);
        }
        return out;
    }
};

TEST(InstrumentClient, OfflineUntilItReportsThenCommandsGoOutCheckedAndEncoded) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    CHECK_FALSE(grinder.status().online);
    CHECK(Refusal::kOffline == grinder.command(Action::kSample, 1, 10, 100.0));
    CHECK(sent().empty());
    grinder.onFrame(idleFrame(), 5 * kMs);
    CHECK_TRUE(grinder.status().online);
    CHECK_EQUAL(5 * kMs, grinder.status().lastHeard);
    CHECK(Refusal::kNone == grinder.command(Action::kSample, 1, 11, 100.04));
    CHECK(Refusal::kNone == grinder.command(Action::kCancel, 77, 11, std::nan("")));  // target, duration not sent
    const std::vector<CanFrame> frames = sent();
    LONGS_EQUAL(2, frames.size());
    inst::Command c;
    Refusal why = Refusal::kNone;
    CHECK_TRUE(inst::decodeCommand(frames[0], &c, &why));
    LONGS_EQUAL(0x6B5, frames[0].id);
    CHECK(c.action == Action::kSample);
    LONGS_EQUAL(1, c.target);
    LONGS_EQUAL(11, c.commandId);
    LONGS_EQUAL(1001, c.maxDurationDs);
    CHECK_TRUE(inst::decodeCommand(frames[1], &c, &why));
    CHECK(c.action == Action::kCancel);
    LONGS_EQUAL(0, c.target);
    LONGS_EQUAL(0, c.maxDurationDs);
    LONGS_EQUAL(2, grinder.status().commandsSent);
    LONGS_EQUAL(1, grinder.status().commandsNotSent);
    CHECK(grinder.status().lastRefusal == Refusal::kOffline);
    LONGS_EQUAL(10, grinder.status().lastRefusedCommandId);
    drainEvents();
    LONGS_EQUAL(1, counts[events::kInstrumentOnline]);
    LONGS_EQUAL(1, counts[events::kInstrumentNotSent]);
}

TEST(InstrumentClient, ACommandTheInstrumentCouldNotTakeIsNotSentAndSaysWhy) {
    Instrument camera(*fsw, events, Kind::kCamera);
    camera.onFrame(idleFrame(Kind::kCamera), 0);
    const struct {
        Action action;
        std::uint8_t target;
        std::uint16_t id;
        double maxS;
        Refusal why;
    } cases[] = {
        {Action::kSample, 1, 1, 10.0, Refusal::kUnsupportedAction},
        {Action::kDig, 1, 2, 10.0, Refusal::kUnsupportedAction},
        {Action::kNone, 1, 3, 10.0, Refusal::kUnsupportedAction},
        {static_cast<Action>(99), 1, 4, 10.0, Refusal::kUnsupportedAction},
        {Action::kImage, 0, 5, 10.0, Refusal::kUnknownTarget},
        {Action::kImage, 1, 0, 10.0, Refusal::kMalformed},
        {Action::kCancel, 0, 0, 0.0, Refusal::kMalformed},
        {Action::kImage, 1, 6, -1.0, Refusal::kMalformed},
        {Action::kImage, 1, 7, 7000.0, Refusal::kMalformed},
        {Action::kImage, 1, 8, std::nan(""), Refusal::kMalformed},
        {Action::kImage, 1, 9, std::numeric_limits<double>::infinity(), Refusal::kMalformed},
    };
    std::uint32_t n = 0;
    for (const auto& c : cases) {
        CHECK(c.why == camera.command(c.action, c.target, c.id, c.maxS));
        ++n;
        LONGS_EQUAL(n, camera.status().commandsNotSent);
        CHECK(c.why == camera.status().lastRefusal);
        LONGS_EQUAL(c.id, camera.status().lastRefusedCommandId);
    }
    CHECK(sent().empty());
    LONGS_EQUAL(0, camera.status().commandsSent);
    drainEvents();
    LONGS_EQUAL(4, counts[events::kInstrumentNotSent]);  // 1st, 2nd, 4th, 8th of 11
    // A controller that refuses the frame: not sent either.
    RefusingBus refusing;
    Instrument grinder(refusing, events, Kind::kGrinder);
    grinder.onFrame(idleFrame(), 0);
    CHECK(Refusal::kNotSent == grinder.command(Action::kSample, 3, 1, 0.0));
    LONGS_EQUAL(0, grinder.status().commandsSent);
    LONGS_EQUAL(1, grinder.status().commandsNotSent);
}

TEST(InstrumentClient, AnExtendIsCheckedSentAndItsFollowOnFollowed) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 4, 21, 30), 0);
    const struct {
        std::uint8_t target;
        std::uint16_t id;
        std::uint16_t extendsId;
        double extraS;
        Refusal why;
    } bad[] = {
        {4, 22, 0, 10.0, Refusal::kMalformed},   // continuing nothing
        {4, 22, 22, 10.0, Refusal::kMalformed},  // itself
        {4, 22, 21, 0.0, Refusal::kMalformed},   // no extra work
        {4, 22, 21, 6553.6, Refusal::kMalformed},
        {4, 22, 21, std::nan(""), Refusal::kMalformed},
        {0, 22, 21, 10.0, Refusal::kUnknownTarget},
        {4, 0, 21, 10.0, Refusal::kMalformed},
    };
    for (const auto& c : bad) {
        CHECK(c.why == grinder.command(Action::kExtend, c.target, c.id, c.extraS, c.extendsId));
    }
    LONGS_EQUAL(7, grinder.status().commandsNotSent);
    CHECK(sent().empty());
    CHECK(Refusal::kNone == grinder.command(Action::kExtend, 4, 22, 12.34, 21));
    const std::vector<CanFrame> out = sent();
    LONGS_EQUAL(1, out.size());
    const std::uint8_t expected[8] = {5, 4, 22, 0, 124, 0, 21, 0};  // 12.4 s: rounded up to 0.1 s
    MEMCMP_EQUAL(expected, out[0].data, 8);
    // Taken: the status names the follow-on, a new command id.
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 4, 22, 25), 100 * kMs);
    LONGS_EQUAL(22, grinder.status().commandId);
    LONGS_EQUAL(2, grinder.status().commandsAccepted);
}

TEST(InstrumentClient, ACommandsLifeIsFollowedAndEvented) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    grinder.onFrame(idleFrame(), 0);
    const std::uint32_t changes0 = grinder.status().changes;
    grinder.onFrame(idleFrame(), 100 * kMs);  // the same report again: no change
    LONGS_EQUAL(changes0, grinder.status().changes);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 4, 21, 0), 150 * kMs);
    const InstrumentStatus& s = grinder.status();
    CHECK(s.state == State::kBusy);
    CHECK(s.action == Action::kSample);
    LONGS_EQUAL(4, s.target);
    LONGS_EQUAL(21, s.commandId);
    LONGS_EQUAL(1, s.commandsAccepted);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 4, 21, 50), 200 * kMs);
    LONGS_EQUAL(50, s.progressPct);
    LONGS_EQUAL(1, s.commandsAccepted);  // the same command
    CHECK(s.changes > changes0 + 1);     // progress is a change
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kDone, Action::kSample, 4, 21, 100), 300 * kMs);
    CHECK(s.state == State::kDone);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kDone, Action::kSample, 4, 21, 100), 400 * kMs);
    // The next command is refused (busy elsewhere, say), then one is cancelled.
    grinder.onFrame(refusalFrame(Kind::kGrinder, Refusal::kOutOfReach, Action::kDig, 5, 22, State::kDone), 450 * kMs);
    LONGS_EQUAL(1, s.commandsRefused);
    CHECK(s.lastRefusal == Refusal::kOutOfReach);
    LONGS_EQUAL(22, s.lastRefusedCommandId);
    CHECK(s.state == State::kDone);  // a refusal leaves the status as it was
    LONGS_EQUAL(21, s.commandId);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kDig, 4, 23, 0), 500 * kMs);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kIdle, Action::kDig, 4, 23, 12, Result::kCancelled), 600 * kMs);
    CHECK(s.result == Result::kCancelled);
    LONGS_EQUAL(2, s.commandsAccepted);
    // A command that ends at once is seen accepted and done in one report.
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kDone, Action::kSample, 4, 24, 100), 700 * kMs);
    LONGS_EQUAL(3, s.commandsAccepted);
    drainEvents();
    LONGS_EQUAL(3, counts[events::kInstrumentAccepted]);
    LONGS_EQUAL(2, counts[events::kInstrumentDone]);
    LONGS_EQUAL(1, counts[events::kInstrumentRefused]);
    LONGS_EQUAL(1, counts[events::kInstrumentCancelled]);
    LONGS_EQUAL(0, counts[events::kInstrumentFailed]);
    LONGS_EQUAL(0, grinder.frameStats().badLength + grinder.frameStats().badValue);
}

TEST(InstrumentClient, AFaultAndItsClearingAndAFailedCommandAreEvented) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 1, 5, 40), 0);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kFailed, Action::kSample, 1, 5, 40, Result::kAborted, 0x42),
                    10 * kMs);
    const InstrumentStatus& s = grinder.status();
    CHECK(s.state == State::kFailed);
    LONGS_EQUAL(0x42, s.faultCode);
    CHECK(s.result == Result::kAborted);
    grinder.onFrame(refusalFrame(Kind::kGrinder, Refusal::kFaulted, Action::kSample, 1, 6, State::kFailed, 0x42),
                    20 * kMs);
    CHECK(s.lastRefusal == Refusal::kFaulted);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kIdle, Action::kSample, 1, 5, 40, Result::kAborted), 30 * kMs);
    LONGS_EQUAL(0, s.faultCode);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 1, 7, 0), 40 * kMs);
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kFailed, Action::kSample, 1, 7, 60, Result::kTimedOut), 50 * kMs);
    drainEvents();
    LONGS_EQUAL(2, counts[events::kInstrumentFailed]);
    LONGS_EQUAL(1, counts[events::kInstrumentFaultCleared]);
    LONGS_EQUAL(1, counts[events::kInstrumentRefused]);
}

TEST(InstrumentClient, BadReportsAreCountedEventedWithTheirOwnIdsAndTheLastGoodStatusKept) {
    Instrument camera(*fsw, events, Kind::kCamera);
    camera.onFrame(statusFrame(Kind::kCamera, State::kBusy, Action::kImage, 2, 9, 30), 5 * kMs);
    CanFrame shortFrame = statusFrame(Kind::kCamera, State::kDone, Action::kImage, 2, 9, 100);
    shortFrame.dlc = 5;
    CanFrame rtr = shortFrame;
    rtr.dlc = 8;
    rtr.flags = CanFrame::kRemote;
    CanFrame grinderAction = statusFrame(Kind::kCamera, State::kBusy, Action::kImage, 2, 9, 60);
    grinderAction.data[1] = static_cast<std::uint8_t>(Action::kDig);
    CanFrame wildProgress = statusFrame(Kind::kCamera, State::kBusy, Action::kImage, 2, 9, 60);
    wildProgress.data[5] = 250;
    camera.onFrame(shortFrame, 10 * kMs);
    camera.onFrame(rtr, 20 * kMs);
    camera.onFrame(grinderAction, 30 * kMs);
    camera.onFrame(wildProgress, 40 * kMs);
    const InstrumentStatus& s = camera.status();
    CHECK(s.state == State::kBusy);
    LONGS_EQUAL(30, s.progressPct);
    CHECK_EQUAL(5 * kMs, s.lastHeard);  // bad frames are no sign of life
    LONGS_EQUAL(2, camera.frameStats().badLength);
    LONGS_EQUAL(2, camera.frameStats().badValue);
    drainEvents();
    LONGS_EQUAL(2, counts[events::kInstrumentBadFrame]);
    LONGS_EQUAL(2, counts[events::kInstrumentBadValue]);
    LONGS_EQUAL(0, counts[events::kDeviceBadFrame]);  // the sensors' ids stay theirs
    LONGS_EQUAL(0, counts[events::kDeviceBadValue]);
}

TEST(InstrumentClient, SilenceMakesItOfflineAndAReportBringsItBack) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    grinder.step(0);
    grinder.onFrame(idleFrame(), 10 * kMs);
    for (core::TimeNs t = 20 * kMs; t <= 510 * kMs; t += 10 * kMs) {
        grinder.step(t);
    }
    CHECK_TRUE(grinder.status().online);  // 500 ms since the report: not yet
    grinder.step(520 * kMs);
    CHECK_FALSE(grinder.status().online);
    LONGS_EQUAL(1, grinder.status().offlineCount);
    // The status keeps what it last said; commands are not sent.
    CHECK(grinder.status().state == State::kIdle);
    CHECK(Refusal::kOffline == grinder.command(Action::kDig, 1, 3, 0.0));
    grinder.step(5 * core::kNsPerSec);
    LONGS_EQUAL(1, grinder.status().offlineCount);  // declared once
    grinder.onFrame(idleFrame(), 5 * core::kNsPerSec);
    CHECK_TRUE(grinder.status().online);
    drainEvents();
    LONGS_EQUAL(1, counts[events::kInstrumentOffline]);
    LONGS_EQUAL(2, counts[events::kInstrumentOnline]);
}

TEST(InstrumentClient, AnInstrumentNeverHeardIsReportedOfflineOnceAfterTheBootTimeout) {
    Instrument camera(*fsw, events, Kind::kCamera);
    for (core::TimeNs t = 0; t <= 10 * core::kNsPerSec; t += 10 * kMs) {
        camera.step(t);
        if (t == 3 * core::kNsPerSec) {
            LONGS_EQUAL(0, camera.status().offlineCount);
        }
    }
    LONGS_EQUAL(1, camera.status().offlineCount);
    drainEvents();
    LONGS_EQUAL(1, counts[events::kInstrumentOffline]);
}

// A babbling instrument flips its command id on every frame: at most
// kInstrumentEventsPerSecond transition events a second, the rest counted and
// summed up once a second.
TEST(InstrumentClient, TransitionEventsAreLimitedPerSecond) {
    Instrument grinder(*fsw, events, Kind::kGrinder);
    grinder.onFrame(idleFrame(), 0);
    drainEvents();
    core::TimeNs t = 0;
    for (std::uint16_t id = 1; id <= 100; ++id) {
        t = static_cast<core::TimeNs>(id) * kMs;
        grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 1, id, 1), t);
    }
    grinder.step(t);
    LONGS_EQUAL(100, grinder.status().commandsAccepted);  // every one counted
    LONGS_EQUAL(90, grinder.status().eventsDropped);
    drainEvents();
    LONGS_EQUAL(kInstrumentEventsPerSecond, counts[events::kInstrumentAccepted]);
    LONGS_EQUAL(0, counts[events::kInstrumentEventsDropped]);  // within the second
    grinder.step(core::kNsPerSec + kMs);
    grinder.step(core::kNsPerSec + 2 * kMs);
    drainEvents();
    LONGS_EQUAL(1, counts[events::kInstrumentEventsDropped]);
    // A new second, a new allowance.
    grinder.onFrame(statusFrame(Kind::kGrinder, State::kBusy, Action::kSample, 1, 500, 1), 2 * core::kNsPerSec);
    drainEvents();
    LONGS_EQUAL(kInstrumentEventsPerSecond + 1, counts[events::kInstrumentAccepted]);
}
