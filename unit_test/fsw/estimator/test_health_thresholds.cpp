// Threshold faults (drive and bus over-current, battery low, pose uncertain):
// raised and cleared at their documented times, hysteresis, short spikes.
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "unit_test/fsw/estimator/health_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::HealthRig;
namespace ev = estimator::events;
namespace fault = msg::fault;

namespace {
constexpr core::TimeNs kFrame = HealthRig::kFrame;
constexpr core::TimeNs kPowerPeriod = 100 * core::kNsPerMs;
}  // namespace

TEST_GROUP(HealthThresholds) {
    HealthRig rig;
    core::TimeNs persist = 0;
    double driveLimit = 0.0;
    void setup() override {
        CHECK(rig.init());
        persist = static_cast<core::TimeNs>(rig.tables.faultResponse().fault_persist_ms) * core::kNsPerMs;
        driveLimit = static_cast<double>(rig.tables.faultResponse().drive_overcurrent_a);
        CHECK(persist > kFrame);  // the tests below assume the default 50 ms
        rig.steps(15);
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }

    // Steps until the next power sample is published; returns its time.
    core::TimeNs stepToNextPowerSample() {
        const core::TimeNs before = rig.feed.lastPowerSample;
        for (int i = 0; i < 20 && rig.feed.lastPowerSample == before; ++i) {
            rig.step();
        }
        return rig.feed.lastPowerSample;
    }

    // Loads a fault-response table with another persistence time.
    void loadPersistMs(std::uint16_t ms) {
        tables::FaultResponseTable t = rig.tables.faultResponse();
        t.fault_persist_ms = ms;
        std::uint8_t image[tables::kMaxTableImageSize];
        const std::size_t length = tables::encodeTable(t, 2, image, sizeof image);
        CHECK(length > 0);
        CHECK(rig.tables.loadChunk(tables::TableId::kFaultResponse, 0, image, length).ok());
        CHECK(rig.tables.validate(tables::TableId::kFaultResponse).ok());
        CHECK(rig.tables.activate(tables::TableId::kFaultResponse).ok());
        rig.tables.run(core::FrameContext{});
        LONGS_EQUAL(ms, rig.tables.faultResponse().fault_persist_ms);
        persist = static_cast<core::TimeNs>(ms) * core::kNsPerMs;
    }
};

TEST(HealthThresholds, DriveOvercurrentRaisesAfterPersistenceAndClearsBelowTheHysteresis) {
    rig.feed.drives.wheels[4].currentA = -(driveLimit + 0.5);  // wheel MR, either direction counts
    const core::TimeNs firstSample = rig.now() + kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(15, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - firstSample >= persist);
    CHECK(raisedAt - firstSample <= persist + kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << 15));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveOvercurrent));
    CHECK(core::Severity::kError == rig.event(ev::kHealthDriveOvercurrent).lastSeverity);
    STRCMP_CONTAINS("fault 15: drive MR over-current -3.30 A", rig.event(ev::kHealthDriveOvercurrent).lastText);

    // Between 0.9 x limit and the limit: stays raised.
    rig.feed.drives.wheels[4].currentA = 0.95 * driveLimit;
    rig.steps(200);
    CHECK(rig.health.active(15));
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthDriveOvercurrentCleared));

    rig.feed.drives.wheels[4].currentA = 0.5 * driveLimit;
    const core::TimeNs clearStart = rig.now() + kFrame;
    const core::TimeNs clearedAt = rig.stepUntil(15, false, 100);
    CHECK(clearedAt - clearStart >= persist);
    CHECK(clearedAt - clearStart <= persist + kFrame);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveOvercurrentCleared));
    CHECK(core::Severity::kInfo == rig.event(ev::kHealthDriveOvercurrentCleared).lastSeverity);
    STRCMP_CONTAINS("fault 15 cleared: drive MR", rig.event(ev::kHealthDriveOvercurrentCleared).lastText);

    // Between the thresholds while clear: stays clear.
    rig.feed.drives.wheels[4].currentA = 0.95 * driveLimit;
    rig.steps(200);
    CHECK_FALSE(rig.health.active(15));
    LONGS_EQUAL(1, rig.health.raisedCount(15));
}

TEST(HealthThresholds, AnOvercurrentSpikeShorterThanThePersistenceDoesNotRaise) {
    const int spikeFrames = static_cast<int>(persist / kFrame);  // spans persist - 10 ms of samples
    for (int repeat = 0; repeat < 20; ++repeat) {
        rig.feed.drives.wheels[0].currentA = 2.0 * driveLimit;
        rig.steps(spikeFrames);
        rig.feed.drives.wheels[0].currentA = 0.1;
        rig.steps(3);
    }
    LONGS_EQUAL(0, rig.health.raisedCount(11));
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthDriveOvercurrent));
    // ...and one more frame of it does.
    rig.feed.drives.wheels[0].currentA = 2.0 * driveLimit;
    rig.steps(spikeFrames + 1);
    CHECK(rig.health.active(11));
}

TEST(HealthThresholds, EachWheelRaisesItsOwnOvercurrentFault) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        rig.feed.drives.wheels[w].currentA = 2.0 * driveLimit;
        const auto id = static_cast<std::uint8_t>(fault::kDriveOvercurrent + w);
        CHECK(rig.stepUntil(id, true, 20) > 0);
        CHECK(rig.health.status().activeMask == (std::uint64_t{1} << id));
        rig.feed.drives.wheels[w].currentA = 0.0;
        CHECK(rig.stepUntil(id, false, 20) > 0);
    }
    LONGS_EQUAL(6, rig.eventCount(ev::kHealthDriveOvercurrent));
    LONGS_EQUAL(6, rig.eventCount(ev::kHealthDriveOvercurrentCleared));
}

TEST(HealthThresholds, BatteryLowIsJudgedOnThe10HzSamplesWithHysteresis) {
    const double low = static_cast<double>(rig.tables.faultResponse().battery_low_v);
    const double clear = static_cast<double>(rig.tables.faultResponse().battery_clear_v);
    rig.feed.power.busVoltageV = low - 0.5;
    const core::TimeNs firstSample = stepToNextPowerSample();
    const core::TimeNs raisedAt = rig.stepUntil(fault::kBatteryLow, true, 100);
    CHECK(raisedAt > 0);
    LONGS_EQUAL(rig.feed.lastPowerSample, raisedAt);  // judged when a sample arrives
    CHECK(raisedAt - firstSample >= persist);
    CHECK(raisedAt - firstSample <= persist + kPowerPeriod);  // documented: + one 10 Hz sample
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << fault::kBatteryLow));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthBatteryLow));
    CHECK(core::Severity::kCritical == rig.event(ev::kHealthBatteryLow).lastSeverity);
    STRCMP_CONTAINS("fault 17: battery low, bus 23.50 V < 24.00 V", rig.event(ev::kHealthBatteryLow).lastText);

    rig.feed.power.busVoltageV = 0.5 * (low + clear);
    rig.steps(300);
    CHECK(rig.health.active(fault::kBatteryLow));

    rig.feed.power.busVoltageV = clear + 0.5;
    const core::TimeNs clearSample = stepToNextPowerSample();
    const core::TimeNs clearedAt = rig.stepUntil(fault::kBatteryLow, false, 100);
    CHECK(clearedAt - clearSample >= persist);
    CHECK(clearedAt - clearSample <= persist + kPowerPeriod);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthBatteryLowCleared));
    CHECK(core::Severity::kInfo == rig.event(ev::kHealthBatteryLowCleared).lastSeverity);

    rig.feed.power.busVoltageV = 0.5 * (low + clear);
    rig.steps(300);
    CHECK_FALSE(rig.health.active(fault::kBatteryLow));
    LONGS_EQUAL(1, rig.health.raisedCount(fault::kBatteryLow));
}

TEST(HealthThresholds, ASingleLowBatterySampleDoesNotRaise) {
    for (int repeat = 0; repeat < 10; ++repeat) {
        rig.feed.power.busVoltageV = 20.0;
        (void)stepToNextPowerSample();
        rig.feed.power.busVoltageV = 28.0;
        (void)stepToNextPowerSample();
    }
    LONGS_EQUAL(0, rig.health.raisedCount(fault::kBatteryLow));
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthBatteryLow));
}

TEST(HealthThresholds, ThePersistenceTimeIsReadFromTheActiveTableEveryRun) {
    loadPersistMs(200);
    // Low on samples spanning 100 ms: enough for 50 ms, not for 200 ms.
    for (int repeat = 0; repeat < 5; ++repeat) {
        rig.feed.power.busVoltageV = 20.0;
        (void)stepToNextPowerSample();
        (void)stepToNextPowerSample();
        rig.feed.power.busVoltageV = 28.0;
        (void)stepToNextPowerSample();
    }
    LONGS_EQUAL(0, rig.health.raisedCount(fault::kBatteryLow));
    rig.feed.power.busVoltageV = 20.0;
    const core::TimeNs firstSample = stepToNextPowerSample();
    const core::TimeNs raisedAt = rig.stepUntil(fault::kBatteryLow, true, 100);
    LONGS_EQUAL(firstSample + persist, raisedAt);
}

TEST(HealthThresholds, BusOvercurrentRaisesAndClearsWithHysteresis) {
    const double limit = static_cast<double>(rig.tables.faultResponse().overcurrent_a);
    rig.feed.power.busCurrentA = limit + 1.0;
    const core::TimeNs firstSample = stepToNextPowerSample();
    const core::TimeNs raisedAt = rig.stepUntil(fault::kBusOvercurrent, true, 100);
    CHECK(raisedAt - firstSample >= persist);
    CHECK(raisedAt - firstSample <= persist + kPowerPeriod);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << fault::kBusOvercurrent));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthBusOvercurrent));
    STRCMP_CONTAINS("fault 18: bus over-current 21.00 A > 20.00 A", rig.event(ev::kHealthBusOvercurrent).lastText);

    rig.feed.power.busCurrentA = 0.95 * limit;
    rig.steps(300);
    CHECK(rig.health.active(fault::kBusOvercurrent));
    rig.feed.power.busCurrentA = 0.5 * limit;
    CHECK(rig.stepUntil(fault::kBusOvercurrent, false, 100) > 0);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthBusOvercurrentCleared));
    rig.feed.power.busCurrentA = 0.95 * limit;
    rig.steps(300);
    CHECK_FALSE(rig.health.active(fault::kBusOvercurrent));
}

TEST(HealthThresholds, PoseUncertainRaisesOnSigmaAndClearsBelowTheClearThreshold) {
    const double faultSigma = static_cast<double>(rig.tables.estimatorNoise().pose_fault_sigma_m);
    const double clearSigma = static_cast<double>(rig.tables.estimatorNoise().pose_clear_sigma_m);
    rig.feed.pose.positionSigmaM = faultSigma + 0.2;
    const core::TimeNs firstEstimate = rig.now() + kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(fault::kPoseUncertain, true, 20);
    CHECK(raisedAt > firstEstimate);             // two estimates needed
    CHECK(raisedAt <= firstEstimate + kFrame);  // documented: within 10 ms of the first
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthPoseUncertain));
    STRCMP_CONTAINS("fault 19: pose uncertain, position sigma 1.20 m > 1.00 m",
                    rig.event(ev::kHealthPoseUncertain).lastText);

    rig.feed.pose.positionSigmaM = 0.5 * (faultSigma + clearSigma);
    rig.steps(200);
    CHECK(rig.health.active(fault::kPoseUncertain));

    rig.feed.pose.positionSigmaM = clearSigma - 0.1;
    const core::TimeNs clearEstimate = rig.now() + kFrame;
    const core::TimeNs clearedAt = rig.stepUntil(fault::kPoseUncertain, false, 20);
    CHECK(clearedAt > clearEstimate);
    CHECK(clearedAt <= clearEstimate + kFrame);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthPoseUncertainCleared));
    CHECK(core::Severity::kInfo == rig.event(ev::kHealthPoseUncertainCleared).lastSeverity);

    rig.feed.pose.positionSigmaM = 0.5 * (faultSigma + clearSigma);
    rig.steps(200);
    CHECK_FALSE(rig.health.active(fault::kPoseUncertain));
}

TEST(HealthThresholds, ASigmaFlappingEveryFrameNeitherRaisesNorFloods) {
    for (int i = 0; i < 1000; ++i) {
        rig.feed.pose.positionSigmaM = i % 2 == 0 ? 5.0 : 0.1;
        rig.step();
    }
    LONGS_EQUAL(0, rig.health.raisedCount(fault::kPoseUncertain));
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthPoseUncertain));
}

TEST_GROUP(HealthFirstFix) {
    HealthRig rig;
    void setup() override { CHECK(rig.init()); }
};

TEST(HealthFirstFix, NoFixWithinTheWaitRaisesPoseUncertainAndTheFirstGoodFixClearsIt) {
    const core::TimeNs wait =
        static_cast<core::TimeNs>(rig.tables.estimatorNoise().first_fix_wait_ms) * core::kNsPerMs;
    rig.feed.pose.initialised = 0;
    rig.feed.pose.positionSigmaM = 0.0;
    const core::TimeNs raisedAt = rig.stepUntil(fault::kPoseUncertain, true, 1000);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - HealthRig::kEpoch > wait);
    CHECK(raisedAt - HealthRig::kEpoch <= wait + 2 * kFrame);  // documented: wait + 20 ms
    STRCMP_CONTAINS("no position fix", rig.event(ev::kHealthPoseUncertain).lastText);

    rig.feed.pose.initialised = 1;
    rig.feed.pose.positionSigmaM = 0.2;
    CHECK(rig.stepUntil(fault::kPoseUncertain, false, 3) > 0);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthPoseUncertainCleared));
}

TEST(HealthFirstFix, NoPoseMessageAtAllCountsAsNoFix) {
    rig.feed.publishPose = false;
    const core::TimeNs raisedAt = rig.stepUntil(fault::kPoseUncertain, true, 1000);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - HealthRig::kEpoch <=
          static_cast<core::TimeNs>(rig.tables.estimatorNoise().first_fix_wait_ms) * core::kNsPerMs + 2 * kFrame);
}

TEST(HealthFirstFix, AFixWithinTheWaitRaisesNothing) {
    rig.feed.pose.initialised = 0;
    rig.steps(200);
    rig.feed.pose.initialised = 1;
    rig.steps(500);
    LONGS_EQUAL(0, rig.health.raisedCount(fault::kPoseUncertain));
}
