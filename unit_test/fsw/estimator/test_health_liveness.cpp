// Heartbeat-loss and task-stall faults, at their documented times.
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/estimator/health_task.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/fsw/estimator/health_test_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::HealthRig;
namespace ev = estimator::events;

namespace {
constexpr core::TimeNs kFrame = HealthRig::kFrame;
}

TEST_GROUP(HealthHeartbeat) {
    HealthRig rig;
    core::TimeNs timeout = 0;
    void setup() override {
        CHECK(rig.init());
        timeout = static_cast<core::TimeNs>(rig.tables.canNodeMap().heartbeat_timeout_ms) * core::kNsPerMs;
        rig.steps(50);  // every node heard
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }
};

TEST(HealthHeartbeat, DriveHeartbeatLossRaisesItsOwnFaultWithinTheBoundAndClearsWhenItIsBack) {
    rig.feed.alive[2] = false;  // wheel RL, fault 3
    const core::TimeNs lastHeard = rig.feed.lastHeartbeat[2];
    const core::TimeNs raisedAt = rig.stepUntil(3, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - lastHeard > timeout);                // not before the consumer's timeout
    CHECK(raisedAt - lastHeard <= timeout + 2 * kFrame);  // documented: timeout + 20 ms
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << 3));
    LONGS_EQUAL(1, rig.health.raisedCount(3));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveHeartbeatLost));
    LONGS_EQUAL(raisedAt, rig.event(ev::kHealthDriveHeartbeatLost).lastTime);
    CHECK(core::Severity::kError == rig.event(ev::kHealthDriveHeartbeatLost).lastSeverity);
    STRCMP_CONTAINS("health: fault 3: drive RL", rig.event(ev::kHealthDriveHeartbeatLost).lastText);

    rig.steps(30);
    CHECK(rig.health.active(3));
    rig.feed.alive[2] = true;
    const core::TimeNs clearedAt = rig.stepUntil(3, false, 20);
    LONGS_EQUAL(rig.feed.lastHeartbeat[2], clearedAt);  // in the frame its heartbeat is read
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveHeartbeatRestored));
    CHECK(core::Severity::kInfo == rig.event(ev::kHealthDriveHeartbeatRestored).lastSeverity);
    STRCMP_CONTAINS("fault 3 cleared: drive RL", rig.event(ev::kHealthDriveHeartbeatRestored).lastText);
    LONGS_EQUAL(0, rig.health.status().activeMask);
}

TEST(HealthHeartbeat, DeviceHeartbeatLossRaisesTheDevicesFault) {
    rig.feed.alive[9] = false;  // DeviceNode::kPositionFix, fault 10
    const core::TimeNs lastHeard = rig.feed.lastHeartbeat[9];
    const core::TimeNs raisedAt = rig.stepUntil(10, true, 100);
    CHECK(raisedAt - lastHeard > timeout);
    CHECK(raisedAt - lastHeard <= timeout + 2 * kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << 10));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDeviceHeartbeatLost));
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthDriveHeartbeatLost));
    STRCMP_CONTAINS("fault 10: device position fix", rig.event(ev::kHealthDeviceHeartbeatLost).lastText);

    rig.feed.alive[9] = true;
    const core::TimeNs clearedAt = rig.stepUntil(10, false, 20);
    LONGS_EQUAL(rig.feed.lastHeartbeat[9], clearedAt);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDeviceHeartbeatRestored));
}

TEST(HealthHeartbeat, EveryNodeMapsToItsFaultId) {
    for (std::size_t i = 0; i < msg::kMonitoredNodeCount; ++i) {
        rig.feed.alive[i] = false;
        const auto id = static_cast<std::uint8_t>(i < 6 ? msg::fault::kDriveHeartbeatLost + i
                                                         : msg::fault::kDeviceHeartbeatLost + (i - 6));
        CHECK(rig.stepUntil(id, true, 100) > 0);
        CHECK(rig.health.status().activeMask == (std::uint64_t{1} << id));
        rig.feed.alive[i] = true;
        CHECK(rig.stepUntil(id, false, 20) > 0);
    }
    LONGS_EQUAL(6, rig.eventCount(ev::kHealthDriveHeartbeatLost));
    LONGS_EQUAL(4, rig.eventCount(ev::kHealthDeviceHeartbeatLost));
}

TEST_GROUP(HealthTaskStall) {
    HealthRig rig;
    core::TimeNs stallPeriods = 0;
    void setup() override {
        CHECK(rig.init());
        stallPeriods = rig.tables.faultResponse().task_stall_periods;
    }
};

TEST(HealthTaskStall, ADisabledTaskIsStalledAfterItsPeriodsAndClearsInTheFrameItRunsAgain) {
    rig.steps(20);
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kWorkerRow, false)));
    const core::TimeNs lastRun = rig.exec.taskLiveness(HealthRig::kWorkerRow)->lastRunEnd;
    const core::TimeNs limit = stallPeriods * kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(21, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - lastRun > limit);
    CHECK(raisedAt - lastRun <= limit + kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << 21));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthTaskStalled));
    CHECK(core::Severity::kError == rig.event(ev::kHealthTaskStalled).lastSeverity);
    STRCMP_CONTAINS("fault 21: task worker stalled", rig.event(ev::kHealthTaskStalled).lastText);
    STRCMP_CONTAINS("disabled", rig.event(ev::kHealthTaskStalled).lastText);

    rig.steps(50);
    CHECK(rig.health.active(21));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthTaskStalled));
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kWorkerRow, true)));
    rig.step();  // its row is above the health task's: seen running in the same frame
    CHECK_FALSE(rig.health.active(21));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthTaskStalledCleared));
    STRCMP_CONTAINS("fault 21 cleared: task worker", rig.event(ev::kHealthTaskStalledCleared).lastText);
}

TEST(HealthTaskStall, ATaskBelowTheHealthTaskClearsInTheFrameAfterItRunsAgain) {
    rig.steps(20);
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kAfterRow, false)));
    const core::TimeNs lastRun = rig.exec.taskLiveness(HealthRig::kAfterRow)->lastRunEnd;
    const core::TimeNs raisedAt = rig.stepUntil(24, true, 100);
    CHECK(raisedAt - lastRun > stallPeriods * kFrame);
    CHECK(raisedAt - lastRun <= stallPeriods * kFrame + kFrame);
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kAfterRow, true)));
    rig.step();
    CHECK(rig.health.active(24));
    rig.step();
    CHECK_FALSE(rig.health.active(24));
}

TEST(HealthTaskStall, ASlowerTaskIsJudgedOnItsOwnPeriod) {
    rig.steps(11);  // the 10 Hz row ran in frame 10
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kSlowRow, false)));
    const core::TimeNs lastRun = rig.exec.taskLiveness(HealthRig::kSlowRow)->lastRunEnd;
    const core::TimeNs period = 10 * kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(23, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - lastRun > stallPeriods * period);
    CHECK(raisedAt - lastRun <= stallPeriods * period + kFrame);
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kSlowRow, true)));
    const core::TimeNs clearedAt = rig.stepUntil(23, false, 20);
    // Its row is below the health task's: seen in the frame after it ran.
    LONGS_EQUAL(rig.exec.taskLiveness(HealthRig::kSlowRow)->lastRunEnd + kFrame, clearedAt);
}

TEST(HealthTaskStall, ATaskThatNeverRanIsMeasuredFromTheHealthTasksFirstRun) {
    CHECK(core::isOk(rig.exec.setTaskEnabled(HealthRig::kWorkerRow, false)));
    const core::TimeNs raisedAt = rig.stepUntil(21, true, 20);
    CHECK(raisedAt - HealthRig::kEpoch > stallPeriods * kFrame);
    CHECK(raisedAt - HealthRig::kEpoch <= stallPeriods * kFrame + kFrame);
}

TEST(HealthTaskStall, RunningTasksAreNeverStalled) {
    rig.steps(1000);
    LONGS_EQUAL(0, rig.health.status().activeMask);
    LONGS_EQUAL(0, rig.eventCount(ev::kHealthTaskStalled));
    CHECK(rig.slow.runs == 100);
}

// The health task alone in an executive whose rows never run: it would see its
// own row silent too, so this shows the skip.
TEST_GROUP(HealthSelf) {
    core::VirtualClock clock{HealthRig::kEpoch};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    core::Executive exec{clock, events};
    test::IdleTask idle;
};

TEST(HealthSelf, TheHealthTaskDoesNotWatchItsOwnRow) {
    CHECK(core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
    estimator::HealthTask health(bus, events, tables, exec);
    CHECK(core::isOk(health.init()));
    const core::RateGroupEntry table[] = {{"health", &health, 1, 0, 1000}, {"idle", &idle, 1, 0, 1000}};
    CHECK(core::isOk(exec.init(core::ExecutiveConfig{}, table, 2)));
    core::FrameContext frame;
    for (int i = 0; i < 100; ++i) {
        frame.frame = static_cast<std::uint64_t>(i);
        frame.actualStart = clock.now();
        frame.scheduledStart = frame.actualStart;
        health.run(frame);
        clock.advance(kFrame);
    }
    CHECK(health.active(msg::fault::kTaskStalled + 1));  // the idle row, never run: the rule works here
    CHECK_FALSE(health.active(msg::fault::kTaskStalled + 0));
    LONGS_EQUAL(0, health.raisedCount(msg::fault::kTaskStalled + 0));
}
