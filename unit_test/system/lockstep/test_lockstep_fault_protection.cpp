// Lockstep: whole missions (rse-demo's runner: the flight software and the
// simulator on one virtual clock, SET_MODE AUTONOMOUS and GOTO (20, 0) from the
// ground) with one fault each, injected by the simulator's fault scheduler:
// fault protection's response is seen in its events and its mission hold, and
// the rover reaches its goal where the fault is recoverable (issue 13). The
// demo's own motor faults are left out; each test adds its fault to the demo
// scenario. RSE_PRINT_CONSOLE=1 prints each mission's console.
#include <cstdio>
#include <cstdlib>
#include <string>

#include "fsw/msg/health_msgs.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::FaultSpec;
using sim::FaultType;
using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;
using sim::Scenario;

namespace {

constexpr core::TimeNs kS = core::kNsPerSec;

core::TimeNs at(double seconds) { return static_cast<core::TimeNs>(seconds * 1e9); }

bool printConsole() { return std::getenv("RSE_PRINT_CONSOLE") != nullptr; }

// The demo mission without its faults, plus `faults`; another scenario file when given.
MissionSummary runWith(std::vector<FaultSpec> faults, double durationS = 300.0,
                       const char* scenario = sim::kDefaultMissionScenario) {
    MissionOptions o;
    const char* argv[] = {"rse-demo", "--no-faults", "--scenario", scenario};
    std::string error;
    if (sim::parseMissionArgs(4, argv, &o, &error) != sim::ParseOutcome::kRun) {
        std::printf("\nbad options: %s\n", error.c_str());
        return MissionSummary{};
    }
    o.durationS = durationS;
    o.quiet = !printConsole();
    o.editScenario = [faults](Scenario& s) {
        for (const FaultSpec& f : faults) {
            s.faults.push_back(f);
        }
    };
    return sim::runMission(o, printConsole() ? stdout : nullptr);
}

// A scenario file with its own faults, as rse-demo --scenario runs it.
MissionSummary runScenario(const char* scenario, double durationS = 300.0) {
    MissionOptions o;
    const char* argv[] = {"rse-demo", "--scenario", scenario};
    std::string error;
    if (sim::parseMissionArgs(3, argv, &o, &error) != sim::ParseOutcome::kRun) {
        std::printf("\nbad options: %s\n", error.c_str());
        return MissionSummary{};
    }
    o.durationS = durationS;
    o.quiet = !printConsole();
    return sim::runMission(o, printConsole() ? stdout : nullptr);
}

void report(const char* what, const MissionSummary& s) {
    std::printf("\n  %s: %s at %.1f s (%s), %.2f m from the goal, %u collisions; fault protection: %u responses, "
                "%u recovered, %u gave up, %u actions, %u holds released, first response %.2f s, last resume %.2f s",
                what, sim::toString(s.outcome), s.outcomeTimeS, s.callHomeText.c_str(), s.goalDistanceM,
                static_cast<unsigned>(s.collisions), static_cast<unsigned>(s.responsesStarted),
                static_cast<unsigned>(s.responsesRecovered), static_cast<unsigned>(s.responsesGaveUp),
                static_cast<unsigned>(s.recoveryActions), static_cast<unsigned>(s.holdsReleased), s.firstResponseTimeS,
                s.lastResumeTimeS);
}

void checkReachedAfterResponse(const MissionSummary& s, double faultAtS) {
    CHECK_TRUE_TEXT(s.outcome == MissionOutcome::kGoalReached, s.callHomeText.c_str());
    CHECK(s.goalDistanceM < 0.6);
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.responsesStarted >= 1);
    CHECK(s.responsesRecovered >= 1);
    LONGS_EQUAL(0, s.responsesGaveUp);
    CHECK(s.holdsReleased >= 1);
    CHECK(s.firstHoldTimeS >= faultAtS);
    CHECK(s.lastResumeTimeS > s.firstHoldTimeS);
    LONGS_EQUAL(0, s.marksUnattributed);  // every raise, response and action named its fault (telemetry)
}

FaultSpec wheelFault(FaultType type, std::size_t wheel, double atS, double untilS = -1.0, double value = 0.0) {
    FaultSpec f;
    f.type = type;
    f.wheel = wheel;
    f.at = at(atS);
    f.until = untilS < 0.0 ? sim::kNever : at(untilS);
    f.value = value;
    return f;
}

}  // namespace

TEST_GROUP(LockstepFaultProtection){};

TEST(LockstepFaultProtection, AShortDriveHeartbeatGapIsRiddenOutAndTheGoalReached) {
    const MissionSummary s = runWith({wheelFault(FaultType::kDriveHeartbeatLoss, 2, 20.0, 20.2)});
    report("heartbeat gap 0.2 s on RL at 20 s", s);
    checkReachedAfterResponse(s, 20.0);
}

TEST(LockstepFaultProtection, ADriveThatCrashesAndRestartsIsBroughtBackAndTheGoalReached) {
    const MissionSummary s = runWith({wheelFault(FaultType::kDriveCrash, 4, 20.0, 22.0)});
    report("drive MR crash at 20 s, restart at 22 s", s);
    checkReachedAfterResponse(s, 20.0);
    // The marks name the crashed drive: its heartbeat fault (5 = 1 + wheel 4),
    // the response to it and its node reset.
    const std::uint8_t lost = msg::fault::kDriveHeartbeatLost + 4;
    const sim::MissionMark* raised = s.firstMark(sim::MarkKind::kFaultRaised, 20.0, lost);
    const sim::MissionMark* started = s.firstMark(sim::MarkKind::kResponseStarted, 20.0, lost);
    const sim::MissionMark* reset = s.firstMark(sim::MarkKind::kRecoveryAction, 20.0, lost);
    CHECK(raised != nullptr && started != nullptr && reset != nullptr);
    LONGS_EQUAL(720, raised->eventId);
    LONGS_EQUAL(4, raised->wheel);
    LONGS_EQUAL(4, started->wheel);
    LONGS_EQUAL(931, reset->eventId);
    LONGS_EQUAL(4, reset->wheel);
    DOUBLES_EQUAL(raised->timeS, started->timeS, 1e-9);
    DOUBLES_EQUAL(started->timeS + 0.5, reset->timeS, 0.011);  // FAULT_RESPONSE.heartbeat_loss_ms, then the reset
}

// Two drives in trouble at once: ML (wheel 1) reports a resettable fault
// (EMCY) at 20 s and MR (wheel 4) crashes at 20 s and restarts at 22 s. Fault
// protection sees ML's fault in the drive status at once and MR's loss only
// when its heartbeat times out, about 0.2 s later; the first response and the
// first hold after 20 s are ML's. Each mark names its own drive (from the
// telemetry, not from the order of events), so MR's detection, response,
// hold and node reset can be told from ML's.
TEST(LockstepFaultProtection, TheMarksOfTwoDrivesInTroubleAtOnceNameEachDrive) {
    FaultSpec emcy = wheelFault(FaultType::kDriveFault, 1, 20.0);
    emcy.cobId = 0x2310;
    const MissionSummary s = runWith({emcy, wheelFault(FaultType::kDriveCrash, 4, 20.0, 22.0)});
    report("drive ML fault (EMCY) and drive MR crash at 20 s", s);
    checkReachedAfterResponse(s, 20.0);
    const std::uint8_t ml = msg::fault::kDriveHeartbeatLost + 1;
    const std::uint8_t mr = msg::fault::kDriveHeartbeatLost + 4;
    const sim::MissionMark* first = s.firstMark(sim::MarkKind::kResponseStarted, 20.0);
    const sim::MissionMark* mlStarted = s.firstMark(sim::MarkKind::kResponseStarted, 20.0, ml);
    const sim::MissionMark* mrRaised = s.firstMark(sim::MarkKind::kFaultRaised, 20.0, mr);
    const sim::MissionMark* mrStarted = s.firstMark(sim::MarkKind::kResponseStarted, 20.0, mr);
    const sim::MissionMark* mrReset = s.firstMark(sim::MarkKind::kRecoveryAction, 20.0, mr);
    CHECK(first != nullptr && mlStarted != nullptr && mrRaised != nullptr && mrStarted != nullptr &&
          mrReset != nullptr);
    std::printf("\n    ML response %.2f s; MR heartbeat fault %.2f s, response %.2f s, node reset %.2f s (wheel %u); "
                "held before MR's detection: %s",
                mlStarted->timeS, mrRaised->timeS, mrStarted->timeS, mrReset->timeS,
                static_cast<unsigned>(mrReset->wheel), s.heldBefore(mrRaised->timeS) ? "yes" : "no");
    // The first response after the faults is ML's, in the frame after them.
    CHECK(first == mlStarted);
    LONGS_EQUAL(1, mlStarted->wheel);
    CHECK(mlStarted->timeS < 20.0 + 0.025);
    // MR's own: detected by its heartbeat (720) later, answered in that frame,
    // reset (NMT) once its heartbeat_loss_ms settle is over.
    LONGS_EQUAL(720, mrRaised->eventId);
    CHECK(mrRaised->timeS > mlStarted->timeS + 0.1);
    DOUBLES_EQUAL(mrRaised->timeS, mrStarted->timeS, 1e-9);
    LONGS_EQUAL(4, mrStarted->wheel);
    LONGS_EQUAL(931, mrReset->eventId);
    LONGS_EQUAL(4, mrReset->wheel);
    DOUBLES_EQUAL(mrStarted->timeS + 0.5, mrReset->timeS, 0.011);
    // The hold at MR's detection: already in force (ML's), or set in that frame.
    const sim::MissionMark* hold = s.firstMark(sim::MarkKind::kHoldSet, mrRaised->timeS);
    CHECK(s.heldBefore(mrRaised->timeS) || (hold != nullptr && hold->timeS - mrRaised->timeS < 0.011));
}

TEST(LockstepFaultProtection, ADriveFaultIsResetAndTheGoalReached) {
    FaultSpec f = wheelFault(FaultType::kDriveFault, 0, 25.0);
    f.cobId = 0x2310;  // EMCY: current, device output side
    const MissionSummary s = runWith({f});
    report("drive FL fault (EMCY 0x2310) at 25 s", s);
    checkReachedAfterResponse(s, 25.0);
}

TEST(LockstepFaultProtection, AHazardDetectorDropoutHoldsTheRoverUntilItSeesAgain) {
    FaultSpec f;
    f.type = FaultType::kSensorDropout;
    f.device = sim::SimDevice::kHazard;
    f.at = at(30.0);
    f.until = at(45.0);
    const MissionSummary s = runWith({f});
    report("hazard detector silent 30-45 s", s);
    checkReachedAfterResponse(s, 30.0);
    CHECK(s.lastResumeTimeS >= 45.0);  // never drove on blind
}

TEST(LockstepFaultProtection, AnImuBiasStepIsHeldThroughUntilThePoseIsTrustedAgain) {
    FaultSpec f;
    f.type = FaultType::kImuBiasStep;
    f.at = at(20.0);
    f.value = 0.005;
    const MissionSummary s = runWith({f});
    report("IMU bias step 0.005 rad/s at 20 s", s);
    checkReachedAfterResponse(s, 20.0);
}

TEST(LockstepFaultProtection, ALowBatteryHoldsTheRoverUntilTheSunRechargesIt) {
    const MissionSummary s = runWith({}, 1500.0, "sim_stub/scenarios/low_battery.toml");
    report("2 % charge at start, 8 A array", s);
    checkReachedAfterResponse(s, 0.0);
    CHECK(s.lastResumeTimeS > 300.0);  // it waited to charge, not drove on
}

TEST(LockstepFaultProtection, AnOverheatingMotorStopsTheRoverUntilItCoolsAndCallsHomeWhenItKeepsOverheating) {
    // 8x the heat for the same current: every stretch of driving takes the
    // motor past 80 degC again. Each time the rover holds until it has cooled
    // 15 degC, resumes, and after the class's tries it calls home.
    const MissionSummary s = runWith({wheelFault(FaultType::kMotorOverheat, 3, 10.0, -1.0, 8.0)}, 900.0);
    report("FR motor heats 8x faster from 10 s", s);
    CHECK(s.holdsReleased >= 2);
    CHECK(s.responsesRecovered >= 2);
    CHECK(s.lastResumeTimeS - s.firstHoldTimeS > 30.0);  // it waited to cool each time
    CHECK(s.outcome == MissionOutcome::kCalledHome);
    CHECK(s.faultProtectionCalledHome);
    LONGS_EQUAL(0, s.collisions);
}

// Off the map: the rover drives along the south edge of the site (the
// orbital map's y_min, -10 m; the world goes on beyond it) and the ground
// gives way, carrying it 2.5 m south, off the map. The estimator refuses the
// fixes that show the jump, then re-anchors (pose uncertain: held); the
// re-anchored pose lies off the site (fault 46); fault protection has the
// waypoint cancelled and the goal replanned from there; the deliberative layer
// plans from the nearest point on the site, the habitual layer drives back on,
// and the rover reaches its goal.
TEST(LockstepFaultProtection, ARoverCarriedOffTheMapIsReplannedFromWhereItStandsAndReachesItsGoal) {
    MissionOptions o;
    const char* argv[] = {"rse-demo", "--no-faults", "--goto", "18,-8.6"};
    std::string error;
    CHECK_TRUE_TEXT(sim::parseMissionArgs(4, argv, &o, &error) == sim::ParseOutcome::kRun, error.c_str());
    o.durationS = 300.0;
    o.quiet = !printConsole();
    o.editScenario = [](Scenario& sc) {
        sc.start.x = 0.0;
        sc.start.y = -8.6;
        sc.map.yMin = -20.0;  // the world goes on south of the orbital map
        FaultSpec f;
        f.type = FaultType::kSlide;
        f.at = at(25.0);
        f.until = at(27.0);
        f.value = 2.5;
        f.bearingRad = -0.5 * 3.141592653589793;
        sc.faults.push_back(f);
    };
    o.editUplinkedMap = [](Scenario& sc) { sc.map.yMin = -10.0; };  // the orbital survey ends at -10 m
    const MissionSummary s = sim::runMission(o, printConsole() ? stdout : nullptr);
    report("slid 2.5 m south off the map at 25-27 s", s);
    const sim::MissionMark* offMap = s.firstMark(sim::MarkKind::kFaultRaised, 0.0, msg::fault::kOffMap);
    const double offMapAtS = offMap != nullptr ? offMap->timeS : -1.0;
    std::printf("\n  off the map (fault 46) raised at %.2f s", offMapAtS);
    CHECK(offMap != nullptr && offMap->eventId == 738);
    CHECK(offMapAtS >= 25.0 && offMapAtS < 35.0);
    CHECK_TRUE_TEXT(s.outcome == MissionOutcome::kGoalReached, s.callHomeText.c_str());
    CHECK(s.goalDistanceM < 0.6);
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.responsesStarted >= 2);    // pose uncertain (held), then off the map (replan)
    CHECK(s.responsesRecovered >= 2);
    LONGS_EQUAL(0, s.responsesGaveUp);
    CHECK(s.replans >= 1);
    CHECK(s.recoveryActions >= 1);  // the replan asked for (event 942)
    const sim::MissionMark* replan = s.firstMark(sim::MarkKind::kRecoveryAction, 25.0);
    CHECK(replan != nullptr && replan->timeS >= offMapAtS && replan->timeS < offMapAtS + 0.011);  // same frame
    LONGS_EQUAL(msg::fault::kOffMap, replan->faultId);  // ReplanRequestMsg::faultId
    LONGS_EQUAL(sim::kNoWheel, replan->wheel);
    LONGS_EQUAL(0, s.marksUnattributed);
}

// 1.3x the current for the same torque: the drive trips (3 A held 100 ms)
// only in the tightest manoeuvres. Each trip is recovered (drive reset,
// interlock released, leg re-sent). Where the plan has one such turn (x86-64)
// the rover reaches the goal; where it has more (aarch64: the plan differs in
// the last bits), restarting the turn from rest trips it again, the tries run
// out within attempt_memory_ms, the drive is given up and the deliberative
// layer calls home. Derating a worn drive would carry on (docs/fault_protection.md).
TEST(LockstepFaultProtection, AMotorWornToOnePointThreeTimesItsCurrentIsRecoveredUntilItsTriesRunOut) {
    const MissionSummary s = runWith({wheelFault(FaultType::kMotorDegradation, 1, 15.0, -1.0, 1.3)});
    report("ML motor 1.3x current from 15 s", s);
    LONGS_EQUAL(0, s.collisions);
    if (s.outcome == MissionOutcome::kGoalReached) {
        CHECK(s.goalDistanceM < 0.6);
        LONGS_EQUAL(0, s.responsesGaveUp);
    } else {
        CHECK(s.outcome == MissionOutcome::kCalledHome);
        CHECK(s.responsesRecovered >= 3);  // the first trips were recovered and driving resumed
        CHECK(s.holdsReleased >= 3);
        LONGS_EQUAL(1, s.responsesGaveUp);
        LONGS_EQUAL(static_cast<int>(rse::msg::CallHomeReason::kMobilityLost), static_cast<int>(s.callHome));
    }
}

// A flight task stall from the scenario (habitual_stall.toml: the demo site,
// task_stall of "habitual" at 20 s, no end): the simulator cannot stop a flight
// task (it only exchanges CAN frames), so its fault scheduler's task_stall is
// sent by the ground link's owner as the operator's EXEC_SET_TASK, disabling
// the habitual layer's row mid-leg. The health monitor raises that row's
// task-stalled fault after FAULT_RESPONSE.task_stall_periods of its 100 ms
// period; fault protection holds the mission and runs the row again (class 7,
// restart the task); the fault clears, the hold is released, the leg is
// re-sent and the rover reaches the goal without contact.
TEST(LockstepFaultProtection, AStalledHabitualLayerIsRestartedAndTheGoalReached) {
    const MissionSummary s = runScenario("sim_stub/scenarios/habitual_stall.toml");
    report("habitual row stalled (EXEC_SET_TASK) at 20 s", s);
    const sim::MissionMark* raised = s.firstMark(sim::MarkKind::kFaultRaised, 20.0);
    const sim::MissionMark* started = s.firstMark(sim::MarkKind::kResponseStarted, 20.0);
    const sim::MissionMark* restarted = s.firstMark(sim::MarkKind::kRecoveryAction, 20.0);
    const sim::MissionMark* held = s.firstMark(sim::MarkKind::kHoldSet, 20.0);
    const sim::MissionMark* released = s.firstMark(sim::MarkKind::kHoldReleased, 20.0);
    CHECK(raised != nullptr && started != nullptr && restarted != nullptr && held != nullptr && released != nullptr);
    std::printf("\n    stall commanded %.2f s (row %d), task-stalled fault %.2f s, response %.2f s, hold %.2f s, "
                "restart %.2f s, hold released %.2f s, goal %.2f s; TASK_TIMING runs %u at the stall, %u at the end",
                s.taskStallTimeS, s.stalledRow, raised->timeS, started->timeS, held->timeS, restarted->timeS,
                released->timeS, s.outcomeTimeS, static_cast<unsigned>(s.stalledRowRunsAtStall),
                static_cast<unsigned>(s.stalledRowRunsAtEnd));
    // The ground's command, at the scheduled time, on the habitual layer's row (12).
    LONGS_EQUAL(1, s.taskStallCommands);
    DOUBLES_EQUAL(20.0, s.taskStallTimeS, 0.011);
    LONGS_EQUAL(12, s.stalledRow);
    LONGS_EQUAL(0, s.commandsRejected);
    // Detected as that row's stall: event 732, three 100 ms periods after its last run.
    LONGS_EQUAL(732, raised->eventId);
    LONGS_EQUAL(msg::fault::kTaskStalled + 12, raised->faultId);  // the row's own fault id
    CHECK(raised->timeS > s.taskStallTimeS + 0.3 - 0.1);
    CHECK(raised->timeS <= s.taskStallTimeS + 0.3 + 0.02);
    // Fault protection's response in the same frame (930), the hold, then the
    // restart (935) once the class's settle time is over.
    LONGS_EQUAL(930, started->eventId);
    LONGS_EQUAL(msg::fault::kTaskStalled + 12, started->faultId);
    CHECK(started->timeS - raised->timeS < 0.011);
    CHECK(held->timeS - raised->timeS < 0.011);
    LONGS_EQUAL(935, restarted->eventId);
    LONGS_EQUAL(msg::fault::kTaskStalled + 12, restarted->faultId);  // TaskRestartMsg::row 12
    CHECK(restarted->timeS >= started->timeS);
    CHECK(restarted->timeS - raised->timeS <= 1.5);
    CHECK(released->timeS > restarted->timeS);
    // The row runs again: the ground sees its runs go on at 10 Hz.
    CHECK(s.stalledRowRunsAtEnd > s.stalledRowRunsAtStall + static_cast<std::uint32_t>(5.0 * (s.outcomeTimeS - 22.0)));
    // And the mission: recovered, the goal reached without contact.
    checkReachedAfterResponse(s, 20.0);
    LONGS_EQUAL(1, s.responsesStarted);
    LONGS_EQUAL(1, s.recoveryActions);
}
