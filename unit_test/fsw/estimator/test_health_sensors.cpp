// Sensor-stale faults (36..39: a device's data stops while its heartbeat goes
// on) and the pose-uncertainty fault on an estimate the fixes refuted, at their
// documented times (fsw/estimator/health_monitor.hpp).
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
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

std::uint8_t staleFault(msg::DeviceNode device) {
    return static_cast<std::uint8_t>(fault::kSensorStale + static_cast<std::uint8_t>(device));
}
core::TimeNs ms(std::uint16_t v) { return static_cast<core::TimeNs>(v) * core::kNsPerMs; }
}  // namespace

TEST_GROUP(HealthSensorStale) {
    HealthRig rig;
    void setup() override {
        CHECK(rig.init());
        rig.steps(150);  // every device has spoken (the fix and the hazard detector at 1 Hz)
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }

    void loadNoise(const tables::EstimatorNoiseTable& t) {
        std::uint8_t image[tables::kMaxTableImageSize];
        const std::size_t length = tables::encodeTable(t, 2, image, sizeof image);
        CHECK(length > 0);
        CHECK(rig.tables.loadChunk(tables::TableId::kEstimatorNoise, 0, image, length).ok());
        CHECK(rig.tables.validate(tables::TableId::kEstimatorNoise).ok());
        CHECK(rig.tables.activate(tables::TableId::kEstimatorNoise).ok());
        rig.tables.run(core::FrameContext{});
    }
};

// The IMU's samples stop, its heartbeat does not: raised after imu_stale_ms
// (not before, at most one frame after), cleared in the frame a sample is read.
TEST(HealthSensorStale, ImuDataStoppingWithItsHeartbeatOnRaisesStaleAndItsReturnClearsIt) {
    const core::TimeNs stale = ms(rig.tables.estimatorNoise().imu_stale_ms);
    const std::uint8_t id = staleFault(msg::DeviceNode::kImu);
    rig.feed.publishImu = false;
    const core::TimeNs lastSample = rig.feed.lastImuSample;
    const core::TimeNs raisedAt = rig.stepUntil(id, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - lastSample > stale);
    CHECK(raisedAt - lastSample <= stale + kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << id));  // no heartbeat fault
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthSensorStale));
    CHECK(core::Severity::kError == rig.event(ev::kHealthSensorStale).lastSeverity);
    STRCMP_CONTAINS("health: fault 36: IMU data stale", rig.event(ev::kHealthSensorStale).lastText);

    rig.steps(50);
    CHECK(rig.health.active(id));
    rig.feed.publishImu = true;
    const core::TimeNs clearedAt = rig.stepUntil(id, false, 5);
    LONGS_EQUAL(rig.feed.lastImuSample, clearedAt);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthSensorStaleCleared));
    STRCMP_CONTAINS("fault 36 cleared: IMU data back", rig.event(ev::kHealthSensorStaleCleared).lastText);
    LONGS_EQUAL(0, rig.health.status().activeMask);
}

TEST(HealthSensorStale, PowerAndPositionFixEachRaiseTheirOwnFaultAfterTheirOwnTime) {
    const core::TimeNs powerStale = ms(rig.tables.estimatorNoise().power_stale_ms);
    rig.feed.publishPower = false;
    const core::TimeNs lastPower = rig.feed.lastPowerSample;
    const core::TimeNs powerAt = rig.stepUntil(staleFault(msg::DeviceNode::kPower), true, 200);
    CHECK(powerAt - lastPower > powerStale);
    CHECK(powerAt - lastPower <= powerStale + kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << staleFault(msg::DeviceNode::kPower)));
    rig.feed.publishPower = true;
    CHECK(rig.stepUntil(staleFault(msg::DeviceNode::kPower), false, 20) > 0);

    const core::TimeNs fixStale = ms(rig.tables.estimatorNoise().fix_stale_ms);
    rig.feed.publishFix = false;
    const core::TimeNs lastFix = rig.feed.lastFixSample;
    const core::TimeNs fixAt = rig.stepUntil(staleFault(msg::DeviceNode::kPositionFix), true, 1000);
    CHECK(fixAt - lastFix > fixStale);
    CHECK(fixAt - lastFix <= fixStale + kFrame);
    STRCMP_CONTAINS("fault 39: position fix data stale", rig.event(ev::kHealthSensorStale).lastText);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << staleFault(msg::DeviceNode::kPositionFix)));
    rig.feed.publishFix = true;
    CHECK(rig.stepUntil(staleFault(msg::DeviceNode::kPositionFix), false, 150) > 0);
    LONGS_EQUAL(2, rig.health.status().raisedTotal);
}

// HazardMsg keeps coming every 100 ms whatever the detector does; only its
// frame count shows the detector has gone quiet.
TEST(HealthSensorStale, ASilentHazardDetectorIsSeenThroughItsFrameCountThoughHazardMsgKeepsComing) {
    const core::TimeNs stale = ms(rig.tables.estimatorNoise().hazard_stale_ms);
    const std::uint8_t id = staleFault(msg::DeviceNode::kHazard);
    rig.feed.hazardSpeaks = false;
    const core::TimeNs lastFrame = rig.feed.lastHazardFrame;
    const core::TimeNs raisedAt = rig.stepUntil(id, true, 400);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - lastFrame > stale);
    CHECK(raisedAt - lastFrame <= stale + kFrame);  // 100 ms messages, but the frame count moved in one
    STRCMP_CONTAINS("fault 38: hazard data stale", rig.event(ev::kHealthSensorStale).lastText);

    rig.feed.hazardSpeaks = true;  // the next 1 Hz report
    const core::TimeNs clearedAt = rig.stepUntil(id, false, 120);
    LONGS_EQUAL(rig.feed.lastHazardFrame, clearedAt);
}

// A device that never sends data is judged from the health task's first run.
TEST(HealthSensorStale, ADeviceThatNeverSpeaksIsStaleItsTimeAfterTheFirstRun) {
    HealthRig fresh;
    CHECK(fresh.init());
    fresh.feed.hazardSpeaks = false;
    const core::TimeNs raisedAt = fresh.stepUntil(staleFault(msg::DeviceNode::kHazard), true, 400);
    const core::TimeNs stale = ms(fresh.tables.estimatorNoise().hazard_stale_ms);
    CHECK(raisedAt - HealthRig::kEpoch > stale);
    CHECK(raisedAt - HealthRig::kEpoch <= stale + kFrame);
}

// Samples flagged invalid are not data: the estimator cannot use them either.
TEST(HealthSensorStale, InvalidImuSamplesDoNotKeepTheImuFresh) {
    rig.feed.publishImu = false;
    const core::TimeNs stale = ms(rig.tables.estimatorNoise().imu_stale_ms);
    for (int i = 0; i < 50; ++i) {
        rig.step();
        const msg::ImuMsg invalid{rig.now(), 0.0, 0, {}};
        (void)rig.bus.publish(invalid);
    }
    CHECK(stale < 50 * kFrame);
    CHECK(rig.health.active(staleFault(msg::DeviceNode::kImu)));
}

// The stale time is read from the active table: a longer one delays the fault.
TEST(HealthSensorStale, TheStaleTimeIsReadFromTheActiveTable) {
    tables::EstimatorNoiseTable t = rig.tables.estimatorNoise();
    t.hazard_stale_ms = 5000;
    loadNoise(t);
    rig.feed.hazardSpeaks = false;
    const core::TimeNs lastFrame = rig.feed.lastHazardFrame;
    const core::TimeNs raisedAt = rig.stepUntil(staleFault(msg::DeviceNode::kHazard), true, 700);
    CHECK(raisedAt - lastFrame > 5000 * core::kNsPerMs);
    CHECK(raisedAt - lastFrame <= 5000 * core::kNsPerMs + kFrame);

    rig.feed.hazardSpeaks = true;
    CHECK(rig.stepUntil(staleFault(msg::DeviceNode::kHazard), false, 120) > 0);
    t.imu_stale_ms = 400;
    loadNoise(t);
    rig.feed.publishImu = false;
    const core::TimeNs lastImu = rig.feed.lastImuSample;
    const core::TimeNs imuAt = rig.stepUntil(staleFault(msg::DeviceNode::kImu), true, 100);
    CHECK(imuAt - lastImu > 400 * core::kNsPerMs);
    CHECK(imuAt - lastImu <= 400 * core::kNsPerMs + kFrame);
}

TEST_GROUP(HealthPoseInconsistent) {
    HealthRig rig;
    void setup() override {
        CHECK(rig.init());
        rig.steps(150);
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }
};

// The estimator's sigma may be small while its estimate is refuted by the
// fixes: the inconsistency flag alone raises fault 19, and it clears only once
// the estimate is consistent again (and its sigma below the clear threshold).
TEST(HealthPoseInconsistent, AnInconsistentEstimateRaisesPoseUncertainWhateverItsSigma) {
    rig.feed.pose.positionSigmaM = 0.05;
    rig.feed.pose.inconsistent = 1;
    rig.feed.pose.consecutiveFixRejections = 3;
    const core::TimeNs firstEstimate = rig.now() + kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(fault::kPoseUncertain, true, 10);
    CHECK(raisedAt > firstEstimate);
    CHECK(raisedAt <= firstEstimate + kFrame);
    STRCMP_CONTAINS("fault 19: pose uncertain, estimate inconsistent with the fixes (3 refused in a row)",
                    rig.event(ev::kHealthPoseUncertain).lastText);

    rig.feed.pose.consecutiveFixRejections = 0;  // re-anchored, not yet confirmed by a fix
    rig.steps(200);
    CHECK(rig.health.active(fault::kPoseUncertain));

    rig.feed.pose.inconsistent = 0;
    const core::TimeNs clearedAt = rig.stepUntil(fault::kPoseUncertain, false, 10);
    CHECK(clearedAt > 0);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthPoseUncertainCleared));
}

TEST(HealthPoseInconsistent, AConsistentEstimateWithALargeSigmaStaysRaisedAfterTheFlagClears) {
    rig.feed.pose.inconsistent = 1;
    CHECK(rig.stepUntil(fault::kPoseUncertain, true, 10) > 0);
    const double clearSigma = static_cast<double>(rig.tables.estimatorNoise().pose_clear_sigma_m);
    rig.feed.pose.inconsistent = 0;
    rig.feed.pose.positionSigmaM = clearSigma + 0.1;
    rig.steps(100);
    CHECK(rig.health.active(fault::kPoseUncertain));
    rig.feed.pose.positionSigmaM = clearSigma - 0.1;
    CHECK(rig.stepUntil(fault::kPoseUncertain, false, 10) > 0);
}
