#include <cmath>

#include "hal/canopen/le_codec.hpp"
#include "hal/devices/device_events.hpp"
#include "hal/devices/hazard_detector.hpp"
#include "hal/devices/imu.hpp"
#include "hal/devices/position_fix.hpp"
#include "hal/devices/power_monitor.hpp"
#include "hal/devices/rse_device_ids.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;

namespace {
CanFrame frame8(std::uint32_t id) {
    CanFrame f;
    f.id = id;
    f.dlc = 8;
    return f;
}
}  // namespace

TEST_GROUP(RseDevices) {
    core::VirtualClock clock;
    core::EventLog events{clock};
};

TEST(RseDevices, ImuDecodesYawRateAndCountsGaps) {
    Imu imu(events);
    CanFrame f = frame8(device_ids::kImuRates);
    le::putI32(&f.data[0], -1500000);  // -1.5 rad/s
    le::putU16(&f.data[4], 10);
    f.data[6] = 0x01;
    imu.onFrame(f, 100);
    DOUBLES_EQUAL(-1.5, imu.latest().yawRateRadS, 1e-12);
    CHECK_TRUE(imu.latest().valid);
    le::putU16(&f.data[4], 13);  // 11 and 12 missed
    imu.onFrame(f, 200);
    LONGS_EQUAL(2, imu.frameStats().gaps);
    LONGS_EQUAL(2, imu.frameStats().accepted);
}

TEST(RseDevices, HostileFramesAreRejectedCountedEventedAndTheLastGoodSampleKept) {
    Imu imu(events);
    CanFrame good = frame8(device_ids::kImuRates);
    le::putI32(&good.data[0], 250000);
    imu.onFrame(good, 1);
    CanFrame shortFrame = good;
    shortFrame.dlc = 4;
    imu.onFrame(shortFrame, 2);
    CanFrame wild = good;
    le::putI32(&wild.data[0], 50000000);  // 50 rad/s
    imu.onFrame(wild, 3);
    DOUBLES_EQUAL(0.25, imu.latest().yawRateRadS, 1e-12);
    LONGS_EQUAL(1, imu.frameStats().badLength);
    LONGS_EQUAL(1, imu.frameStats().badValue);
    core::Event e;
    unsigned badFrame = 0, badValue = 0;
    while (core::isOk(events.pop(&e))) {
        badFrame += e.id == events::kDeviceBadFrame ? 1U : 0U;
        badValue += e.id == events::kDeviceBadValue ? 1U : 0U;
    }
    LONGS_EQUAL(1, badFrame);
    LONGS_EQUAL(1, badValue);
}

TEST(RseDevices, PowerMonitorScalesAndRejectsImpossibleCharge) {
    PowerMonitor power(events);
    CanFrame f = frame8(device_ids::kPower);
    le::putU16(&f.data[0], 28500);
    le::putI16(&f.data[2], -1200);
    le::putU16(&f.data[4], 8750);
    le::putU16(&f.data[6], 3000);
    power.onFrame(f, 5);
    DOUBLES_EQUAL(28.5, power.latest().busVoltageV, 1e-9);
    DOUBLES_EQUAL(-1.2, power.latest().busCurrentA, 1e-9);
    DOUBLES_EQUAL(0.875, power.latest().stateOfCharge, 1e-9);
    le::putU16(&f.data[4], 10001);
    power.onFrame(f, 6);
    LONGS_EQUAL(1, power.frameStats().badValue);
    DOUBLES_EQUAL(0.875, power.latest().stateOfCharge, 1e-9);
}

TEST(RseDevices, PositionFixPairsHalvesByCounterInEitherOrder) {
    PositionFixSource fix(events);
    CanFrame x = frame8(device_ids::kFixX);
    CanFrame y = frame8(device_ids::kFixY);
    le::putI32(&x.data[0], 12345);
    le::putU16(&x.data[4], 500);
    le::putU16(&x.data[6], 7);
    le::putI32(&y.data[0], -2000);
    le::putI16(&y.data[4], 15708);
    le::putU16(&y.data[6], 7);
    fix.onFrame(y, 10);
    LONGS_EQUAL(0, fix.latest().count);
    fix.onFrame(x, 11);
    LONGS_EQUAL(1, fix.latest().count);
    DOUBLES_EQUAL(12.345, fix.latest().xM, 1e-9);
    DOUBLES_EQUAL(-2.0, fix.latest().yM, 1e-9);
    DOUBLES_EQUAL(1.5708, fix.latest().headingRad, 1e-9);
    DOUBLES_EQUAL(0.5, fix.latest().sigmaM, 1e-9);
    // Mismatched halves never make a fix.
    le::putU16(&x.data[6], 8);
    le::putU16(&y.data[6], 9);
    fix.onFrame(x, 20);
    fix.onFrame(y, 21);
    LONGS_EQUAL(1, fix.latest().count);
    CHECK(fix.unpaired() >= 1);
}

TEST(RseDevices, HazardTableUpdatesByIdClearsAndExpires) {
    HazardDetector hazard(events);
    CanFrame f = frame8(device_ids::kHazard);
    le::putI16(&f.data[0], 250);
    le::putI16(&f.data[2], -300);
    le::putI16(&f.data[4], 40);
    f.data[6] = 3;
    hazard.onFrame(f, 0);
    le::putI16(&f.data[0], 200);
    hazard.onFrame(f, core::kNsPerSec / 2);  // same obstacle, closer
    LONGS_EQUAL(1, hazard.sightings().size());
    DOUBLES_EQUAL(2.0, hazard.sightings().at(0)->rangeM, 1e-9);
    DOUBLES_EQUAL(-0.3, hazard.sightings().at(0)->bearingRad, 1e-9);
    hazard.expire(core::kNsPerSec);
    LONGS_EQUAL(1, hazard.sightings().size());
    hazard.expire(2 * core::kNsPerSec);
    LONGS_EQUAL(0, hazard.sightings().size());
    hazard.onFrame(f, 3 * core::kNsPerSec);
    f.data[6] = 0;  // clear
    hazard.onFrame(f, 3 * core::kNsPerSec);
    LONGS_EQUAL(0, hazard.sightings().size());
    f.data[6] = 4;
    le::putI16(&f.data[2], 4000);  // bearing beyond pi
    hazard.onFrame(f, 4 * core::kNsPerSec);
    LONGS_EQUAL(1, hazard.frameStats().badValue);
}
