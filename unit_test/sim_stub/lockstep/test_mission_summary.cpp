// How a lockstep mission went, as rse-demo prints it (sim_stub/lockstep/
// mission_summary.hpp), from summaries made by hand: every line of the printed
// summary with its figures, the lines that appear only when they apply
// (pace, UDP link, plan executive, first response, task stall), each
// outcome's own line, the marks' queries (first of a kind, by fault, counts,
// the hold in force before a time) and the names the console uses.
#include <cstdio>
#include <cstring>
#include <string>

#include "sim_stub/lockstep/mission_summary.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MarkKind;
using sim::MissionMark;
using sim::MissionOutcome;
using sim::MissionSummary;

namespace {

// Everything written to a temporary file so far.
std::string readAll(std::FILE* f) {
    std::fflush(f);
    std::rewind(f);
    std::string text;
    char chunk[4096];
    for (std::size_t n = std::fread(chunk, 1, sizeof chunk, f); n > 0; n = std::fread(chunk, 1, sizeof chunk, f)) {
        text.append(chunk, n);
    }
    return text;
}

bool contains(const std::string& text, const char* what) { return text.find(what) != std::string::npos; }

std::string printed(const MissionSummary& s) {
    std::FILE* out = std::tmpfile();
    CHECK(out != nullptr);
    sim::printMissionSummary(s, out);
    const std::string text = readAll(out);
    std::fclose(out);
    return text;
}

ground::MissionPoint point(int number, bool seen, double timeS, const char* layer) {
    ground::MissionPoint p;
    p.number = number;
    p.seen = seen;
    p.timeS = timeS;
    p.layer = layer;
    return p;
}

// A goal mission that reached its goal, every optional line on.
MissionSummary reachedGoal() {
    MissionSummary s;
    s.outcome = MissionOutcome::kGoalReached;
    s.goalX = 20.0;
    s.goalY = -1.5;
    s.outcomeTimeS = 95.27;
    s.endTimeS = 96.0;
    s.wallTimeS = 1.5;
    s.pace = 10.0;
    s.pacedFrames = 9600;
    s.framesBehind = 3;
    s.behindMaxMs = 12.54;
    s.udpLink = true;
    s.udpTelemetry = "127.0.0.1:1235";
    s.udpCommands = "127.0.0.1:40000";
    s.udpStats.txPackets = 100;
    s.udpStats.txDropped = 1;
    s.udpStats.errors = 2;
    s.udpStats.rxPackets = 5;
    s.udpUndeliverable = 2;
    s.finalX = 19.8;
    s.finalY = -1.25;
    s.finalHeadingDeg = 3.46;
    s.goalDistanceM = 0.32;
    s.distanceM = 21.05;
    s.collisions = 0;
    s.leastClearanceM = 0.41;
    s.energyWh = 12.344;
    s.stateOfCharge = 0.8751;
    s.plansMade = 3;
    s.planLengthM = 20.5;
    s.riskUsed = 9.5e-4;
    s.riskBound = 1e-3;
    s.riskInForce = 2e-3;
    s.legsSent = 5;
    s.legsAchieved = 4;
    s.failUps = 1;
    s.replans = 1;
    s.boundRelaxations = 1;
    s.riskRelaxations = 1;
    s.callHomes = 0;
    s.habitualReplans = 2;
    s.responsesStarted = 2;
    s.responsesRecovered = 1;
    s.responsesGaveUp = 0;
    s.recoveryActions = 3;
    s.holdsReleased = 1;
    s.firstResponseTimeS = 30.5;
    s.firstHoldTimeS = 30.51;
    s.lastResumeTimeS = 41.0;
    s.taskStallCommands = 2;
    s.taskStallTimeS = 60.0;
    s.stalledRow = 7;
    s.stalledRowRunsAtStall = 600;
    s.stalledRowRunsAtEnd = 900;
    s.commandsAccepted = 12;
    s.commandsRejected = 1;
    s.record.verdict = "9 of 10 points seen";
    for (int n = 2; n <= 9; ++n) {
        s.record.points[static_cast<std::size_t>(n - 1)] = point(n, false, 0.0, "");
    }
    s.record.points[0] = point(1, true, 0.52, "operator");
    s.record.points[9] = point(10, true, 123.456, "deliberative + mode owner");
    return s;
}

void addMark(MissionSummary* s, MarkKind kind, double timeS, std::uint8_t faultId = 0) {
    MissionMark m;
    m.kind = kind;
    m.timeS = timeS;
    m.faultId = faultId;
    s->marks[s->markCount++] = m;
}

}  // namespace

TEST_GROUP(MissionSummary){};

// The whole summary of a goal reached, line by line (the figures rounded as
// the formats say: 95.27 s -> 95.3, 12.344 Wh -> 12.34, 0.8751 -> 87.5 %).
TEST(MissionSummary, EveryLineOfAReachedGoalWithItsFigures) {
    const std::string expected =
        "\n=== rse-demo mission summary ===\n"
        "outcome:    goal (20.00, -1.50) reached at 95.3 s\n"
        "time:       96.0 s simulated in 1.5 s wall (64.0x real time)\n"
        "pace:       10x real time: 9600 frames paced, 3 reached after their due time; behind by up to 12.5 ms\n"
        "udp link:   telemetry to 127.0.0.1:1235: 100 packets sent, 1 dropped, 2 errors (2 undeliverable: ICMP port "
        "unreachable, nothing listening there); commands on 127.0.0.1:40000: 5 received\n"
        "truth:      final position (19.80, -1.25) heading 3.5 deg, 0.32 m from the goal; driven 21.05 m; "
        "collisions 0, least clearance 0.41 m; energy 12.34 Wh, state of charge 87.5 %\n"
        "plan:       3 plans made; the last 20.50 m, risk used 0.00095 (bound 0.001, in force 0.002)\n"
        "legs:       5 sent, 4 achieved, 1 fail-ups; 1 replans, 1 bound relaxations, 1 risk relaxations, 0 call "
        "homes; habitual replans 2\n"
        "fault prot: 2 responses, 1 recovered, 0 gave up, 3 recovery actions, 1 holds released; first response "
        "30.50 s, first hold 30.51 s, last resume 41.00 s\n"
        "task stall: 2 EXEC_SET_TASK sent; row 7 disabled at 60.00 s; its TASK_TIMING runs 600 then, 900 at the end\n"
        "commands:   12 accepted, 1 rejected\n"
        "points:     9 of 10 points seen\n"
        "             1 at     0.52 s  operator\n"
        "             2 not seen\n"
        "             3 not seen\n"
        "             4 not seen\n"
        "             5 not seen\n"
        "             6 not seen\n"
        "             7 not seen\n"
        "             8 not seen\n"
        "             9 not seen\n"
        "            10 at   123.46 s  deliberative + mode owner\n"
        "\n";
    STRCMP_EQUAL(expected.c_str(), printed(reachedGoal()).c_str());
}

// The lines that apply only sometimes are left out: no --pace, no UDP link,
// no response yet (no first-response times), no task stall; no wall time
// gives a ratio of 0 rather than a division by zero.
TEST(MissionSummary, TheLinesThatDoNotApplyAreLeftOut) {
    MissionSummary s = reachedGoal();
    s.pace = 0.0;
    s.udpLink = false;
    s.firstResponseTimeS = -1.0;
    s.taskStallCommands = 0;
    s.wallTimeS = 0.0;
    const std::string text = printed(s);
    CHECK_FALSE(contains(text, "pace:"));
    CHECK_FALSE(contains(text, "udp link:"));
    CHECK_FALSE(contains(text, "first response"));
    CHECK_FALSE(contains(text, "task stall:"));
    CHECK_FALSE(contains(text, "plan exec:"));
    CHECK_TRUE(contains(text, "time:       96.0 s simulated in 0.0 s wall (0.0x real time)\n"));
    CHECK_TRUE(contains(text, "fault prot: 2 responses, 1 recovered, 0 gave up, 3 recovery actions, 1 holds released\n"));
}

// A plan mission: its outcome line names the plan and the last drive's goal,
// and the plan executive's line its figures.
TEST(MissionSummary, APlanMissionNamesThePlanAndTheExecutivesFigures) {
    MissionSummary s = reachedGoal();
    s.outcome = MissionOutcome::kPlanComplete;
    s.planMission = true;
    std::strncpy(s.planExec.planName, "two_targets", sizeof s.planExec.planName);
    s.planExec.state = msg::PlanExecutiveState::kComplete;
    s.planExec.cost = 32.5;
    s.planExec.costBefore = 30.25;
    s.planExec.regenerations = 1;
    s.planExec.deprecatedCount = 2;
    s.planExec.activitiesStarted = 6;
    s.planExec.activitiesCompleted = 5;
    s.planExec.activitiesEarly = 1;
    s.planExec.activitiesLate = 0;
    s.planExec.activitiesFailed = 1;
    s.planExec.operatorCalls = 0;
    const std::string text = printed(s);
    CHECK_TEXT(contains(text, "outcome:    plan two_targets complete at 95.3 s, the last drive's goal (20.00, -1.50)\n"),
               text.c_str());
    CHECK_TEXT(contains(text, "plan exec:  two_targets complete: cost 32.50 (before the last regeneration 30.25), 1 "
                              "regenerations, 2 options deprecated; activities 6 started, 5 completed (1 early, 0 "
                              "late), 1 failed; 0 operator calls\n"),
               text.c_str());
}

TEST(MissionSummary, ATimedOutMissionSaysWhereTheDeliberativeLayerAndTheModeStood) {
    MissionSummary s = reachedGoal();
    s.outcome = MissionOutcome::kTimedOut;
    s.outcomeTimeS = 180.0;
    s.finalState = msg::DeliberativeState::kExecuting;
    s.finalMode = 2;
    CHECK_TRUE(contains(printed(s), "outcome:    timed out at 180.0 s (deliberative layer EXECUTING, mode AUTONOMOUS)\n"));
    s.finalMode = 9;  // no mode
    CHECK_TRUE(contains(printed(s), "(deliberative layer EXECUTING, mode ?)\n"));
}

TEST(MissionSummary, TheSummarySaysWhyTheRoverCalledHome) {
    MissionSummary s;
    s.outcome = MissionOutcome::kCalledHome;
    s.callHome = msg::CallHomeReason::kMobilityLost;
    s.callHomeText = "mobility lost (the drive interlock holds every drive)";
    s.outcomeTimeS = 45.6;
    s.finalMode = 0;
    s.interlockTripped = true;
    std::FILE* out = std::tmpfile();
    CHECK(out != nullptr);
    sim::printMissionSummary(s, out);
    const std::string text = readAll(out);
    std::fclose(out);
    CHECK_TRUE(contains(text, "called home at 45.6 s, reason 5: mobility lost (the drive interlock holds every drive) "
                              "(mode SAFE, drive interlock tripped)"));
    CHECK_TRUE(contains(text, "truth:"));
}

TEST(MissionSummary, ASetupFailureSummaryGivesTheReasonAndNoFigures) {
    MissionSummary s;
    s.setupError = "the drives did not become operational";
    std::FILE* out = std::tmpfile();
    CHECK(out != nullptr);
    sim::printMissionSummary(s, out);
    const std::string text = readAll(out);
    std::fclose(out);
    CHECK_TRUE(contains(text, "setup failed: the drives did not become operational"));
    CHECK_FALSE(contains(text, "truth:"));
}

// The marks in time order: the first of a kind at or after a time, the
// first about one fault, how many are about it, and whether the hold was in
// force just before a time (the last hold change before it set it).
TEST(MissionSummary, TheMarksAnswerWhatCameFirstHowOftenAndWhetherTheRoverWasHeld) {
    MissionSummary s;
    addMark(&s, MarkKind::kFaultRaised, 10.0, 3);
    addMark(&s, MarkKind::kHoldSet, 10.0);
    addMark(&s, MarkKind::kResponseStarted, 10.0, 3);
    addMark(&s, MarkKind::kRecoveryAction, 10.5, 3);
    addMark(&s, MarkKind::kHoldReleased, 12.0);
    addMark(&s, MarkKind::kFaultRaised, 20.0, 17);
    addMark(&s, MarkKind::kFaultRaised, 25.0, 3);
    addMark(&s, MarkKind::kHoldSet, 25.0);
    const MissionMark* first = s.firstMark(MarkKind::kFaultRaised, 0.0);
    CHECK(first == &s.marks[0]);
    CHECK(s.firstMark(MarkKind::kFaultRaised, 10.01) == &s.marks[5]);  // at or after
    CHECK(s.firstMark(MarkKind::kFaultRaised, 20.0) == &s.marks[5]);
    CHECK(s.firstMark(MarkKind::kFaultRaised, 10.01, 3) == &s.marks[6]);
    CHECK(s.firstMark(MarkKind::kFaultRaised, 0.0, 17) == &s.marks[5]);
    CHECK(s.firstMark(MarkKind::kGaveUp, 0.0) == nullptr);
    CHECK(s.firstMark(MarkKind::kFaultRaised, 25.01) == nullptr);
    CHECK(s.firstMark(MarkKind::kFaultRaised, 0.0, 4) == nullptr);
    LONGS_EQUAL(2, s.countMarks(MarkKind::kFaultRaised, 3));
    LONGS_EQUAL(1, s.countMarks(MarkKind::kFaultRaised, 17));
    LONGS_EQUAL(0, s.countMarks(MarkKind::kResponseStarted, 17));
    LONGS_EQUAL(2, s.countMarks(MarkKind::kHoldSet, 0));
    CHECK_FALSE(s.heldBefore(10.0));  // set at 10.0: not before it
    CHECK_TRUE(s.heldBefore(10.01));
    CHECK_TRUE(s.heldBefore(12.0));
    CHECK_FALSE(s.heldBefore(12.01));
    CHECK_FALSE(s.heldBefore(25.0));
    CHECK_TRUE(s.heldBefore(1e9));
    // Only the marks counted are read.
    s.markCount = 2;
    CHECK(s.firstMark(MarkKind::kResponseStarted, 0.0) == nullptr);
    LONGS_EQUAL(1, s.countMarks(MarkKind::kFaultRaised, 3));
}

TEST(MissionSummary, TheNamesAreTheConsoles) {
    STRCMP_EQUAL("setup failed", sim::toString(MissionOutcome::kSetupFailed));
    STRCMP_EQUAL("goal reached", sim::toString(MissionOutcome::kGoalReached));
    STRCMP_EQUAL("called home", sim::toString(MissionOutcome::kCalledHome));
    STRCMP_EQUAL("timed out", sim::toString(MissionOutcome::kTimedOut));
    STRCMP_EQUAL("plan complete", sim::toString(MissionOutcome::kPlanComplete));
    STRCMP_EQUAL("?", sim::toString(static_cast<MissionOutcome>(9)));
    const char* const deliberative[] = {"IDLE", "WAITING", "PLANNING", "EXECUTING", "CALLED HOME", "COMPLETE", "?"};
    for (std::uint8_t i = 0; i < 7; ++i) {
        STRCMP_EQUAL(deliberative[i], sim::deliberativeStateName(static_cast<msg::DeliberativeState>(i)));
    }
    const char* const executive[] = {"idle", "selecting", "dispatching", "regenerating", "complete", "failed", "?"};
    for (std::uint8_t i = 0; i < 7; ++i) {
        STRCMP_EQUAL(executive[i], sim::planExecutiveStateName(static_cast<msg::PlanExecutiveState>(i)));
    }
    // The plan's name: NUL-padded, or the whole field when it fills it.
    msg::PlanExecutiveStatusMsg status{};
    STRCMP_EQUAL("", sim::planName(status).c_str());
    std::strncpy(status.planName, "hop", sizeof status.planName);
    STRCMP_EQUAL("hop", sim::planName(status).c_str());
    std::memset(status.planName, 'a', sizeof status.planName);
    LONGS_EQUAL(sizeof status.planName, sim::planName(status).size());
}
