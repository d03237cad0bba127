// Lockstep: the flight software drives the simulated rover over CAN.
#include <cmath>
#include <cstdio>

#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

// Wheel odometry as the flight software sees it: integrate the drives' published
// velocity actuals (skid-steer, straight line: v = r * mean wheel speed).
double g_odometryM = 0.0;
constexpr double kWheelRadiusM = 0.10;  // rover geometry (a table once tables exist)

void integrateOdometry(sim::LockstepRig& rig) {
    double sum = 0.0;
    for (const msg::WheelStatus& w : rig.driveStatus().wheels) {
        sum += w.velocityRadS;
    }
    g_odometryM += kWheelRadiusM * (sum / msg::kWheelCount) * 0.010;
}

}  // namespace

TEST_GROUP(LockstepDrive) {
    sim::LockstepRig* rig = nullptr;
    void setup() override {
        g_odometryM = 0.0;
        rig = new sim::LockstepRig("sim_stub/scenarios/straight_10m.toml");
        CHECK(core::Status::kOk == rig->init());
    }
    void teardown() override { delete rig; }
};

TEST(LockstepDrive, AllSixDrivesBootConfigureAndEnable) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    CHECK(rig->clock().now() < 1 * kNsPerSec);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        CHECK(sim::PowerState::kOperationEnabled == rig->drives().drive(w).powerState());
        LONGS_EQUAL(3, rig->drives().drive(w).modeOfOperation());
        LONGS_EQUAL(100, rig->drives().drive(w).heartbeatPeriodMs());
        // Once after power-on and once after the master's start-up reset of communication.
        CHECK(rig->fsw().canIo().drive(w).stats().configAttempts <= 2);
        LONGS_EQUAL(0, rig->fsw().canIo().drive(w).stats().configFailures);
    }
}

TEST(LockstepDrive, StraightTenMetresOdometryMatchesTruth) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    rig->setOnFrame(integrateOdometry);
    const double startX = rig->rover().truth().pose.x;
    rig->commandAllWheels(2.0);  // 0.2 m/s
    CHECK_TRUE(rig->runUntil([] { return g_odometryM >= 10.0; }, 80 * kNsPerSec));
    rig->commandAllWheels(0.0);
    rig->runFor(1 * kNsPerSec);  // coast to a stop (50 ms time constant)
    const double truthDistance = rig->rover().truth().pose.x - startX;
    char figures[160];
    std::snprintf(figures, sizeof figures, "straight 10 m: odometry %.4f m, truth %.4f m, error %.2f mm",
                  g_odometryM, truthDistance, 1000.0 * (g_odometryM - truthDistance));
    UT_PRINT(figures);
    // Stated tolerance: odometry within 1 cm (0.1 %) of the true distance on flat
    // ground without slip; the rover stops within 2 cm of 10 m; heading stays put.
    DOUBLES_EQUAL(truthDistance, g_odometryM, 0.01);
    DOUBLES_EQUAL(10.0, truthDistance, 0.02);
    DOUBLES_EQUAL(0.0, rig->rover().truth().pose.y, 1e-6);
    DOUBLES_EQUAL(0.0, rig->rover().truth().pose.theta, 1e-6);
    LONGS_EQUAL(0, rig->rover().truth().collisions);
}

TEST(LockstepDrive, MotorFailureIsReportedAndEveryOtherWheelIsStopped) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    rig->commandAllWheels(2.0);
    rig->runFor(2 * kNsPerSec);
    DOUBLES_EQUAL(2.0, rig->drives().drive(0).wheelSpeedRadS(), 0.01);
    LONGS_EQUAL(0, rig->consoleCount("EVT 601 "));

    const core::TimeNs injectedAt = rig->clock().now();
    rig->rover().failMotor(1);  // middle-left
    // EMCY -> drive faulted -> interlock: every wheel commanded to zero within 3 frames.
    CHECK_TRUE(rig->runUntil([&] { return rig->fsw().canIo().interlock().tripped(); }, 100 * kNsPerMs));
    rig->runFor(20 * kNsPerMs);
    CHECK(rig->clock().now() - injectedAt <= 50 * kNsPerMs);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (w != 1) {
            LONGS_EQUAL(0, rig->drives().drive(w).targetVelocityMradS());
        }
    }
    LONGS_EQUAL(0x5000, rig->fsw().canIo().drive(1).lastEmcyCode());
    // Three fault resets are refused: the drive is declared failed.
    CHECK_TRUE(rig->runUntil([&] { return rig->fsw().canIo().drive(1).state() == hal::DriveState::kFailed; },
                             1 * kNsPerSec));
    rig->runFor(1 * kNsPerSec);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        DOUBLES_EQUAL(0.0, rig->drives().drive(w).wheelSpeedRadS(), 0.01);
    }
    CHECK(msg::DriveHealth::kFailed == rig->driveStatus().wheels[1].health);
    LONGS_EQUAL(1, rig->driveStatus().interlockTripped);
    LONGS_EQUAL(1, rig->consoleCount("EVT 601 CRIT  reflexive: wheel 1 drive unhealthy"));  // interlock
    // Fault protection then asks for another round of resets (and node resets
    // after it), so the "still faulted" report may come more than once.
    CHECK(rig->consoleCount("EVT 434 CRIT  drive ML (node 2): still faulted after 3 resets (EMCY 0x5000)") >= 1);
    LONGS_EQUAL(1, rig->consoleCount("EVT 406 ERROR drive ML (node 2): EMCY 0x5000"));
    // RESET_INTERLOCK (its bus message, as the mobility commands publish it) is
    // refused while the failed drive stays unhealthy: the hold stays.
    msg::InterlockResetMsg reset{};
    CHECK(core::isOk(rig->fsw().bus().publish(reset)));
    rig->runFor(200 * kNsPerMs);
    CHECK_TRUE(rig->fsw().canIo().interlock().tripped());
    LONGS_EQUAL(1, rig->consoleCount("EVT 606 WARN  reflexive: interlock reset refused: wheel 1 drive still unhealthy"));
}

TEST(LockstepDrive, CrashedDriveIsLostThenReconfiguredAfterItsRestart) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    const core::TimeNs crashedAt = rig->clock().now();
    rig->rover().crashDrive(4);
    CHECK_TRUE(rig->runUntil([&] { return rig->fsw().canIo().drive(4).state() == hal::DriveState::kLost; },
                             1 * kNsPerSec));
    // Heartbeat period 100 ms, consumer timeout 250 ms: detected within 360 ms
    // (up to one period since the last beat, plus the timeout, plus one frame).
    CHECK(rig->clock().now() - crashedAt <= 360 * kNsPerMs);
    rig->runFor(10 * kNsPerMs);  // the interlock acts on the status of the frame before
    CHECK(rig->fsw().canIo().interlock().tripped());
    rig->runFor(100 * kNsPerMs);  // the console writes events out at 10 Hz
    LONGS_EQUAL(1, rig->consoleCount("EVT 402 ERROR canopen: node 5 lost"));
    LONGS_EQUAL(1, rig->consoleCount("EVT 436 ERROR drive MR (node 5): lost"));
    const std::uint32_t attemptsBefore = rig->fsw().canIo().drive(4).stats().configAttempts;
    rig->rover().restartDrive(4);
    CHECK_TRUE(rig->runUntil([&] { return rig->fsw().canIo().drive(4).state() == hal::DriveState::kOperational; },
                             2 * kNsPerSec));
    LONGS_EQUAL(attemptsBefore + 1, rig->fsw().canIo().drive(4).stats().configAttempts);
    LONGS_EQUAL(1, rig->fsw().canIo().drive(4).stats().losses);
}

TEST(LockstepDrive, NoHeapAllocationAcrossTenThousandFramesOfFlightAndSimulator) {
    rse::test::AllocationWatch watch;
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    rig->commandAllWheels(1.0);
    rig->runFor(100 * kNsPerSec - rig->clock().now());  // 10 000 frames in all
    const auto allocations = watch.count();
    LONGS_EQUAL(0, allocations);
    CHECK(rig->fsw().executive().stats().framesRun >= 10000);
    CHECK(rig->rover().truth().pose.x > 9.0);  // it really drove
}

TEST(LockstepDrive, HostileWheelCommandsAreRefusedAndThePreviousOneKept) {
    CHECK_TRUE(rig->runUntil([&] { return rig->allDrivesOperational(); }, 2 * kNsPerSec));
    rig->commandAllWheels(1.0);
    rig->runFor(500 * kNsPerMs);
    const std::uint8_t truncated[8] = {};
    CHECK(core::Status::kOk == rig->fsw().bus().publish(msg::ids::kWheelCommand, truncated, sizeof truncated));
    rig->commandAllWheels(std::nan(""));
    rig->commandAllWheels(99.0);  // beyond the drives' 5 rad/s
    rig->runFor(500 * kNsPerMs);
    // The truncated one does not decode: refused by CAN I/O's input pipe
    // (counted apart, event 211); the other two by their content (event 204).
    LONGS_EQUAL(1, rig->fsw().canIo().malformed());
    LONGS_EQUAL(2, rig->fsw().canIo().commandsRejected());
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(1000, rig->drives().drive(w).targetVelocityMradS());
    }
    // Each count evented on its 1st, 2nd, 4th ... occurrence.
    LONGS_EQUAL(1, rig->consoleCount("EVT 211 ERROR can_io: bus message 0x"));
    LONGS_EQUAL(2, rig->consoleCount("EVT 204 ERROR app: wheel command refused: wheel speed not finite"));
    LONGS_EQUAL(2, rig->consoleCount("EVT 204 "));
}
