// The mobility commands (APID 0x182): the e-stop through its switch (the mode
// owner's EstopSwitch face: evented, announced), a manual drive (refused while
// the e-stop holds), an interlock reset request.
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/rover_mode.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/reflexive/mobility_commands.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;

TEST_GROUP(MobilityCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    cmdtlm::RoverMode mode{clock, bus, events};
    test::BusProbe<msg::ModeMsg> modes{bus, "modes"};
    test::BusProbe<msg::ManualDriveMsg> drives{bus, "drives"};
    test::BusProbe<msg::InterlockResetMsg> resets{bus, "resets"};
    reflexive::MobilityCommands commands{clock, bus, mode};
    cmdtlm::CommandOutcome execute(CommandCode code) {
        const test::AcceptedCommand c(code);
        return commands.execute(c.verdict());
    }
    cmdtlm::CommandOutcome drive(float v, float omega, float duration) {
        const test::AcceptedCommand c(CommandCode::DRIVE, cmdtlm::DRIVE_Args{v, omega, duration});
        return commands.execute(c.verdict());
    }
};

TEST(MobilityCommands, OwnsTheMobilityApid) { LONGS_EQUAL(0x182, commands.apid()); }

TEST(MobilityCommands, TheEstopIsTheModeOwnersAndIsEventedAndAnnounced) {
    mode.setMode(cmdtlm::Mode::kManual);
    (void)modes.drain();
    (void)test::drainEventsWithId(events, 0);  // the mode change's
    CHECK_TRUE(execute(CommandCode::ESTOP_SET).ok);
    CHECK_TRUE(mode.estop());
    msg::ModeMsg m{};
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(1, m.estop);
    LONGS_EQUAL(msg::mode::kManual, m.mode);  // the mode is not the e-stop's to change
    CHECK_TRUE(execute(CommandCode::ESTOP_CLEAR).ok);
    CHECK_FALSE(mode.estop());
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(0, m.estop);
    LONGS_EQUAL(msg::mode::kManual, m.mode);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(cmdtlm::events::kEstopSet, e.id);
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(cmdtlm::events::kEstopCleared, e.id);
    CHECK_FALSE(core::isOk(events.pop(&e)));
}

namespace {

// A switch that only remembers: the mobility commands need no more of the mode owner.
class RecordingSwitch final : public cmdtlm::EstopSwitch {
public:
    bool estop() const override { return held; }
    void setEstop(bool set) override {
        held = set;
        ++changes;
    }
    bool held = false;
    unsigned changes = 0;
};

}  // namespace

TEST(MobilityCommands, TheCommandsNeedOnlyTheEstopSwitch) {
    RecordingSwitch estop;
    reflexive::MobilityCommands narrow{clock, bus, estop};
    const test::AcceptedCommand set(CommandCode::ESTOP_SET);
    CHECK_TRUE(narrow.execute(set.verdict()).ok);
    CHECK_TRUE(estop.held);
    const test::AcceptedCommand go(CommandCode::DRIVE, cmdtlm::DRIVE_Args{0.5F, 0.0F, 1.0F});
    CHECK_FALSE(narrow.execute(go.verdict()).ok);  // held
    const test::AcceptedCommand clear(CommandCode::ESTOP_CLEAR);
    CHECK_TRUE(narrow.execute(clear.verdict()).ok);
    CHECK_TRUE(narrow.execute(go.verdict()).ok);
    LONGS_EQUAL(2, estop.changes);
    LONGS_EQUAL(1, drives.drain());
    LONGS_EQUAL(0, modes.drain());  // the switch, not the commands, announces
}

TEST(MobilityCommands, ADriveGoesToTheManualDriveTaskUnlessTheEstopHolds) {
    clock.advance(3 * core::kNsPerSec);
    CHECK_TRUE(drive(0.5F, -0.25F, 4.0F).ok);
    msg::ManualDriveMsg m{};
    LONGS_EQUAL(1, drives.drain(&m));
    DOUBLES_EQUAL(0.5, m.speedMS, 0.0);
    DOUBLES_EQUAL(-0.25, m.turnRateRadS, 0.0);
    DOUBLES_EQUAL(4.0, m.durationS, 0.0);
    CHECK_EQUAL(3 * core::kNsPerSec, m.timeNs);
    mode.setEstop(true);
    const cmdtlm::CommandOutcome o = drive(0.5F, 0.0F, 1.0F);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(0, o.detail);  // clear the e-stop first
    LONGS_EQUAL(0, drives.drain());
}

TEST(MobilityCommands, ResetInterlockAsksCanIo) {
    CHECK_TRUE(execute(CommandCode::RESET_INTERLOCK).ok);
    LONGS_EQUAL(1, resets.drain());
}

TEST(MobilityCommands, ACommandOfAnotherApidIsNotItsToCarryOut) {
    const cmdtlm::CommandOutcome o = execute(CommandCode::NOOP);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(-1, o.detail);
}
