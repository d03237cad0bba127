// The pose estimator task on an in-memory software bus: initialisation from the
// first fix, odometry and yaw-rate sources, gating, bad inputs, events,
// counters, the published estimate, and no heap use.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/pose_estimator_events.hpp"
#include "fsw/estimator/pose_estimator_task.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;
using core::TimeNs;
namespace ev = rse::estimator::events;

namespace {

constexpr TimeNs kFrame = 10 * core::kNsPerMs;

}  // namespace

TEST_GROUP(PoseEstimatorTask) {
    core::VirtualClock clock{1 * core::kNsPerSec};
    core::EventLog events{clock};
    // CppUTest creates each test object on the heap, so the bus's storage stays off the stack.
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    estimator::PoseEstimatorTask task{bus, events, tables};
    core::PipeId probe = 0;
    core::Message inbox{};
    std::uint64_t frameCount = 0;
    unsigned published = 0;
    msg::PoseEstimateMsg lastPublished{};

    // What the simulated devices say each frame.
    double wheels[msg::kWheelCount] = {};
    TimeNs wheelAge[msg::kWheelCount] = {};  // feedback age at publish time
    bool wheelReported[msg::kWheelCount] = {true, true, true, true, true, true};
    msg::DriveHealth health[msg::kWheelCount] = {};
    bool drivePublishing = true;
    bool imuPublishing = true;
    double imuRate = 0.0;
    // Default ROVER_GEOMETRY (r 0.10 m, track 0.60 m, skid factor 1.5), as the f32 fields hold them.
    double radius = 0.0;
    double wheelYawGain = 0.0;  // yaw rate per rad/s of right-minus-left wheel speed

    void setup() override {
        CHECK_TRUE(Status::kOk == tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount));
        const tables::RoverGeometryTable& g = tables.roverGeometry();
        radius = static_cast<double>(g.wheel_radius_m);
        wheelYawGain = radius / (static_cast<double>(g.skid_factor) * static_cast<double>(g.track_width_m));
        DOUBLES_EQUAL(0.10, radius, 1e-6);
        DOUBLES_EQUAL(0.10 / 0.9, wheelYawGain, 1e-6);
        CHECK_TRUE(Status::kOk == task.init());
        CHECK_TRUE(Status::kOk == bus.createPipe("probe", 4, &probe));
        CHECK_TRUE(Status::kOk == bus.subscribe(probe, msg::ids::kPoseEstimate));
        for (msg::DriveHealth& h : health) {
            h = msg::DriveHealth::kOperational;
        }
        (void)test::drainEventsWithId(events, 0);
    }

    void publishFix(double x, double y, double heading, double sigma) {
        CHECK_TRUE(Status::kOk == bus.publish(msg::PositionFixMsg{clock.now(), x, y, heading, sigma}));
    }

    // One minor frame: devices publish (as CAN I/O would), the task runs at the
    // frame's start, the probe takes what it published, time moves on.
    void runFrame(TimeNs actualStart) {
        const TimeNs now = clock.now();
        if (drivePublishing) {
            msg::DriveStatusMsg status{};
            status.timeNs = now;
            for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
                status.wheels[w].velocityRadS = wheels[w];
                status.wheels[w].feedbackTimeNs = now - wheelAge[w];
                status.wheels[w].feedbackCount = wheelReported[w] ? 100U : 0U;
                status.wheels[w].health = health[w];
            }
            CHECK_TRUE(Status::kOk == bus.publish(status));
        }
        if (imuPublishing) {
            CHECK_TRUE(Status::kOk == bus.publish(msg::ImuMsg{now, imuRate, 1, {}}));
        }
        const core::FrameContext frame{frameCount, static_cast<std::uint32_t>(frameCount % 100), now, actualStart};
        task.run(frame);
        ++frameCount;
        while (core::isOk(bus.receive(probe, &inbox))) {
            CHECK_TRUE(Status::kOk == inbox.decode(&lastPublished));
            ++published;
        }
        clock.advance(kFrame);
    }
    void runFrame() { runFrame(clock.now()); }
    void runFrames(int n) {
        for (int i = 0; i < n; ++i) {
            runFrame();
        }
    }

    void setAllWheels(double left, double right) {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            wheels[w] = w < 3 ? left : right;
        }
    }

    // Initialised at (x, y, heading) from a fix at the floor sigma, after one plain frame.
    void initialiseAt(double x, double y, double heading) {
        runFrame();
        publishFix(x, y, heading, 0.05);
        runFrame();
        CHECK_TRUE(task.filter().initialised());
        (void)test::drainEventsWithId(events, 0);
    }

    unsigned eventsWithId(core::EventId id) { return test::drainEventsWithId(events, id); }
};

TEST(PoseEstimatorTask, BeforeTheFirstFixItPublishesAnUninitialisedEstimateEveryRun) {
    setAllWheels(3.0, 3.0);
    runFrames(5);
    LONGS_EQUAL(5, published);
    CHECK_FALSE(task.filter().initialised());
    const msg::PoseEstimateMsg& m = lastPublished;
    LONGS_EQUAL(0, m.initialised);
    CHECK_EQUAL(clock.now() - kFrame, m.timeNs);
    DOUBLES_EQUAL(0.0, m.xM, 0.0);
    DOUBLES_EQUAL(0.0, m.yM, 0.0);
    DOUBLES_EQUAL(0.0, m.headingRad, 0.0);
    for (int i = 0; i < 9; ++i) {
        DOUBLES_EQUAL(i % 4 == 0 ? 1e6 : 0.0, m.covariance[i], 0.0);
    }
    DOUBLES_EQUAL(1e3, m.positionSigmaM, 1e-9);
    CHECK_TRUE(std::memcmp(&m, &task.latest(), sizeof m) == 0);
}

TEST(PoseEstimatorTask, TheFirstValidFixInitialisesWithTheFloorAndTableSigmas) {
    runFrame();
    publishFix(3.0, -4.0, 0.5, 0.002);  // below the 0.01 m floor
    runFrame();
    const test::DrainedEvents initialised = test::drainEvents(events, ev::kPoseInitialised);
    LONGS_EQUAL(1, initialised.count);
    CHECK_TRUE(initialised.text.rfind("estimator: initialised at", 0) == 0);
    const msg::PoseEstimateMsg& m = lastPublished;
    LONGS_EQUAL(1, m.initialised);
    DOUBLES_EQUAL(3.0, m.xM, 0.0);
    DOUBLES_EQUAL(-4.0, m.yM, 0.0);
    DOUBLES_EQUAL(0.5, m.headingRad, 0.0);
    const double floorM = static_cast<double>(tables.estimatorNoise().position_fix_sigma_floor_m);
    const double headingSigma = static_cast<double>(tables.estimatorNoise().fix_heading_sigma_rad);
    const double biasSigma = static_cast<double>(tables.estimatorNoise().initial_gyro_bias_sigma_rad_s);
    DOUBLES_EQUAL(floorM * floorM, m.covariance[0], 1e-15);
    DOUBLES_EQUAL(floorM * floorM, m.covariance[4], 1e-15);
    DOUBLES_EQUAL(headingSigma * headingSigma, m.covariance[8], 1e-15);
    DOUBLES_EQUAL(0.0, m.covariance[1], 0.0);
    DOUBLES_EQUAL(biasSigma * biasSigma, m.gyroBiasVariance, 1e-15);
    DOUBLES_EQUAL(floorM, m.positionSigmaM, 1e-12);
    LONGS_EQUAL(1, m.fixesAccepted);
}

TEST(PoseEstimatorTask, DrivesOnWheelOdometryAndTheImu) {
    initialiseAt(1.0, 2.0, 0.0);
    setAllWheels(2.0, 2.0);  // 0.2 m/s
    runFrames(100);          // 1 s of predictions after the initialising frame
    const msg::PoseEstimateMsg& m = lastPublished;
    DOUBLES_EQUAL(1.0 + 2.0 * radius, m.xM, 1e-12);
    DOUBLES_EQUAL(2.0, m.yM, 1e-12);
    DOUBLES_EQUAL(2.0 * radius, m.speedMS, 1e-15);
    DOUBLES_EQUAL(0.0, m.yawRateRadS, 0.0);
    LONGS_EQUAL(1, m.yawFromImu);
    LONGS_EQUAL(100, task.counters().predictions);
    CHECK_TRUE(m.covariance[0] > 0.05 * 0.05);  // uncertainty grew since the fix
    CHECK_TRUE(m.positionSigmaM > 0.05);

    imuRate = 0.1;  // the IMU turns the rover; the wheels say straight: the IMU wins
    runFrames(100);
    DOUBLES_EQUAL(0.1, lastPublished.yawRateRadS, 1e-15);  // no fix yet: bias estimate still 0
    DOUBLES_EQUAL(0.1, lastPublished.headingRad, 1e-12);
}

TEST(PoseEstimatorTask, AnOutlierIsGatedCountedEventedAndMovesNothing) {
    initialiseAt(0.0, 0.0, 0.0);
    runFrames(50);  // standing still
    const estimator::PoseState before = task.filter().state();
    publishFix(20.0, 0.0, 0.0, 0.05);
    runFrame();
    CHECK_TRUE(before == task.filter().state());
    LONGS_EQUAL(1, task.counters().fixesRejected);
    LONGS_EQUAL(1, lastPublished.fixesRejected);
    LONGS_EQUAL(1, lastPublished.fixesAccepted);
    const test::DrainedEvents gated = test::drainEvents(events, ev::kFixRejectedByGate);
    LONGS_EQUAL(1, gated.count);
    CHECK_TRUE(gated.text.find("d2") != std::string::npos);

    publishFix(0.01, 0.0, 0.0, 0.05);  // a good one still gets in
    runFrame();
    LONGS_EQUAL(2, lastPublished.fixesAccepted);
    CHECK_TRUE(task.filter().x() > 0.0);
}

TEST(PoseEstimatorTask, FallsBackToTheWheelYawRateWhileTheImuIsStaleAndBack) {
    initialiseAt(0.0, 0.0, 0.0);
    setAllWheels(-1.0, 1.0);  // turning on the spot
    imuRate = 0.123;
    runFrames(10);
    DOUBLES_EQUAL(0.123, lastPublished.yawRateRadS, 1e-15);
    LONGS_EQUAL(1, lastPublished.yawFromImu);

    imuPublishing = false;  // last sample now 10 ms old at the next frame
    runFrames(10);          // ages 10..100 ms; stale beyond imu_timeout_ms = 50
    LONGS_EQUAL(5, task.counters().imuStale);
    LONGS_EQUAL(5, lastPublished.imuStaleCount);
    LONGS_EQUAL(0, lastPublished.yawFromImu);
    DOUBLES_EQUAL(2.0 * wheelYawGain, lastPublished.yawRateRadS, 1e-12);
    LONGS_EQUAL(1, eventsWithId(ev::kYawFromWheels));  // once per switch, not per frame

    imuPublishing = true;
    runFrames(3);
    LONGS_EQUAL(1, lastPublished.yawFromImu);
    DOUBLES_EQUAL(0.123, lastPublished.yawRateRadS, 1e-15);
    LONGS_EQUAL(1, eventsWithId(ev::kYawFromImu));
    LONGS_EQUAL(2, task.counters().yawSourceSwitches);
    LONGS_EQUAL(5, task.counters().imuStale);
}

TEST(PoseEstimatorTask, StaleWheelsAreLeftOutAndNoneFreshMeansStandingStill) {
    initialiseAt(0.0, 0.0, 0.0);
    setAllWheels(2.0, 4.0);
    imuPublishing = false;  // so the wheel yaw rate shows in the estimate

    for (std::size_t w = 0; w < 3; ++w) {
        wheelAge[w] = 60 * core::kNsPerMs;  // the left side is stale: the right side's mean stands in
    }
    runFrames(10);
    DOUBLES_EQUAL(4.0 * radius, lastPublished.speedMS, 1e-15);
    DOUBLES_EQUAL(0.0, lastPublished.yawRateRadS, 0.0);
    LONGS_EQUAL(0, task.counters().odometryStale);

    wheelAge[0] = 0;  // one fresh left wheel is the left mean
    wheelReported[3] = false;  // never reported: not fresh even with a current time
    wheels[4] = 6.0;
    runFrame();
    DOUBLES_EQUAL(radius * (2.0 + 5.0) / 2.0, lastPublished.speedMS, 1e-12);
    DOUBLES_EQUAL(wheelYawGain * (5.0 - 2.0), lastPublished.yawRateRadS, 1e-12);

    for (TimeNs& age : wheelAge) {
        age = 51 * core::kNsPerMs;
    }
    const double xBefore = task.filter().x();
    runFrames(4);
    LONGS_EQUAL(4, task.counters().odometryStale);
    LONGS_EQUAL(3, eventsWithId(ev::kOdometryStale));  // 1st, 2nd and 4th: throttled, all counted
    DOUBLES_EQUAL(0.0, lastPublished.speedMS, 0.0);
    DOUBLES_EQUAL(xBefore, task.filter().x(), 0.0);

    drivePublishing = false;  // no drive status at all: the last one ages out the same way
    runFrame();
    LONGS_EQUAL(5, task.counters().odometryStale);
}

TEST(PoseEstimatorTask, ALockedWheelStaysInItsSidesMean) {
    initialiseAt(0.0, 0.0, 0.0);
    setAllWheels(3.0, 3.0);
    wheels[0] = 0.0;  // locked
    health[0] = msg::DriveHealth::kFailed;
    imuPublishing = false;
    runFrames(10);
    DOUBLES_EQUAL(radius * (2.0 + 3.0) / 2.0, lastPublished.speedMS, 1e-12);
    DOUBLES_EQUAL(wheelYawGain * (3.0 - 2.0), lastPublished.yawRateRadS, 1e-12);
}

TEST(PoseEstimatorTask, MalformedAndNonFiniteInputsAreCountedEventedAndNotUsed) {
    initialiseAt(0.0, 0.0, 0.0);
    imuPublishing = false;
    setAllWheels(1.0, 1.0);
    runFrames(10);  // IMU stale: wheels give the yaw rate
    (void)test::drainEventsWithId(events, 0);

    const std::uint8_t shortImu[3] = {1, 2, 3};
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kImu, shortImu, sizeof shortImu));
    CHECK_TRUE(Status::kOk == bus.publish(msg::ImuMsg{clock.now(), NAN, 1, {}}));
    CHECK_TRUE(Status::kOk == bus.publish(msg::ImuMsg{clock.now(), 0.5, 0, {}}));
    runFrame();
    LONGS_EQUAL(1, task.counters().malformed);
    LONGS_EQUAL(1, task.counters().notFinite);
    LONGS_EQUAL(1, task.counters().imuInvalid);
    LONGS_EQUAL(0, lastPublished.yawFromImu);  // none of them was taken as a sample
    DOUBLES_EQUAL(0.0, lastPublished.yawRateRadS, 0.0);
    const test::DrainedEvents malformed = test::drainEvents(events, ev::kEstimatorMalformed);
    LONGS_EQUAL(1, malformed.count);
    CHECK_TRUE(malformed.text.find("0x0120") != std::string::npos);

    wheels[0] = NAN;  // that wheel is left out; the others carry the left mean
    runFrame();
    LONGS_EQUAL(2, task.counters().notFinite);
    DOUBLES_EQUAL(radius, lastPublished.speedMS, 1e-15);
    CHECK_TRUE(std::isfinite(lastPublished.xM));
    LONGS_EQUAL(1, eventsWithId(ev::kInputNotFinite));  // 2nd occurrence: reported
}

TEST(PoseEstimatorTask, AnInvalidFixIsCountedEventedAndDoesNotInitialise) {
    runFrame();
    publishFix(NAN, 0.0, 0.0, 0.05);
    runFrame();
    publishFix(1.0, 0.0, 0.0, 0.0);
    runFrame();
    publishFix(1.0, 0.0, INFINITY, 0.05);
    runFrame();
    CHECK_FALSE(task.filter().initialised());
    LONGS_EQUAL(3, lastPublished.fixesInvalid);
    LONGS_EQUAL(0, lastPublished.initialised);
    const test::DrainedEvents invalid = test::drainEvents(events, ev::kFixInvalid);
    LONGS_EQUAL(2, invalid.count);  // 1st and 2nd of 3 (throttled)
    CHECK_TRUE(invalid.text.rfind("estimator: ", 0) == 0);

    publishFix(1.0, 0.0, 0.0, 0.05);
    runFrame();
    CHECK_TRUE(task.filter().initialised());
    LONGS_EQUAL(1, lastPublished.fixesAccepted);

    publishFix(1.0, 0.0, 0.0, -1.0);  // after initialisation too
    runFrame();
    LONGS_EQUAL(4, lastPublished.fixesInvalid);
}

TEST(PoseEstimatorTask, OfTwoFixesInOneFrameTheLatestIsUsed) {
    runFrame();
    publishFix(1.0, 1.0, 0.0, 0.05);
    publishFix(2.0, 2.0, 0.0, 0.05);
    runFrame();
    LONGS_EQUAL(1, task.counters().fixesSuperseded);
    LONGS_EQUAL(1, eventsWithId(ev::kFixSuperseded));
    DOUBLES_EQUAL(2.0, lastPublished.xM, 0.0);
    LONGS_EQUAL(1, lastPublished.fixesAccepted);
}

TEST(PoseEstimatorTask, TimeGoingBackwardsRefusesOnePredictionAndRecovers) {
    initialiseAt(0.0, 0.0, 0.0);
    setAllWheels(1.0, 1.0);
    runFrames(5);
    runFrame(clock.now() - 100 * core::kNsPerMs);
    LONGS_EQUAL(1, task.counters().predictionsRefused);
    LONGS_EQUAL(1, eventsWithId(ev::kPredictionRefused));
    const std::uint32_t predictions = task.counters().predictions;
    runFrames(3);
    LONGS_EQUAL(predictions + 3, task.counters().predictions);
    LONGS_EQUAL(1, task.counters().predictionsRefused);
}

TEST(PoseEstimatorTask, TheNoiseTableIsReadEveryRun) {
    runFrame();
    // A new ESTIMATOR_NOISE with a 1 m fix floor, activated at a frame boundary.
    const std::vector<std::uint8_t> image = test::defaultImage(tables::TableId::kEstimatorNoise);
    tables::EstimatorNoiseTable t{};
    CHECK_TRUE(tables::decodeTable(image.data(), image.size(), &t).ok());
    t.position_fix_sigma_floor_m = 1.0F;
    std::vector<std::uint8_t> changed(tables::kMaxTableImageSize);
    changed.resize(tables::encodeTable(t, 2, changed.data(), changed.size()));
    CHECK_TRUE(tables.loadChunk(tables::TableId::kEstimatorNoise, 0, changed.data(), changed.size()).ok());
    CHECK_TRUE(tables.validate(tables::TableId::kEstimatorNoise).ok());
    CHECK_TRUE(tables.activate(tables::TableId::kEstimatorNoise).ok());
    tables.run(core::FrameContext{});

    publishFix(0.0, 0.0, 0.0, 0.05);
    runFrame();
    DOUBLES_EQUAL(1.0, lastPublished.covariance[0], 1e-12);
}

TEST(PoseEstimatorTask, TenThousandRunsAllocateNothing) {
    initialiseAt(0.0, 0.0, 0.0);
    setAllWheels(2.0, 2.5);
    imuRate = 0.05;
    test::AllocationWatch watch;
    for (int i = 0; i < 10000; ++i) {
        imuPublishing = (i % 2000) < 1900;  // an IMU outage every 20 s
        if (i % 100 == 50) {
            const bool outlier = i % 1000 == 50;
            publishFix(task.filter().x() + (outlier ? 30.0 : 0.0), task.filter().y(), task.filter().heading(), 0.05);
        }
        runFrame();
        core::Event e;
        while (core::isOk(events.pop(&e))) {
        }
    }
    LONGS_EQUAL(0, watch.count());
    // ...and it really ran: every path the loop meant to take was taken.
    LONGS_EQUAL(10000, task.counters().predictions);
    LONGS_EQUAL(10, task.counters().fixesRejected);
    LONGS_EQUAL(91, task.counters().fixesAccepted);  // the initialising one and 90 good ones
    CHECK_TRUE(task.counters().imuStale > 0);
    LONGS_EQUAL(9, task.counters().yawSourceSwitches);  // to wheels and back 4 times, the 5th outage runs to the end
}

namespace {

void activateNoise(tables::TableService& service, const tables::EstimatorNoiseTable& t) {
    std::vector<std::uint8_t> image(tables::kMaxTableImageSize);
    image.resize(tables::encodeTable(t, 2, image.data(), image.size()));
    CHECK_TRUE(service.loadChunk(tables::TableId::kEstimatorNoise, 0, image.data(), image.size()).ok());
    CHECK_TRUE(service.validate(tables::TableId::kEstimatorNoise).ok());
    CHECK_TRUE(service.activate(tables::TableId::kEstimatorNoise).ok());
    service.run(core::FrameContext{});
}

}  // namespace

// Fewer outliers in a row than fix_reject_limit are refused and move nothing;
// the limit'th refusal marks the estimate inconsistent, the next fix re-anchors
// it, and a fix passing the gate after that makes it consistent again.
TEST(PoseEstimatorTask, FixesRefusedInARowMarkTheEstimateInconsistentAndTheNextReanchorsIt) {
    const unsigned limit = tables.estimatorNoise().fix_reject_limit;
    LONGS_EQUAL(3, limit);
    initialiseAt(0.0, 0.0, 0.0);
    runFrames(99);
    for (unsigned i = 0; i + 1 < limit; ++i) {  // a short burst of outliers: refused, nothing else
        publishFix(2.0, 0.0, 0.0, 0.05);
        runFrames(100);
    }
    LONGS_EQUAL(limit - 1, lastPublished.consecutiveFixRejections);
    LONGS_EQUAL(0, lastPublished.inconsistent);
    publishFix(0.0, 0.0, 0.0, 0.05);
    runFrames(100);
    LONGS_EQUAL(0, lastPublished.consecutiveFixRejections);
    LONGS_EQUAL(0, eventsWithId(ev::kFixesInconsistent));

    // The source now says the rover is 2 m east, fix after fix.
    const estimator::PoseState before = task.filter().state();
    for (unsigned i = 0; i < limit; ++i) {
        publishFix(2.0, 0.0, 0.0, 0.05);
        runFrame();
        LONGS_EQUAL(i + 1, lastPublished.consecutiveFixRejections);
        LONGS_EQUAL(i + 1 == limit ? 1 : 0, lastPublished.inconsistent);
        runFrames(99);
    }
    CHECK_TRUE(before == task.filter().state());  // refused fixes never move it
    const test::DrainedEvents flagged = test::drainEvents(events, ev::kFixesInconsistent);
    LONGS_EQUAL(1, flagged.count);
    CHECK_TRUE(flagged.text.find("3 fixes refused in a row") != std::string::npos);

    publishFix(2.0, 0.0, 0.0, 0.05);  // re-anchors: taken without the gate
    runFrame();
    DOUBLES_EQUAL(2.0, task.filter().x(), 1e-9);
    LONGS_EQUAL(1, lastPublished.reanchors);
    LONGS_EQUAL(0, lastPublished.consecutiveFixRejections);
    LONGS_EQUAL(1, lastPublished.inconsistent);  // not confirmed yet
    const test::DrainedEvents reanchored = test::drainEvents(events, ev::kPoseReanchored);
    LONGS_EQUAL(1, reanchored.count);
    CHECK_TRUE(reanchored.text.find("moved 2.00 m") != std::string::npos);
    // Position and heading as at initialisation; the bias sigma back to its initial value.
    const double floor = static_cast<double>(tables.estimatorNoise().position_fix_sigma_floor_m);
    const double biasSigma = static_cast<double>(tables.estimatorNoise().initial_gyro_bias_sigma_rad_s);
    DOUBLES_EQUAL(0.05 * 0.05, task.filter().covariance()(0, 0), 1e-12);
    CHECK_TRUE(floor < 0.05);
    DOUBLES_EQUAL(biasSigma * biasSigma, task.filter().covariance()(3, 3), 1e-12);

    runFrames(99);
    publishFix(2.0, 0.0, 0.0, 0.05);  // agrees with the re-anchored estimate: consistent again
    runFrame();
    LONGS_EQUAL(0, lastPublished.inconsistent);
    LONGS_EQUAL(1, eventsWithId(ev::kFixesConsistent));
}

// The failure the limit exists for: a gyro bias step far beyond what the bias
// walk lets the filter follow. Standing still at the origin, the IMU suddenly
// reads 0.02 rad/s. Without recovery every fix is refused from then on; with
// it the filter re-anchors, re-estimates the bias and takes the fixes again.
TEST(PoseEstimatorTask, AfterABiasStepItReanchorsReestimatesTheBiasAndTakesTheFixesAgain) {
    initialiseAt(0.0, 0.0, 0.0);
    for (int s = 0; s < 300; ++s) {  // five minutes of fixes: the bias sigma shrinks
        runFrames(99);
        publishFix(0.0, 0.0, 0.0, 0.05);
        runFrame();
    }
    CHECK_TRUE(std::sqrt(task.filter().covariance()(3, 3)) < 0.001);
    imuRate = 0.02;
    std::uint32_t worstRun = 0;
    for (int s = 0; s < 120; ++s) {
        runFrames(99);
        publishFix(0.0, 0.0, 0.0, 0.05);
        runFrame();
        worstRun = std::max(worstRun, lastPublished.consecutiveFixRejections);
    }
    CHECK_TRUE(task.counters().fixesRejected >= tables.estimatorNoise().fix_reject_limit);
    LONGS_EQUAL(tables.estimatorNoise().fix_reject_limit, worstRun);
    CHECK_TRUE(lastPublished.reanchors >= 1);
    LONGS_EQUAL(0, lastPublished.inconsistent);
    DOUBLES_EQUAL(0.02, task.filter().gyroBias(), 0.001);
    DOUBLES_EQUAL(0.0, task.filter().heading(), 0.01);
    // The last minute: every fix taken.
    const std::uint32_t rejected = task.counters().fixesRejected;
    for (int s = 0; s < 60; ++s) {
        runFrames(99);
        publishFix(0.0, 0.0, 0.0, 0.05);
        runFrame();
    }
    LONGS_EQUAL(rejected, task.counters().fixesRejected);
}

TEST(PoseEstimatorTask, TheRejectLimitIsReadFromTheActiveTable) {
    tables::EstimatorNoiseTable t = tables.estimatorNoise();
    t.fix_reject_limit = 5;
    activateNoise(tables, t);
    initialiseAt(0.0, 0.0, 0.0);
    for (int i = 0; i < 4; ++i) {
        publishFix(2.0, 0.0, 0.0, 0.05);
        runFrames(100);
    }
    LONGS_EQUAL(4, lastPublished.consecutiveFixRejections);
    LONGS_EQUAL(0, lastPublished.inconsistent);
    publishFix(2.0, 0.0, 0.0, 0.05);
    runFrame();
    LONGS_EQUAL(1, lastPublished.inconsistent);
}
