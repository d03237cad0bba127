// The mobility commands (APID 0x182): the e-stop through the mode owner, a
// manual drive (refused while the e-stop holds), an interlock reset request.
#include "fsw/reflexive/mobility_commands.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "unit_test/support/app_test_support.hpp"

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

TEST(MobilityCommands, TheEstopIsTheModeOwnersAndIsAnnounced) {
    CHECK_TRUE(execute(CommandCode::ESTOP_SET).ok);
    CHECK_TRUE(mode.estop());
    msg::ModeMsg m{};
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(1, m.estop);
    CHECK_TRUE(execute(CommandCode::ESTOP_CLEAR).ok);
    CHECK_FALSE(mode.estop());
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
