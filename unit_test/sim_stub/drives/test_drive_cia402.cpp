// CiA 402 drive emulator: power state machine, PDO cycle, motor model, EMCY and
// fault handling (docs/icd.md §1.4).
#include <cmath>

#include "unit_test/sim_stub/drives/drive_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::sim::PowerState;
using rse::test::Captured;
using rse::test::DriveRig;
using rse::test::kCycle;
using rse::test::kNode;
using rse::test::Tpdo;

namespace {

constexpr std::uint32_t kEmcy = 0x080 + kNode;

std::uint16_t emcyCode(const hal::CanFrame& f) { return static_cast<std::uint16_t>(f.data[0] | (f.data[1] << 8)); }

void checkEmcy(const hal::CanFrame& f, std::uint16_t code, std::uint8_t errorRegister) {
    LONGS_EQUAL(kEmcy, f.id);
    LONGS_EQUAL(8, f.dlc);
    LONGS_EQUAL(code, emcyCode(f));
    LONGS_EQUAL(errorRegister, f.data[2]);
    for (int i = 3; i < 8; ++i) {
        LONGS_EQUAL(0, f.data[i]);
    }
}

}  // namespace

TEST_GROUP(DriveCia402) {
    DriveRig rig;
};

TEST(DriveCia402, PowerStateWalkWithExactStatuswords) {
    rig.configureAndStart();
    Tpdo t = rig.cycle(0x0000, 0);
    CHECK(t.present);
    LONGS_EQUAL(0x0240, t.statusword);  // switch on disabled + remote
    LONGS_EQUAL(0x0040, t.statusword & 0x004F);
    t = rig.cycle(0x0006, 0);  // shutdown
    LONGS_EQUAL(0x0221, t.statusword);
    LONGS_EQUAL(0x0021, t.statusword & 0x006F);
    t = rig.cycle(0x0007, 0);  // switch on
    LONGS_EQUAL(0x0233, t.statusword);
    LONGS_EQUAL(0x0023, t.statusword & 0x006F);
    t = rig.cycle(0x000F, 0);  // enable operation: at rest, target 0 reached, speed = 0
    LONGS_EQUAL(0x1637, t.statusword);
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);
    CHECK(PowerState::kOperationEnabled == rig.drive.powerState());

    t = rig.cycle(0x0007, 0);  // disable operation
    LONGS_EQUAL(0x0233, t.statusword);
    t = rig.cycle(0x000F, 0);
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);
    t = rig.cycle(0x000B, 0);  // quick stop
    LONGS_EQUAL(0x1617, t.statusword);
    LONGS_EQUAL(0x0007, t.statusword & 0x006F);
    t = rig.cycle(0x000B, 0);  // stays in quick stop active
    CHECK(PowerState::kQuickStopActive == rig.drive.powerState());
    t = rig.cycle(0x0000, 0);  // disable voltage
    LONGS_EQUAL(0x0240, t.statusword);

    // From ready to switch on, "switch on + enable operation" does transitions 3 and 4 at once.
    (void)rig.cycle(0x0006, 0);
    t = rig.cycle(0x000F, 0);
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);
    // Enable operation from switch on disabled does nothing (a shutdown must come first).
    (void)rig.cycle(0x0000, 0);
    t = rig.cycle(0x000F, 0);
    LONGS_EQUAL(0x0240, t.statusword);
    LONGS_EQUAL(rig.drive.stats().syncs, rig.drive.stats().tpdoSent);
}

TEST(DriveCia402, VelocityTracksTheTargetAndCurrentScalesWithDegradation) {
    rig.enable();
    Tpdo t;
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    CHECK(t.present);
    CHECK(t.velocity >= 990 && t.velocity <= 1010);
    CHECK((t.statusword & 0x0400) != 0);  // target reached
    CHECK((t.statusword & 0x1000) == 0);  // speed not 0
    DOUBLES_EQUAL(1.0, rig.drive.wheelSpeedRadS(), 0.01);
    // Steady speed: no-load 150 mA + 2000 mA/N m x 0.3 N m rolling resistance.
    CHECK(t.current > 700 && t.current < 800);
    const double nominal = t.current;

    rig.drive.setDegradation(1.5);
    t = rig.cycle(0x000F, 1000);
    DOUBLES_EQUAL(1.5, t.current / nominal, 0.01);
    CHECK(t.velocity >= 990 && t.velocity <= 1010);  // same work, more current

    // Reverse: the speed follows, the current is a magnitude.
    rig.drive.setDegradation(1.0);
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x000F, -1000);
    }
    CHECK(t.velocity <= -990 && t.velocity >= -1010);
    CHECK(t.current > 700 && t.current < 800);
    LONGS_EQUAL(-1000, static_cast<std::int32_t>(rig.uploadValue(0x60FF, 0)));
    CHECK(static_cast<std::int32_t>(rig.uploadValue(0x606C, 0)) <= -990);
}

TEST(DriveCia402, FirstOrderLagAndAccelerationCurrent) {
    rig.enable();
    Tpdo t = rig.cycle(0x000F, 1000);
    // The target is applied at this SYNC: nothing has moved yet.
    LONGS_EQUAL(0, t.velocity);
    t = rig.cycle(0x000F, 1000);
    // One 10 ms step of a 50 ms lag: 1000 (1 - e^-0.2) = 181 mrad/s.
    CHECK(std::abs(t.velocity - 181) <= 1);
    // Accelerating: more than the steady 750 mA.
    CHECK(t.current > 800);
    for (int i = 0; i < 4; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    // One time constant after: 1 - e^-1 of the way (632 mrad/s).
    CHECK(std::abs(t.velocity - 632) <= 1);
}

TEST(DriveCia402, SpeedLimitAndInternalLimitBit) {
    rig.enable();
    Tpdo t;
    for (int i = 0; i < 150; ++i) {
        t = rig.cycle(0x000F, 9000);
    }
    LONGS_EQUAL(5000, t.velocity);
    CHECK((t.statusword & 0x0800) != 0);
    CHECK((t.statusword & 0x0400) != 0);  // reached what it may reach
    t = rig.cycle(0x000F, 4000);
    CHECK((t.statusword & 0x0800) == 0);
}

TEST(DriveCia402, NoModeSetNoMotion) {
    rig.boot();  // 0x6060 never written: no mode of operation
    rig.nmt(0x01, kNode);
    rig.step();
    (void)rig.cycle(0x0006, 0);
    (void)rig.cycle(0x0007, 0);
    Tpdo t;
    for (int i = 0; i < 50; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);
    LONGS_EQUAL(0, t.velocity);
}

TEST(DriveCia402, WheelCoastsWhenDisabledAndOnLeavingOperational) {
    rig.enable();
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 2000);
    }
    CHECK(rig.drive.wheelSpeedRadS() > 1.9);
    Tpdo t = rig.cycle(0x0007, 2000);  // disable operation: power stage off, wheel coasts
    t = rig.cycle(0x0007, 2000);
    LONGS_EQUAL(0, t.current);
    CHECK(t.velocity < 2000 && t.velocity > 0);
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x0007, 2000);
    }
    LONGS_EQUAL(0, t.velocity);

    // NMT stop while operation enabled: "disable voltage" (0x6007 = 2), wheel coasts to 0.
    (void)rig.cycle(0x000F, 2000);
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 2000);
    }
    rig.nmt(0x02, kNode);
    rig.advance(kCycle);
    CHECK(PowerState::kSwitchOnDisabled == rig.drive.powerState());
    rig.idle(core::kNsPerSec);
    DOUBLES_EQUAL(0.0, rig.drive.wheelSpeedRadS(), 0.001);
    hal::CanFrame f;
    rig.sync();
    rig.step();
    CHECK_FALSE(rig.receiveId(0x185, &f));  // no PDOs in stopped
}

TEST(DriveCia402, TpdoEveryNthSyncWithTransmissionType) {
    rig.enable();
    hal::CanFrame r;
    CHECK(rig.sdoDownload(0x1800, 2, 3, 1, &r));
    unsigned tpdos = 0;
    for (int i = 0; i < 9; ++i) {
        tpdos += rig.cycle(0x000F, 0).present ? 1U : 0U;
    }
    LONGS_EQUAL(3, tpdos);
}

TEST(DriveCia402, FailedMotorFaultsAndStaysFaulted) {
    rig.enable();
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 1000);
    }
    rig.drive.failMotor();
    Captured c = rig.cycleAll(0x000F, 1000);
    hal::CanFrame f;
    CHECK(c.find(kEmcy, &f));
    checkEmcy(f, 0x5000, 0x01);
    CHECK(c.find(0x185, &f));
    Tpdo t = DriveRig::decodeTpdo(f);
    LONGS_EQUAL(0x000F, t.statusword & 0x004F);  // fault reaction active
    LONGS_EQUAL(0, t.current);                     // no torque
    t = rig.cycle(0x0000, 0);
    LONGS_EQUAL(0x0208, t.statusword);  // fault + remote
    LONGS_EQUAL(0x0008, t.statusword & 0x004F);
    LONGS_EQUAL(0x01, rig.uploadValue(0x1001, 0));
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x0000, 0);
    }
    LONGS_EQUAL(0, t.velocity);

    // Fault reset (0x0000 then the rising edge 0x0080), three times: refused every time.
    for (int attempt = 0; attempt < 3; ++attempt) {
        (void)rig.cycle(0x0000, 0);
        c = rig.cycleAll(0x0080, 0);
        LONGS_EQUAL(0, c.countId(kEmcy));
        CHECK(c.find(0x185, &f));
        LONGS_EQUAL(0x0008, DriveRig::decodeTpdo(f).statusword & 0x004F);
    }
    LONGS_EQUAL(3, rig.drive.stats().faultResetsRefused);
    LONGS_EQUAL(0, rig.drive.stats().faultResets);
    CHECK(PowerState::kFault == rig.drive.powerState());

    // Commands are no use either.
    for (int i = 0; i < 20; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    LONGS_EQUAL(0, t.velocity);

    // Not even a reset node: the motor is still broken, the drive faults again on boot.
    rig.nmt(0x81, kNode);
    rig.step();
    rig.advance(kCycle);  // the self-test after boot finds the motor still broken
    c = rig.capture();
    CHECK(c.find(0x705, &f));
    CHECK(c.find(kEmcy, &f));
    checkEmcy(f, 0x5000, 0x01);
}

TEST(DriveCia402, OverCurrentFaultClearsWithFaultReset) {
    rig.enable();
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 1000);
    }
    rig.drive.setLoadTorque(2.0);  // 150 + 4000 mA > 3000 mA limit
    Tpdo t = rig.cycle(0x000F, 1000);
    CHECK(t.current > 3000);
    CHECK((t.statusword & 0x0080) != 0);  // warning: over the limit, trip timer running
    LONGS_EQUAL(0x0027, t.statusword & 0x006F);
    Captured c;
    hal::CanFrame f;
    int cycles = 1;
    for (; cycles < 30; ++cycles) {
        c = rig.cycleAll(0x000F, 1000);
        if (c.find(kEmcy, &f)) {
            break;
        }
    }
    // More than 100 ms above the limit, not much more.
    CHECK(cycles >= 10 && cycles <= 12);
    checkEmcy(f, 0x2310, 0x03);
    CHECK(c.find(0x185, &f));
    LONGS_EQUAL(0x000F, DriveRig::decodeTpdo(f).statusword & 0x004F);
    t = rig.cycle(0x0000, 0);
    LONGS_EQUAL(0x0008, t.statusword & 0x004F);
    LONGS_EQUAL(0x2310, rig.drive.lastEmcyCode());

    // The load is gone; a fault reset clears it with EMCY 0x0000 and register 0.
    rig.drive.setLoadTorque(0.3);
    c = rig.cycleAll(0x0080, 0);
    CHECK(c.find(kEmcy, &f));
    checkEmcy(f, 0x0000, 0x00);
    CHECK(c.find(0x185, &f));
    LONGS_EQUAL(0x0240, DriveRig::decodeTpdo(f).statusword);
    LONGS_EQUAL(1, rig.drive.stats().faultResets);
    LONGS_EQUAL(0, rig.uploadValue(0x1001, 0));

    // And it drives again.
    (void)rig.cycle(0x0006, 0);
    (void)rig.cycle(0x0007, 0);
    for (int i = 0; i < 100; ++i) {
        t = rig.cycle(0x000F, 1000);
    }
    CHECK(t.velocity >= 990 && t.velocity <= 1010);
    LONGS_EQUAL(1, rig.drive.stats().faults);
}

// A wheel slipping under a blocked rover: the block's share of the load
// draws current while the drive pushes, none once it is told to stop (the
// slip's friction stops the wheel); an ordinary load is drawn either way.
TEST(DriveCia402, TheBlockShareOfTheLoadIsDrawnOnlyWhilePushing) {
    rig.enable();
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 2500);
    }
    rig.drive.setLoadTorque(0.6 + 3.1);  // rolling plus a blocked rover's slide friction
    rig.drive.setBlockTorque(3.1);
    Tpdo t = rig.cycle(0x000F, 2500);
    CHECK(t.current > 7000);  // pushing: 150 + 2000 x 3.7 mA
    (void)rig.cycle(0x000F, 0);  // told to stop (the TPDO of this cycle still shows the push)
    t = rig.cycle(0x000F, 0);    // braking
    CHECK(t.velocity > 100);     // still turning (the lag)...
    CHECK(t.current < 3000);     // ...but not pushing: under the trip
    for (int i = 0; i < 9; ++i) {
        t = rig.cycle(0x000F, 0);
        CHECK(t.current < 3000);
    }
    LONGS_EQUAL(0, rig.drive.stats().faults);  // no over-current trip
    // An ordinary load (no block share) is drawn while braking too.
    rig.drive.setLoadTorque(1.2);
    rig.drive.setBlockTorque(0.0);
    for (int i = 0; i < 50; ++i) {
        (void)rig.cycle(0x000F, 2500);
    }
    (void)rig.cycle(0x000F, 0);
    t = rig.cycle(0x000F, 0);
    CHECK(t.current >= 2550);  // 150 + 2000 x 1.2 mA, and the deceleration's
    LONGS_EQUAL(0, rig.drive.stats().faults);
}

TEST(DriveCia402, InjectedFaultCarriesItsCodeAndRegisterBits) {
    rig.enable();
    rig.drive.injectFault(0x4310);  // over-temperature
    Captured c = rig.cycleAll(0x000F, 0);
    hal::CanFrame f;
    CHECK(c.find(kEmcy, &f));
    checkEmcy(f, 0x4310, 0x09);  // generic + temperature
    (void)rig.cycle(0x0000, 0);
    // Fault reset needs a rising edge: holding bit 7 does nothing more.
    c = rig.cycleAll(0x0080, 0);
    CHECK(c.find(kEmcy, &f));
    checkEmcy(f, 0x0000, 0x00);
    c = rig.cycleAll(0x0080, 0);
    LONGS_EQUAL(0, c.countId(kEmcy));
    CHECK(PowerState::kSwitchOnDisabled == rig.drive.powerState());
}

TEST(DriveCia402, NoEmcyInStoppedButTheFaultIsThere) {
    rig.enable();
    rig.nmt(0x02, kNode);
    rig.advance(kCycle);
    rig.drain();
    rig.drive.injectFault(0x3210);
    rig.advance(kCycle);
    hal::CanFrame f;
    CHECK_FALSE(rig.receiveId(kEmcy, &f));
    LONGS_EQUAL(1, rig.drive.stats().emcySuppressed);
    rig.advance(kCycle);
    CHECK(PowerState::kFault == rig.drive.powerState());
    rig.nmt(0x80, kNode);
    rig.step();
    LONGS_EQUAL(0x05, rig.uploadValue(0x1001, 0));  // generic + voltage
}
