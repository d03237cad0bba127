// The health task on the bus: FaultStatusMsg publication, malformed and
// non-finite inputs, and no heap after init.
#include <cmath>
#include <cstdint>
#include <limits>

#include "fsw/core/clock.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/msg_ids.hpp"
#include "unit_test/fsw/estimator/health_test_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::HealthRig;
namespace ev = estimator::events;
namespace fault = msg::fault;

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}

TEST_GROUP(HealthStatus) {
    HealthRig rig;
    void setup() override { CHECK(rig.init()); }
};

TEST(HealthStatus, PublishedInTheFirstRunThenOncePerSecondWhileNothingChanges) {
    rig.step();
    LONGS_EQUAL(1, rig.statusSeen);
    LONGS_EQUAL(HealthRig::kEpoch, rig.lastStatus.timeNs);
    rig.steps(99);
    LONGS_EQUAL(1, rig.statusSeen);
    rig.step();  // the 101st run
    LONGS_EQUAL(2, rig.statusSeen);
    LONGS_EQUAL(HealthRig::kEpoch + 100 * HealthRig::kFrame, rig.lastStatus.timeNs);
    rig.steps(300);
    LONGS_EQUAL(5, rig.statusSeen);
    LONGS_EQUAL(5, rig.health.statusPublished());
    CHECK(rig.lastStatus.activeMask == 0);
    LONGS_EQUAL(0, rig.lastStatus.lastFaultId);
    LONGS_EQUAL(0, rig.lastStatus.raisedTotal);
}

TEST(HealthStatus, PublishedInTheFrameAFaultIsRaisedOrCleared) {
    rig.steps(50);
    const std::uint32_t before = rig.statusSeen;
    rig.feed.alive[0] = false;  // wheel FL, fault 1
    const core::TimeNs raisedAt = rig.stepUntil(fault::kDriveHeartbeatLost, true, 100);
    LONGS_EQUAL(before + 1, rig.statusSeen);
    LONGS_EQUAL(raisedAt, rig.lastStatusTime);
    CHECK(rig.lastStatus.activeMask == (std::uint64_t{1} << fault::kDriveHeartbeatLost));
    LONGS_EQUAL(fault::kDriveHeartbeatLost, rig.lastStatus.lastFaultId);
    LONGS_EQUAL(1, rig.lastStatus.lastRaised);
    LONGS_EQUAL(1, rig.lastStatus.raisedTotal);
    LONGS_EQUAL(0, rig.lastStatus.clearedTotal);

    rig.steps(99);  // no change: nothing until a second has passed
    LONGS_EQUAL(before + 1, rig.statusSeen);
    rig.step();
    LONGS_EQUAL(before + 2, rig.statusSeen);
    CHECK(rig.lastStatus.activeMask == (std::uint64_t{1} << fault::kDriveHeartbeatLost));

    rig.feed.alive[0] = true;
    const core::TimeNs clearedAt = rig.stepUntil(fault::kDriveHeartbeatLost, false, 20);
    LONGS_EQUAL(before + 3, rig.statusSeen);
    LONGS_EQUAL(clearedAt, rig.lastStatusTime);
    CHECK(rig.lastStatus.activeMask == 0);
    LONGS_EQUAL(fault::kDriveHeartbeatLost, rig.lastStatus.lastFaultId);
    LONGS_EQUAL(0, rig.lastStatus.lastRaised);
    LONGS_EQUAL(1, rig.lastStatus.clearedTotal);
}

TEST(HealthStatus, SeveralFaultsAtOnceShowInTheMask) {
    rig.steps(20);
    rig.feed.drives.wheels[1].currentA = 10.0;
    rig.feed.power.busCurrentA = 50.0;
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kAfterRow, false)));
    rig.steps(30);
    const std::uint64_t expected = (std::uint64_t{1} << 12) | (std::uint64_t{1} << fault::kBusOvercurrent) |
                                   (std::uint64_t{1} << (fault::kTaskStalled + HealthRig::kAfterRow));
    CHECK(rig.lastStatus.activeMask == expected);
    CHECK(rig.health.status().activeMask == expected);
    LONGS_EQUAL(3, rig.lastStatus.raisedTotal);
}

TEST_GROUP(HealthInputs) {
    HealthRig rig;
    void setup() override {
        CHECK(rig.init());
        rig.steps(20);
    }
};

TEST(HealthInputs, AMessageThatDoesNotDecodeIsCountedEventedAndIgnored) {
    const std::uint8_t junk[10] = {};
    CHECK(core::isOk(rig.bus.publish(msg::ids::kDriveStatus, junk, sizeof junk)));
    CHECK(core::isOk(rig.bus.publish(msg::ids::kPower, junk, sizeof junk)));
    rig.step();
    LONGS_EQUAL(2, rig.health.malformedMessages());
    LONGS_EQUAL(2, rig.eventCount(ev::kHealthInputRejected));  // 1st and 2nd occurrence
    STRCMP_CONTAINS("health: bus message 0x0121 (10 B) on pipe health refused",  // core::InputPipe's wording
                    rig.event(ev::kHealthInputRejected).lastText);
    CHECK(core::Severity::kWarning == rig.event(ev::kHealthInputRejected).lastSeverity);
    CHECK(rig.health.status().activeMask == 0);

    for (int i = 0; i < 30; ++i) {
        CHECK(core::isOk(rig.bus.publish(msg::ids::kPoseEstimate, junk, sizeof junk)));
        rig.step();
    }
    LONGS_EQUAL(32, rig.health.malformedMessages());
    LONGS_EQUAL(6, rig.eventCount(ev::kHealthInputRejected));  // 1, 2, 4, 8, 16, 32: rate limited
}

TEST(HealthInputs, ANonFiniteCurrentCarriesNoInformationTheFaultKeepsItsState) {
    rig.feed.drives.wheels[0].currentA = 10.0;
    CHECK(rig.stepUntil(11, true, 20) > 0);
    rig.feed.drives.wheels[0].currentA = kNaN;
    rig.steps(100);
    CHECK(rig.health.active(11));
    LONGS_EQUAL(100, rig.health.nonFiniteInputs());
    LONGS_EQUAL(7, rig.eventCount(ev::kHealthInputRejected));  // 1, 2, 4 .. 64
    STRCMP_CONTAINS("FL drive currentA not finite", rig.event(ev::kHealthInputRejected).lastText);
    rig.feed.drives.wheels[0].currentA = 0.0;
    CHECK(rig.stepUntil(11, false, 20) > 0);

    // Nor does it raise a clear fault.
    rig.feed.drives.wheels[0].currentA = std::numeric_limits<double>::infinity();
    rig.steps(100);
    CHECK_FALSE(rig.health.active(11));
    LONGS_EQUAL(1, rig.health.raisedCount(11));
}

TEST(HealthInputs, NonFinitePowerAndPoseValuesAreIgnored) {
    rig.feed.power.busVoltageV = 20.0;
    CHECK(rig.stepUntil(fault::kBatteryLow, true, 50) > 0);
    rig.feed.power.busVoltageV = kNaN;
    rig.feed.power.busCurrentA = kNaN;
    rig.steps(100);  // ten samples
    CHECK(rig.health.active(fault::kBatteryLow));
    LONGS_EQUAL(20, rig.health.nonFiniteInputs());
    rig.feed.power.busVoltageV = 20.0;
    rig.feed.power.busCurrentA = 5.0;

    rig.feed.pose.positionSigmaM = 3.0;
    CHECK(rig.stepUntil(fault::kPoseUncertain, true, 5) > 0);
    rig.feed.pose.positionSigmaM = kNaN;
    rig.steps(10);
    rig.feed.pose.positionSigmaM = -1.0;  // a sigma is never negative
    rig.steps(10);
    CHECK(rig.health.active(fault::kPoseUncertain));
    LONGS_EQUAL(40, rig.health.nonFiniteInputs());
}

TEST_GROUP(HealthMemory) {
    HealthRig rig;
    void setup() override { CHECK(rig.init()); }
};

TEST(HealthMemory, TenThousandFramesWithFaultsComingAndGoingAllocateNothing) {
    rig.step();  // first-use costs of the executive and the event log, outside the watch
    test::AllocationWatch watch;
    for (int frame = 0; frame < 10000; ++frame) {
        const int phase = frame % 500;
        const int cycle = frame / 500;
        rig.feed.drives.wheels[cycle % 6].currentA = phase < 200 ? 5.0 : 0.0;
        rig.feed.power.busVoltageV = phase < 300 ? 22.0 : 28.0;
        rig.feed.power.busCurrentA = phase >= 100 && phase < 250 ? 30.0 : 5.0;
        rig.feed.pose.positionSigmaM = phase >= 50 && phase < 150 ? 2.0 : 0.2;
        rig.feed.alive[cycle % 10] = phase >= 400;
        (void)rig.exec.setTaskEnabled(HealthRig::kWorkerRow, !(phase >= 320 && phase < 380));
        rig.step();
    }
    const auto allocations = watch.count();
    LONGS_EQUAL(0, allocations);
    // The faults really came and went (so "no allocation" covers the event paths).
    CHECK(rig.health.status().raisedTotal >= 20 * 6);
    CHECK(rig.health.status().clearedTotal >= 20 * 5);
    CHECK(rig.eventCount(ev::kHealthBatteryLow) == 20);
    CHECK(rig.eventCount(ev::kHealthTaskStalled) == 20);
    CHECK(rig.eventCount(ev::kHealthDriveHeartbeatLost) + rig.eventCount(ev::kHealthDeviceHeartbeatLost) == 20);
    CHECK(rig.health.statusPublished() > 100);
    LONGS_EQUAL(0, rig.bus.stats().dropped);
}
