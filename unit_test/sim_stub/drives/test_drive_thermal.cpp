// The drive emulator's motor temperature: heats with I^2, cools to ambient,
// the overheat factor raises the heat gain, and TPDO2 reports it at 10 Hz.
#include <cmath>

#include "unit_test/sim_stub/drives/drive_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::DriveRig;
using test::kCycle;
using test::kNode;

namespace {

// Drives the wheel at `mradS` for `duration` (one master cycle per 10 ms);
// returns how many TPDO2 frames came and the last temperature they carried.
struct Tpdo2Seen {
    unsigned frames = 0;
    double lastC = NAN;
    bool allDlc2 = true;
};
Tpdo2Seen driveFor(DriveRig& rig, std::int32_t mradS, core::TimeNs duration) {
    Tpdo2Seen seen;
    for (core::TimeNs t = 0; t < duration; t += kCycle) {
        const test::Captured c = rig.cycleAll(0x000F, mradS);
        for (std::size_t i = 0; i < c.count; ++i) {
            if (c.frames[i].id == 0x280U + kNode) {
                ++seen.frames;
                seen.allDlc2 = seen.allDlc2 && c.frames[i].dlc == 2;
                seen.lastC = 0.1 * static_cast<double>(static_cast<std::int16_t>(c.frames[i].data[0] |
                                                                                  (c.frames[i].data[1] << 8)));
            }
        }
    }
    return seen;
}

}  // namespace

TEST_GROUP(DriveThermal) {};

TEST(DriveThermal, HeatsWithCurrentCoolsToAmbientAndReportsAtTenHertz) {
    DriveRig rig;
    rig.drive.setAmbientTemperature(-30.0);
    rig.enable();
    DOUBLES_EQUAL(-30.0, rig.drive.temperatureC(), 0.01);
    const Tpdo2Seen seen = driveFor(rig, 2000, 60 * core::kNsPerSec);
    LONGS_EQUAL(600, seen.frames);
    CHECK_TRUE(seen.allDlc2);
    // 750 mA steady: 0.2 x 0.75^2 x 60 s = 6.75 degC above ambient at equilibrium,
    // 63 % of it after one time constant.
    const double rise = rig.drive.temperatureC() + 30.0;
    CHECK(rise > 0.55 * 6.75 && rise < 0.75 * 6.75);
    DOUBLES_EQUAL(rig.drive.temperatureC(), seen.lastC, 0.1);
    // Torque off: it cools back towards ambient.
    const double hot = rig.drive.temperatureC();
    (void)driveFor(rig, 0, 1 * core::kNsPerSec);
    rig.nmt(0x02, kNode);  // stopped: no current, no TPDO2
    rig.idle(120 * core::kNsPerSec);
    CHECK(rig.drive.temperatureC() < hot - 0.8 * rise);
    CHECK(rig.drive.temperatureC() > -30.0);
}

TEST(DriveThermal, TheOverheatFactorRaisesTheHeatGain) {
    DriveRig nominal;
    DriveRig overheated;
    overheated.drive.setOverheat(10.0);
    overheated.drive.setOverheat(-1.0);  // ignored
    overheated.drive.setOverheat(NAN);   // ignored
    DOUBLES_EQUAL(10.0, overheated.drive.overheat(), 0.0);
    nominal.enable();
    overheated.enable();
    (void)driveFor(nominal, 2000, 10 * core::kNsPerSec);
    (void)driveFor(overheated, 2000, 10 * core::kNsPerSec);
    const double riseNominal = nominal.drive.temperatureC() - 20.0;
    const double riseOverheated = overheated.drive.temperatureC() - 20.0;
    CHECK(riseNominal > 0.0);
    DOUBLES_EQUAL(10.0, riseOverheated / riseNominal, 0.5);
}

TEST(DriveThermal, NoTpdo2OutsideOperational) {
    DriveRig rig;
    rig.configureAndStart();
    rig.nmt(0x80, kNode);  // back to pre-operational
    for (int i = 0; i < 50; ++i) {
        rig.sync();
        rig.advance(kCycle);
    }
    LONGS_EQUAL(0, rig.drive.stats().tpdo2Sent);
}
