// What rse-demo's watch takes from the flight software (sim_stub/lockstep/
// flight_watch.hpp), fed by hand on a bus and an event log of its own: the
// latest plan status, plan executive status and mode; the plan executive's
// refusal and the call home in the flight software's words; when a goal or a
// plan mission has ended; and fault protection's marks, each named (fault id,
// wheel) by the telemetry published in the frame of its event and by nothing
// else: not a message of another frame, not a raise count that does not add up.
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "sim_stub/lockstep/flight_watch.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MarkKind;
using sim::MissionMark;
using sim::MissionSummary;

namespace fp = fault_protection::events;
namespace pe = plan_executive::events;
namespace health = estimator::events;

namespace {

constexpr std::uint8_t kWheel2Lost = msg::fault::kDriveHeartbeatLost + 2;  // fault id 3

void checkMark(const MissionMark& m, MarkKind kind, std::uint16_t eventId, double timeS, std::uint8_t faultId,
               std::uint8_t wheel) {
    CHECK(kind == m.kind);
    LONGS_EQUAL(eventId, m.eventId);
    DOUBLES_EQUAL(timeS, m.timeS, 1e-9);
    LONGS_EQUAL(faultId, m.faultId);
    LONGS_EQUAL(wheel, m.wheel);
}

}  // namespace

TEST_GROUP(FlightWatch) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    sim::FlightWatch* watch = nullptr;
    MissionSummary summary;

    void setup() override {
        watch = new sim::FlightWatch(bus, events);
        CHECK_TRUE(watch->subscribe());
    }
    void teardown() override { delete watch; }

    // The start of a frame at `ms` milliseconds of flight time.
    void at(core::TimeNs ms) {
        clock.sleepUntil(ms * core::kNsPerMs);
    }
    core::TimeNs now() const { return clock.now(); }
    template <typename T>
    void publish(const T& m) {
        CHECK(core::isOk(bus.publish(m)));
    }
    void publishRaised(std::uint64_t mask, std::uint32_t raisedTotal) {
        msg::FaultStatusMsg f{};
        f.timeNs = now();
        f.activeMask = mask;
        f.raisedTotal = raisedTotal;
        publish(f);
    }
    void publishHold(std::uint32_t reasons, std::uint32_t resumeCount) {
        msg::MissionHoldMsg h{};
        h.timeNs = now();
        h.reasons = reasons;
        h.resumeCount = resumeCount;
        publish(h);
    }
    const MissionSummary& filled() {
        watch->fill(&summary);
        return summary;
    }
};

TEST(FlightWatch, TheLatestPlanStatusExecutiveStatusAndModeAreKept) {
    CHECK_FALSE(watch->modeIs(0));  // no mode seen yet (the zeroed 0 is not SAFE)
    msg::PlanStatusMsg plan{};
    plan.state = msg::DeliberativeState::kPlanning;
    publish(plan);
    plan.state = msg::DeliberativeState::kExecuting;
    plan.plansMade = 2;
    publish(plan);
    msg::PlanExecutiveStatusMsg exec{};
    exec.state = msg::PlanExecutiveState::kDispatching;
    exec.plansAccepted = 1;
    publish(exec);
    msg::ModeMsg mode{};
    mode.mode = msg::mode::kAutonomous;
    publish(mode);
    watch->drain();
    CHECK(msg::DeliberativeState::kExecuting == watch->plan().state);
    LONGS_EQUAL(2, watch->plan().plansMade);
    CHECK(msg::PlanExecutiveState::kDispatching == watch->planExec().state);
    LONGS_EQUAL(1, watch->planExec().plansAccepted);
    CHECK_TRUE(watch->modeIs(msg::mode::kAutonomous));
    CHECK_FALSE(watch->modeIs(msg::mode::kSafe));
    LONGS_EQUAL(msg::mode::kAutonomous, watch->mode());
    // A plan status that does not decode (cut short) changes nothing.
    const std::uint8_t cut[4] = {};
    CHECK(core::isOk(bus.publish(msg::ids::kPlanStatus, cut, sizeof cut)));
    watch->drain();
    CHECK(msg::DeliberativeState::kExecuting == watch->plan().state);
}

// A goal mission ends with the deliberative layer's COMPLETE or CALLED HOME;
// a plan mission with the executive's complete or failed (the deliberative
// layer's call home fails one drive, which the plan may redo); either with
// fault protection's call home.
TEST(FlightWatch, WhenAGoalAndAPlanMissionHaveEnded) {
    msg::PlanStatusMsg plan{};
    plan.state = msg::DeliberativeState::kCalledHome;
    publish(plan);
    watch->drain();
    CHECK_TRUE(watch->ended(false));
    CHECK_FALSE(watch->ended(true));
    msg::PlanExecutiveStatusMsg exec{};
    exec.state = msg::PlanExecutiveState::kFailed;
    publish(exec);
    plan.state = msg::DeliberativeState::kComplete;
    publish(plan);
    watch->drain();
    CHECK_TRUE(watch->ended(false));
    CHECK_TRUE(watch->ended(true));
    exec.state = msg::PlanExecutiveState::kComplete;
    publish(exec);
    plan.state = msg::DeliberativeState::kExecuting;
    publish(plan);
    watch->drain();
    CHECK_FALSE(watch->ended(false));
    CHECK_TRUE(watch->ended(true));
    exec.state = msg::PlanExecutiveState::kDispatching;
    publish(exec);
    watch->drain();
    CHECK_FALSE(watch->ended(true));
    events.report(fp::kCallHome, core::Severity::kCritical, "fault protection: CALL HOME (drive lost)");
    watch->drain();
    CHECK_TRUE(watch->faultProtectionCalledHome());
    CHECK_TRUE(watch->ended(false));
    CHECK_TRUE(watch->ended(true));
}

// The executive's latest refusal (952, 953 or 954) in its own words, and the
// call home in the flight software's words: the deliberative layer's reason
// without the goal counts after it; a give-up's reason is kept over fault
// protection's call home that follows it.
TEST(FlightWatch, TheRefusalAndTheCallHomeAreInTheFlightSoftwaresWords) {
    events.report(pe::kUploadRefused, core::Severity::kError, "plan_exec: PLAN_START refused: bad CRC");
    watch->drain();
    STRCMP_EQUAL("plan_exec: PLAN_START refused: bad CRC", watch->planRefusal().c_str());
    events.report(pe::kSelectionRefused, core::Severity::kError, "plan_exec: plan p refused: no valid selection");
    events.report(pe::kPlanAccepted, core::Severity::kInfo, "plan_exec: plan q accepted");
    watch->drain();
    STRCMP_EQUAL("plan_exec: plan p refused: no valid selection", watch->planRefusal().c_str());

    events.report(deliberative::events::kCallHome, core::Severity::kCritical,
                  "deliberative: CALL HOME: no plan within the risk limit, goal 0, risk 0.002");
    watch->drain();
    STRCMP_EQUAL("no plan within the risk limit", watch->callHomeText().c_str());
    CHECK_FALSE(watch->faultProtectionCalledHome());
    events.report(fp::kGaveUp, core::Severity::kCritical, "fault_prot: gave up on wheel 2 after 3 attempts");
    events.report(fp::kCallHome, core::Severity::kCritical, "fault_prot: CALL HOME: fault unrecovered");
    watch->drain();
    STRCMP_EQUAL("fault_prot: gave up on wheel 2 after 3 attempts", watch->callHomeText().c_str());
    CHECK_TRUE(watch->faultProtectionCalledHome());
}

// A drive lost and recovered, as fault protection handles it frame by frame:
// each mark named by the telemetry of its own frame; the counts, times and
// hold from the events and MissionHoldMsg.
TEST(FlightWatch, EachMarkIsNamedByTheTelemetryOfItsFrame) {
    at(10000);  // wheel 2's heartbeat lost: fault id 3 newly active, one raise
    publishRaised(std::uint64_t{1} << kWheel2Lost, 1);
    events.report(health::kHealthDriveHeartbeatLost, core::Severity::kWarning, "health: drive 2 lost");
    watch->drain();
    at(10010);  // fault protection answers: its status lists the response, the hold set
    msg::FaultProtectionStatusMsg status{};
    status.timeNs = now();
    status.responsesStarted = 1;
    status.activeCount = 1;
    status.responses[0].faultId = kWheel2Lost;
    status.responses[0].state = msg::ResponseState::kWaiting;
    publish(status);
    publishHold(1, 0);
    events.report(fp::kResponseStarted, core::Severity::kWarning, "fault_prot: response to wheel 2");
    watch->drain();
    at(10500);  // a fault reset of drive 2
    msg::DriveRecoveryMsg reset{};
    reset.timeNs = now();
    reset.wheel = 2;
    reset.action = msg::DriveRecoveryAction::kFaultReset;
    publish(reset);
    events.report(fp::kDriveAction, core::Severity::kWarning, "fault_prot: wheel 2 fault reset 1 of 3");
    watch->drain();
    at(12000);  // recovered: the hold released
    publishHold(0, 1);
    events.report(fp::kRecovered, core::Severity::kInfo, "fault_prot: wheel 2 recovered");
    watch->drain();
    at(15000);  // a task restart of row 4: fault id 20 + 4
    msg::TaskRestartMsg restart{};
    restart.timeNs = now();
    restart.row = 4;
    publish(restart);
    events.report(fp::kTaskRestart, core::Severity::kWarning, "fault_prot: row 4 restarted");
    watch->drain();
    at(16000);  // off the map: a replan from the pose
    msg::ReplanRequestMsg replan{};
    replan.timeNs = now();
    replan.faultId = msg::fault::kOffMap;
    publish(replan);
    events.report(fp::kReplanRequested, core::Severity::kWarning, "fault_prot: replan from the pose");
    watch->drain();

    const MissionSummary& s = filled();
    LONGS_EQUAL(7, s.markCount);
    checkMark(s.marks[0], MarkKind::kFaultRaised, health::kHealthDriveHeartbeatLost, 10.0, kWheel2Lost, 2);
    checkMark(s.marks[1], MarkKind::kHoldSet, 0, 10.01, 0, sim::kNoWheel);
    checkMark(s.marks[2], MarkKind::kResponseStarted, fp::kResponseStarted, 10.01, kWheel2Lost, 2);
    checkMark(s.marks[3], MarkKind::kRecoveryAction, fp::kDriveAction, 10.5, kWheel2Lost, 2);
    checkMark(s.marks[4], MarkKind::kHoldReleased, 0, 12.0, 0, sim::kNoWheel);
    checkMark(s.marks[5], MarkKind::kRecoveryAction, fp::kTaskRestart, 15.0, msg::fault::kTaskStalled + 4,
              sim::kNoWheel);
    checkMark(s.marks[6], MarkKind::kRecoveryAction, fp::kReplanRequested, 16.0, msg::fault::kOffMap, sim::kNoWheel);
    LONGS_EQUAL(0, s.marksUnattributed);
    LONGS_EQUAL(0, s.marksDropped);
    LONGS_EQUAL(1, s.responsesStarted);
    LONGS_EQUAL(1, s.responsesRecovered);
    LONGS_EQUAL(0, s.responsesGaveUp);
    LONGS_EQUAL(3, s.recoveryActions);
    LONGS_EQUAL(1, s.holdsReleased);
    DOUBLES_EQUAL(10.01, s.firstResponseTimeS, 1e-9);
    DOUBLES_EQUAL(10.01, s.firstHoldTimeS, 1e-9);
    DOUBLES_EQUAL(12.0, s.lastResumeTimeS, 1e-9);
    CHECK_FALSE(s.faultProtectionCalledHome);
}

// Nothing seen: no marks, the times -1.
TEST(FlightWatch, NoFaultHandlingLeavesTheTimesUnset) {
    watch->drain();
    const MissionSummary& s = filled();
    LONGS_EQUAL(0, s.markCount);
    DOUBLES_EQUAL(-1.0, s.firstResponseTimeS, 0.0);
    DOUBLES_EQUAL(-1.0, s.firstHoldTimeS, 0.0);
    DOUBLES_EQUAL(-1.0, s.lastResumeTimeS, 0.0);
}

// A raise event without telemetry in its frame, one whose fault status came a
// frame earlier, one whose status was drained before it (a frame's telemetry
// and events are read together: nothing is kept for a later drain), and one
// whose status does not add up (two new faults, one raise counted: a status
// was missed) are marked, unnamed, and counted.
TEST(FlightWatch, AMarkNoTelemetryOfItsFrameNamesIsCountedUnattributed) {
    at(1000);
    events.report(health::kHealthBatteryLow, core::Severity::kCritical, "health: battery low");
    watch->drain();
    at(2000);
    publishRaised(std::uint64_t{1} << msg::fault::kBusOvercurrent, 1);
    watch->drain();
    at(2010);
    events.report(health::kHealthBusOvercurrent, core::Severity::kWarning, "health: bus over-current");
    watch->drain();
    at(2500);  // the status drained alone, then an event of the same time in a later drain
    publishRaised((std::uint64_t{1} << msg::fault::kBusOvercurrent) | (std::uint64_t{1} << msg::fault::kPoseUncertain),
                  2);
    watch->drain();
    events.report(health::kHealthPoseUncertain, core::Severity::kWarning, "health: pose uncertain");
    watch->drain();
    at(3000);  // two new faults, one raise counted
    publishRaised((std::uint64_t{1} << msg::fault::kBusOvercurrent) | (std::uint64_t{1} << msg::fault::kPoseUncertain) |
                      (std::uint64_t{1} << msg::fault::kOffMap) | (std::uint64_t{1} << msg::fault::kSensorStale),
                  3);
    events.report(health::kHealthOffMap, core::Severity::kWarning, "health: off the map");
    watch->drain();
    at(4000);  // in order again: the next raise is named
    publishRaised((std::uint64_t{1} << msg::fault::kBusOvercurrent) | (std::uint64_t{1} << msg::fault::kPoseUncertain) |
                      (std::uint64_t{1} << msg::fault::kOffMap) | (std::uint64_t{1} << msg::fault::kSensorStale) |
                      (std::uint64_t{1} << msg::fault::kBatteryLow),
                  4);
    events.report(health::kHealthBatteryLow, core::Severity::kCritical, "health: battery low");
    watch->drain();
    const MissionSummary& s = filled();
    LONGS_EQUAL(5, s.markCount);
    LONGS_EQUAL(4, s.marksUnattributed);
    checkMark(s.marks[0], MarkKind::kFaultRaised, health::kHealthBatteryLow, 1.0, 0, sim::kNoWheel);
    checkMark(s.marks[1], MarkKind::kFaultRaised, health::kHealthBusOvercurrent, 2.01, 0, sim::kNoWheel);
    checkMark(s.marks[2], MarkKind::kFaultRaised, health::kHealthPoseUncertain, 2.5, 0, sim::kNoWheel);
    checkMark(s.marks[3], MarkKind::kFaultRaised, health::kHealthOffMap, 3.0, 0, sim::kNoWheel);
    checkMark(s.marks[4], MarkKind::kFaultRaised, health::kHealthBatteryLow, 4.0, msg::fault::kBatteryLow,
              sim::kNoWheel);
}

// Two drives lost in one frame: one raise event each, in ascending fault id,
// each named by its own id and wheel.
TEST(FlightWatch, TwoRaisesInOneFrameAreNamedInTheHealthMonitorsOrder) {
    at(5000);
    publishRaised((std::uint64_t{1} << (msg::fault::kDriveOvercurrent + 1)) |
                      (std::uint64_t{1} << (msg::fault::kDriveOvercurrent + 4)),
                  2);
    events.report(health::kHealthDriveOvercurrent, core::Severity::kWarning, "health: drive 1 over-current");
    events.report(health::kHealthDriveOvercurrent, core::Severity::kWarning, "health: drive 4 over-current");
    watch->drain();
    const MissionSummary& s = filled();
    LONGS_EQUAL(2, s.markCount);
    checkMark(s.marks[0], MarkKind::kFaultRaised, health::kHealthDriveOvercurrent, 5.0,
              msg::fault::kDriveOvercurrent + 1, 1);
    checkMark(s.marks[1], MarkKind::kFaultRaised, health::kHealthDriveOvercurrent, 5.0,
              msg::fault::kDriveOvercurrent + 4, 4);
    LONGS_EQUAL(0, s.marksUnattributed);
}

// The first kMissionMarks marks are kept; the rest are counted.
TEST(FlightWatch, MarksBeyondTheTableAreCountedAsDropped) {
    for (std::uint32_t i = 0; i < 300; ++i) {
        at(100 + 10 * static_cast<core::TimeNs>(i));
        publishHold(i % 2 == 0 ? 1U : 0U, (i + 1) / 2);
        watch->drain();
    }
    const MissionSummary& s = filled();
    LONGS_EQUAL(sim::kMissionMarks, s.markCount);
    LONGS_EQUAL(300 - sim::kMissionMarks, s.marksDropped);
    CHECK(MarkKind::kHoldSet == s.marks[0].kind);
    CHECK(MarkKind::kHoldReleased == s.marks[255].kind);
    LONGS_EQUAL(150, s.holdsReleased);
}
