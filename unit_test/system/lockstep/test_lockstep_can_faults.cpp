// Lockstep: CAN-side faults injected by the simulator's scenario (never by
// touching flight state) and what the flight software makes of them: a drive
// that never boots, a motor that overheats.
#include <fstream>
#include <memory>
#include <sstream>
#include <string>

#include "fsw/msg/health_msgs.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::kNsPerMs;
using core::kNsPerSec;

namespace {

// straight_10m with extra scenario text (faults, rover node ids, drives).
sim::Scenario straightWith(const std::string& extra) {
    std::ifstream in("sim_stub/scenarios/straight_10m.toml");
    std::stringstream text;
    text << in.rdbuf();
    return sim::parseScenario(text.str() + "\n" + extra, "straight_10m+test.toml");
}

}  // namespace

TEST_GROUP(LockstepCanFaults) {};

// The simulated rover's rear-right drive answers at node 9, where the flight
// node map (shipped CAN_NODE_MAP) expects node 6: to the flight software that
// drive never boots.
TEST(LockstepCanFaults, ADriveThatNeverBootsIsReportedLostAndRaisesItsHeartbeatFault) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(straightWith("[rover]\ndrive_nodes = [1, 2, 3, 4, 5, 9]\n"));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    const std::uint8_t rr = msg::fault::kDriveHeartbeatLost + 5;
    rig.runFor(2900 * kNsPerMs);
    CHECK_FALSE(rig.fsw().health().active(rr));
    for (std::size_t w = 0; w + 1 < msg::kWheelCount; ++w) {
        CHECK(rig.fsw().canIo().drive(w).state() == hal::DriveState::kOperational);
    }
    CHECK_TRUE(rig.runUntil([&] { return rig.fsw().health().active(rr); }, 200 * kNsPerMs));
    CHECK(rig.clock().now() <= 3050 * kNsPerMs);  // drive_boot_timeout_ms 3000 + a frame or two
    CHECK(rig.fsw().canIo().drive(5).state() == hal::DriveState::kLost);
    LONGS_EQUAL(1, rig.consoleCount("EVT 407 "));
    for (std::size_t w = 0; w + 1 < msg::kWheelCount; ++w) {
        CHECK_FALSE(rig.fsw().health().active(static_cast<std::uint8_t>(msg::fault::kDriveHeartbeatLost + w)));
    }
}

TEST(LockstepCanFaults, AnOverheatingMotorRaisesOnlyItsOverTemperatureFault) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(straightWith("[[faults]]\ntype = \"motor_overheat\"\nat_s = 1.0\nwheel = 2\nheat_factor = 20\n"));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return rig.allDrivesOperational(); }, 2 * kNsPerSec));
    rig.commandAllWheels(2.0);
    const std::uint8_t ml = msg::fault::kDriveOvertemp + 1;
    CHECK_TRUE(rig.runUntil([&] { return rig.fsw().health().active(ml); }, 40 * kNsPerSec));
    const msg::WheelStatus& hot = rig.driveStatus().wheels[1];
    CHECK(hot.temperatureValid == 1);
    CHECK(hot.temperatureC > 80.0F);
    DOUBLES_EQUAL(rig.drives().drive(1).temperatureC(), static_cast<double>(hot.temperatureC), 1.0);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (w != 1) {
            CHECK_FALSE(rig.fsw().health().active(static_cast<std::uint8_t>(msg::fault::kDriveOvertemp + w)));
            CHECK(rig.driveStatus().wheels[w].temperatureC < 50.0F);
        }
    }
    char figures[120];
    std::snprintf(figures, sizeof figures, "overheat x20 from 1.0 s: fault raised at %.2f s, motor %.1f degC",
                  static_cast<double>(rig.clock().now()) / 1e9, static_cast<double>(hot.temperatureC));
    UT_PRINT(figures);
    rig.runFor(200 * kNsPerMs);  // the console writes events at 10 Hz
    LONGS_EQUAL(1, rig.consoleCount("EVT 736 "));
    // Stopped, it cools below 65 degC and the fault clears.
    rig.commandAllWheels(0.0);
    CHECK_TRUE(rig.runUntil([&] { return !rig.fsw().health().active(ml); }, 120 * kNsPerSec));
    rig.runFor(200 * kNsPerMs);
    LONGS_EQUAL(1, rig.consoleCount("EVT 737 "));
}

TEST(LockstepCanFaults, ANominalDriveRaisesNoOverTemperatureFault) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(straightWith(""));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return rig.allDrivesOperational(); }, 2 * kNsPerSec));
    rig.commandAllWheels(2.0);
    rig.runFor(60 * kNsPerSec);
    LONGS_EQUAL(0, rig.consoleCount("EVT 736 "));
    // Margin: a drive in straight driving settles about 23 degC above the 20 degC
    // ambient (one thermal time constant in: 63 % of that), far below 80 degC.
    for (const msg::WheelStatus& w : rig.driveStatus().wheels) {
        CHECK(w.temperatureC < 40.0F);
    }
    char figures[120];
    std::snprintf(figures, sizeof figures, "nominal 60 s at 2 rad/s: motor FL %.1f degC at %.2f A",
                  static_cast<double>(rig.driveStatus().wheels[0].temperatureC), rig.driveStatus().wheels[0].currentA);
    UT_PRINT(figures);
}

// The defect found against an independent CANopen device: an EMCY while the
// master configures a drive (pre-operational, where RPDOs are ignored) used
// to end in "failed" for good. Here one drive faults with its boot-up and
// another in the middle of its configuration.
TEST(LockstepCanFaults, AFaultWhileADriveIsConfiguredIsResetBySdoAndItComesUp) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(straightWith("[[faults]]\ntype = \"drive_fault\"\nat_s = 0.0\nwheel = 4\n"
                                      "[[faults]]\ntype = \"drive_fault\"\nat_s = 0.04\nwheel = 2\nemcy_code = 0x3210\n"));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return rig.allDrivesOperational(); }, 3 * kNsPerSec));
    for (const std::size_t w : {1U, 3U}) {
        const hal::WheelDrive& d = rig.fsw().canIo().drive(w);
        CHECK(d.stats().faults >= 1);
        CHECK(d.stats().sdoFaultResets >= 1);
        LONGS_EQUAL(0, d.stats().configFailures);
        LONGS_EQUAL(1, rig.drives().drive(w).stats().faultResets);
    }
    char figures[120];
    std::snprintf(figures, sizeof figures, "faults during configuration: all six drives operational at %.2f s",
                  static_cast<double>(rig.clock().now()) / 1e9);
    UT_PRINT(figures);
}

TEST(LockstepCanFaults, AFaultWhileDrivingIsResetByRpdoAndTheDriveComesBack) {
    // On the heap: FswApp alone is some 9 MB, more than a thread's stack.
    const auto rigHolder = std::make_unique<sim::LockstepRig>(straightWith("[[faults]]\ntype = \"drive_fault\"\nat_s = 3.0\nwheel = 6\n"));
    sim::LockstepRig& rig = *rigHolder;
    CHECK(core::Status::kOk == rig.init());
    CHECK_TRUE(rig.runUntil([&] { return rig.allDrivesOperational(); }, 2 * kNsPerSec));
    rig.commandAllWheels(2.0);
    CHECK_TRUE(rig.runUntil([&] { return rig.fsw().canIo().drive(5).stats().faults == 1; }, 4 * kNsPerSec));
    CHECK(rig.clock().now() >= 3 * kNsPerSec);
    CHECK_TRUE(rig.runUntil([&] { return rig.allDrivesOperational(); }, 2 * kNsPerSec));
    const hal::WheelDrive& d = rig.fsw().canIo().drive(5);
    LONGS_EQUAL(0, d.stats().sdoFaultResets);
    CHECK(d.stats().faultResets >= 1);
    LONGS_EQUAL(1, rig.drives().drive(5).stats().faultResets);
    CHECK_TRUE(rig.fsw().canIo().interlock().tripped());  // latched until fault protection or ground resets it
}
