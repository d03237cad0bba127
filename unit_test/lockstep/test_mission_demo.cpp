// rse-demo's logic (sim_stub/lockstep/mission_runner.hpp): its command line
// (the goal checked against the dictionary's GOTO ranges), its exit codes, the
// summary's wording, short lockstep missions judged against the truth the
// summary reports, and the demo itself: the ten points of the RSE
// demonstration in order, each with its substance, the report and the map
// written; a run that cannot show them all saying so and exiting 3. (The
// hidden rock whose detour does not fit, point 5's other side, is in the
// scenario suite, test_scenario_suite.cpp.)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/core/byte_codec.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;
using sim::ParseOutcome;

namespace {

ParseOutcome parse(std::vector<const char*> args, MissionOptions* o, std::string* error) {
    args.insert(args.begin(), "rse-demo");
    return sim::parseMissionArgs(static_cast<int>(args.size()), args.data(), o, error);
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A folder of its own under build/ for a run's report and map.
std::string reportFolder(const char* name) { return std::string("build/test_mission_demo/") + name; }

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

unsigned countOf(const std::string& text, const char* what) {
    unsigned n = 0;
    for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) {
        ++n;
    }
    return n;
}

// The GOTO argument bytes as flight decodes them: x, y, risk (f64, big-endian).
void checkGotoArgs(const MissionOptions& o, double x, double y, double risk) {
    LONGS_EQUAL(24, o.gotoArgs.size());
    core::BeReader r(o.gotoArgs.data(), o.gotoArgs.size());
    DOUBLES_EQUAL(x, r.f64(), 0.0);
    DOUBLES_EQUAL(y, r.f64(), 0.0);
    DOUBLES_EQUAL(risk, r.f64(), 0.0);
}

}  // namespace

TEST_GROUP(MissionDemoOptions) {
    MissionOptions o;
    std::string error;
};

// Without --goto and --duration the mission is the scenario's own: the demo
// scenario's [mission] is GOTO (20, 0) at 10^-3 for 180 s.
TEST(MissionDemoOptions, NoArgumentsIsTheDemoMissionToTwentyMetres) {
    CHECK(ParseOutcome::kRun == parse({}, &o, &error));
    STRCMP_EQUAL("sim_stub/scenarios/demo_mission.toml", o.scenarioPath.c_str());
    CHECK_FALSE(o.anyOutcome);
    CHECK_FALSE(o.clearFaults);
    CHECK_FALSE(o.quiet);
    DOUBLES_EQUAL(0.0, o.durationS, 0.0);  // the scenario's
    CHECK_TRUE(o.gotoArgs.empty());        // the scenario's
    CHECK_TRUE(sim::applyScenarioMission(sim::loadScenarioFile(o.scenarioPath), &o, &error));
    DOUBLES_EQUAL(180.0, o.durationS, 0.0);
    checkGotoArgs(o, 20.0, 0.0, 1e-3);
    CHECK_TRUE(o.planText.empty());
}

// The scenario's [mission] where the command line says nothing, never over it;
// a scenario without one gets the demo's goal and 180 s; a plan mission its
// plan's text and the bound for SET_RISK_BOUND.
TEST(MissionDemoOptions, TheScenariosMissionFillsOnlyWhatTheCommandLineLeftOpen) {
    sim::Scenario s = sim::parseScenario(
        "seed = 1\nduration_s = 75\n[map]\nx_min_m = -5\nx_max_m = 30\ny_min_m = -10\ny_max_m = 10\n"
        "[start]\nx_m = 0\ny_m = 0\n[mission]\ngoal_x_m = 12.5\ngoal_y_m = -3\nrisk_bound = 1e-5\n",
        "own.toml");
    MissionOptions own;
    CHECK_TRUE(sim::applyScenarioMission(s, &own, &error));
    checkGotoArgs(own, 12.5, -3.0, 1e-5);
    DOUBLES_EQUAL(75.0, own.durationS, 0.0);
    CHECK_TRUE(sim::applyScenarioMission(s, &own, &error));  // again: nothing changes
    checkGotoArgs(own, 12.5, -3.0, 1e-5);
    // --goto and --duration win.
    CHECK(ParseOutcome::kRun == parse({"--goto", "4,1,0.01", "--duration", "30"}, &o, &error));
    CHECK_TRUE(sim::applyScenarioMission(s, &o, &error));
    checkGotoArgs(o, 4.0, 1.0, 0.01);
    DOUBLES_EQUAL(30.0, o.durationS, 0.0);
    // No [mission]: the demo's goal and duration.
    s.mission = sim::MissionSpec{};
    MissionOptions none;
    CHECK_TRUE(sim::applyScenarioMission(s, &none, &error));
    checkGotoArgs(none, 20.0, 0.0, 1e-3);
    DOUBLES_EQUAL(180.0, none.durationS, 0.0);
    // A plan: its text and its bound; no GOTO.
    s.mission.present = true;
    s.mission.planFile = "p.plan";
    s.mission.planText = "plan p\nend\n";
    s.mission.riskBound = 1e-4;
    MissionOptions plan;
    CHECK_TRUE(sim::applyScenarioMission(s, &plan, &error));
    CHECK_TRUE(plan.gotoArgs.empty());
    STRCMP_EQUAL("plan p\nend\n", plan.planText.c_str());
    STRCMP_EQUAL("p.plan", plan.planFile.c_str());
    DOUBLES_EQUAL(1e-4, plan.risk, 0.0);
    DOUBLES_EQUAL(75.0, plan.durationS, 0.0);
}

// A plan the ground's check refuses is never sent: the setup fails before the
// rover boots and says why (the runner checks it as `rse-ground plan load` does).
TEST(MissionDemoOptions, APlanTheGroundCheckRefusesIsNotSent) {
    const char* path = "build/test_mission_demo/bad_plan.toml";
    const char* plan = "build/test_mission_demo/bad.plan";
    std::filesystem::create_directories("build/test_mission_demo");
    std::FILE* f = std::fopen(plan, "w");
    CHECK(f != nullptr);
    std::fputs("plan bad\nactivity a drive start nowhere [1, 2] cost 1 at 1 1\nend\n", f);
    std::fclose(f);
    f = std::fopen(path, "w");
    CHECK(f != nullptr);
    std::fputs("seed = 1\n[map]\nx_min_m = -5\nx_max_m = 30\ny_min_m = -10\ny_max_m = 10\n"
               "[start]\nx_m = 0\ny_m = 0\n[mission]\nplan_file = \"bad.plan\"\n",
               f);
    std::fclose(f);
    CHECK(ParseOutcome::kRun == parse({"--scenario", path, "--quiet"}, &o, &error));
    const MissionSummary s = sim::runMission(o, nullptr);
    CHECK(MissionOutcome::kSetupFailed == s.outcome);
    CHECK_TEXT(contains(s.setupError, "bad.plan: the plan did not pass the ground check"), s.setupError.c_str());
}

TEST(MissionDemoOptions, EveryOptionIsTaken) {
    const char* args[] = {"rse-demo", "--report", "some/where", "--any-outcome"};
    MissionOptions withReport;
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(4, args, &withReport, &error));
    STRCMP_EQUAL("some/where", withReport.reportDir.c_str());
    CHECK_TRUE(withReport.anyOutcome);
    const char* none[] = {"rse-demo", "--no-report"};
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(2, none, &withReport, &error));
    CHECK_TRUE(withReport.reportDir.empty());
    CHECK_TRUE(withReport.noReport);
    // Without either, runMission writes nothing; rse-demo's main writes to build/mission.
    MissionOptions defaults;
    const char* bare[] = {"rse-demo"};
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(1, bare, &defaults, &error));
    CHECK_TRUE(defaults.reportDir.empty());
    CHECK_FALSE(defaults.noReport);
    STRCMP_EQUAL("build/mission", sim::kDefaultReportDir);
    CHECK(ParseOutcome::kRun == parse({"--scenario", "other.toml", "--no-faults", "--goto", "4,-1.5,0.01", "--duration",
                                       "30", "--quiet"},
                                      &o, &error));
    STRCMP_EQUAL("other.toml", o.scenarioPath.c_str());
    CHECK_TRUE(o.clearFaults);
    CHECK_TRUE(o.quiet);
    DOUBLES_EQUAL(30.0, o.durationS, 0.0);
    DOUBLES_EQUAL(4.0, o.goalX, 0.0);
    DOUBLES_EQUAL(-1.5, o.goalY, 0.0);
    DOUBLES_EQUAL(0.01, o.risk, 0.0);
    checkGotoArgs(o, 4.0, -1.5, 0.01);
}

TEST(MissionDemoOptions, AGotoWithoutRiskTakesTheDefaultBound) {
    CHECK(ParseOutcome::kRun == parse({"--goto", "4,0"}, &o, &error));
    checkGotoArgs(o, 4.0, 0.0, 1e-3);
}

TEST(MissionDemoOptions, ABadGotoIsAUsageError) {
    const char* const bad[] = {"4", "4,", ",0", "4,0,1e-3,7", "a,0", "4,0,x", "4,0,0.9", "4,0,0", "1e5,0", "4,nan"};
    for (const char* g : bad) {
        MissionOptions fresh;
        error.clear();
        const ParseOutcome r = parse({"--goto", g}, &fresh, &error);
        if (r != ParseOutcome::kUsageError) {
            FAIL(("--goto " + std::string(g) + " was accepted").c_str());
        }
        CHECK_TRUE(contains(error, "--goto"));
    }
    // Out of the dictionary's range: the ground encoder's reason is shown.
    CHECK(ParseOutcome::kUsageError == parse({"--goto", "4,0,0.9"}, &o, &error));
    CHECK_TRUE(contains(error, "risk"));
}

TEST(MissionDemoOptions, UnknownFlagsMissingValuesAndBadDurationsAreUsageErrors) {
    CHECK(ParseOutcome::kUsageError == parse({"--fast"}, &o, &error));
    CHECK_TRUE(contains(error, "'--fast'"));
    CHECK(ParseOutcome::kUsageError == parse({"--goto"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--scenario"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "-3"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "3s"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--command-at", "-1"}, &o, &error));
    CHECK_TRUE(contains(error, "--command-at"));
    CHECK(ParseOutcome::kUsageError == parse({"--command-at", "soon"}, &o, &error));
    CHECK(ParseOutcome::kRun == parse({"--command-at", "2.5"}, &o, &error));
    DOUBLES_EQUAL(2.5, o.commandAtS, 0.0);
    CHECK(ParseOutcome::kHelp == parse({"--help"}, &o, &error));
}

TEST(MissionDemoOptions, ExitCodesAreTwoForUsageOneForSetupZeroForHelp) {
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    CHECK(out != nullptr && err != nullptr);
    const char* unknown[] = {"rse-demo", "--fast"};
    LONGS_EQUAL(2, sim::missionMain(2, unknown, out, err));
    const char* noScenario[] = {"rse-demo", "--scenario", "sim_stub/scenarios/no_such_scenario.toml", "--quiet"};
    LONGS_EQUAL(1, sim::missionMain(4, noScenario, out, err));
    const char* help[] = {"rse-demo", "--help"};
    LONGS_EQUAL(0, sim::missionMain(2, help, out, err));
    const std::string errText = readAll(err);
    CHECK_TRUE(contains(errText, "unknown or incomplete option '--fast'"));
    CHECK_TRUE(contains(errText, "usage: rse-demo"));
    CHECK_TRUE(contains(errText, "setup failed"));
    CHECK_TRUE(contains(readAll(out), "usage: rse-demo"));
    std::fclose(out);
    std::fclose(err);
}

TEST(MissionDemoOptions, TheSummarySaysWhyTheRoverCalledHome) {
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

TEST(MissionDemoOptions, ASetupFailureSummaryGivesTheReasonAndNoFigures) {
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

TEST_GROUP(MissionDemoRun) {
    std::FILE* out = nullptr;
    MissionOptions o;
    std::string error;
    void setup() override { out = std::tmpfile(); }
    void teardown() override {
        if (out != nullptr) {
            std::fclose(out);
        }
    }
};

// A near goal without the faults: planned, driven, complete; the figures the
// summary gives agree with each other and with the truth.
TEST(MissionDemoRun, ANearGoalWithoutFaultsIsReachedAndTheSummaryAgreesWithTheTruth) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--no-faults", "--goto", "4,0", "--duration", "60"}, &o, &error));
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    if (s.outcome != MissionOutcome::kGoalReached) {
        std::printf("%s\n", text.c_str());
    }
    CHECK(MissionOutcome::kGoalReached == s.outcome);
    CHECK(msg::DeliberativeState::kComplete == s.finalState);
    CHECK(s.outcomeTimeS < 60.0);
    DOUBLES_EQUAL(s.outcomeTimeS + 2.0, s.endTimeS, 0.02);  // the tail for the last events
    // Truth: at the goal, without contact, along a path no shorter than the displacement.
    DOUBLES_EQUAL(std::hypot(s.finalX - 4.0, s.finalY), s.goalDistanceM, 1e-12);
    CHECK(s.goalDistanceM < 0.6);
    CHECK(s.distanceM >= std::hypot(s.finalX, s.finalY) - 1e-9);
    CHECK(s.distanceM < 8.0);
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.energyWh > 0.0);
    // Flight software: a plan, every leg sent ended achieved or failed up, no call home.
    CHECK(s.plansMade >= 1);
    CHECK(s.legsSent >= 1);
    LONGS_EQUAL(s.legsSent, s.legsAchieved + s.failUps);
    LONGS_EQUAL(0, s.callHomes);
    CHECK(s.riskUsed <= s.riskInForce);
    DOUBLES_EQUAL(1e-3, s.riskBound, 1e-15);
    CHECK(s.commandsAccepted >= 2);  // SET_MODE and GOTO, authenticated
    LONGS_EQUAL(0, s.commandsRejected);
    // The stream: the demo's lines, the console's, the summaries.
    CHECK_TRUE(contains(text, "DEMO ground: GOTO x=4.00 y=0.00 risk=0.001"));
    CHECK_TRUE(contains(text, "DEMO deliberative layer: COMPLETE"));
    LONGS_EQUAL(1, countOf(text, "EVT 908 INFO  deliberative: every goal reached"));
    CHECK(countOf(text, "] HK  #") >= 10);
    CHECK_TRUE(contains(text, "outcome:    goal (4.00, 0.00) reached"));
    CHECK_TRUE(contains(text, "rse-fsw summary:"));
    CHECK_TRUE(contains(text, "deliberative"));
}

// The duration ends a mission that has not finished; --quiet leaves the console out.
TEST(MissionDemoRun, TheDurationEndsAnUnfinishedMissionAndQuietLeavesTheConsoleOut) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--no-faults", "--duration", "6", "--quiet"}, &o, &error));
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    CHECK(MissionOutcome::kTimedOut == s.outcome);
    CHECK(s.endTimeS >= 6.0 && s.endTimeS < 6.02);
    CHECK(s.goalDistanceM > 5.0);  // nowhere near (20, 0) yet
    LONGS_EQUAL(0, countOf(text, "] HK  #"));
    LONGS_EQUAL(0, countOf(text, " EVT "));
    CHECK_TRUE(contains(text, "outcome:    timed out at 6.0 s"));
}

// The demonstration (issue 17, must-show 1): the demo scenario shows the ten
// points of the RSE demonstration, each once, in order, each read from what
// the flight software published, with its substance; the report and the map
// are written and carry every point.
TEST(MissionDemoRun, TheDemoShowsTheTenPointsInOrderAndWritesTheReportAndTheMap) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--quiet"}, &o, &error));
    o.reportDir = reportFolder("demo");
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    const ground::MissionRecord& r = s.record;
    if (!s.tenPointsInOrder || std::getenv("RSE_PRINT_CONSOLE") != nullptr) {
        std::printf("%s\n", text.c_str());
    }
    CHECK_TRUE(s.tenPointsInOrder);
    STRCMP_EQUAL("ten points: all in order", r.verdict.c_str());
    for (int n = 1; n <= ground::kMissionPointCount; ++n) {
        const ground::MissionPoint& p = r.points[static_cast<std::size_t>(n - 1)];
        CHECK_TRUE(p.seen);
        LONGS_EQUAL(n, p.number);
        if (n > 1) {
            CHECK(p.timeS >= r.points[static_cast<std::size_t>(n - 2)].timeS);
        }
        // Printed once, numbered, as it was seen.
        const std::string line = "POINT " + std::to_string(n) + " ";
        LONGS_EQUAL(1, countOf(text, line.c_str()));
    }
    const auto fact = [&r](int n, const char* name) {
        const auto& f = r.points[static_cast<std::size_t>(n - 1)].facts;
        const auto it = f.find(name);
        return it == f.end() ? std::nan("") : it->second;
    };
    // 1: the operator's bound, as the flight software took it.
    DOUBLES_EQUAL(1e-3, fact(1, "risk bound"), 1e-15);
    // 2: legs with an energy and a power bound.
    CHECK(fact(2, "energy bound J") > 0.0);
    CHECK(fact(2, "power bound W") > 0.0);
    // 5: the hidden rock (the scenario's obstacle 3, not on the coarse map),
    // replanned round within the leg's bounds: no fail-up from its sighting to
    // the leg achieved, and the deliberative layer not involved.
    DOUBLES_EQUAL(3.0, fact(5, "hazard"), 0.0);
    DOUBLES_EQUAL(0.0, fact(5, "fail-ups"), 0.0);
    CHECK(fact(5, "seen s") < r.points[4].timeS);
    // 6 and 7: the power bound broken by the worn motor, then relaxed above
    // what it was, and driving resumed.
    CHECK(fact(7, "power bound after W") > fact(7, "power bound before W"));
    DOUBLES_EQUAL(fact(6, "power bound W"), fact(7, "power bound before W"), 0.5);
    // 8: after the motor failure (87 s in the scenario).
    CHECK(r.points[7].timeS > 87.0);
    // 10: the risk-bound call home, the rover safed.
    DOUBLES_EQUAL(static_cast<double>(msg::CallHomeReason::kNoPlanWithinRisk), fact(10, "call home reason"), 0.0);
    CHECK(MissionOutcome::kCalledHome == s.outcome);
    CHECK(msg::CallHomeReason::kNoPlanWithinRisk == s.callHome);
    LONGS_EQUAL(0, s.finalMode);  // SAFE
    CHECK(s.riskRelaxations >= 1);
    LONGS_EQUAL(0, s.collisions);

    // The report and the map, named at the end.
    CHECK_TRUE(contains(text, "mission report: build/test_mission_demo/demo/report.md"));
    CHECK_TRUE(contains(text, "mission map:    build/test_mission_demo/demo/map.svg"));
    CHECK_TRUE(contains(text, "points:     ten points: all in order"));
    const std::string report = readFile(s.reportPath);
    const std::string map = readFile(s.mapPath);
    CHECK_TRUE(contains(report, "**ten points: all in order**"));
    CHECK_TRUE(contains(report, "## Timing per task"));
    CHECK_TRUE(contains(report, "| deliberative |"));
    CHECK_TRUE(contains(map, "<svg"));
    CHECK_TRUE(contains(map, "</svg>"));
    for (int n = 1; n <= ground::kMissionPointCount; ++n) {
        const ground::MissionPoint& p = r.points[static_cast<std::size_t>(n - 1)];
        CHECK_TRUE(contains(report, ("| " + std::to_string(n) + " | ").c_str()));
        CHECK_TRUE(p.hasPlace);
        CHECK_TRUE(contains(map, ("id=\"point-" + std::to_string(n) + "\"").c_str()));
    }
    CHECK_TRUE(contains(map, "class=\"hidden-rock\""));
    CHECK_TRUE(contains(map, "class=\"track-truth\""));
    CHECK_TRUE(contains(map, "class=\"track-estimate\""));
    CHECK_TRUE(contains(map, "class=\"mean-path\""));
    CHECK(countOf(map, "class=\"ellipse\"") >= 21);  // a plan of 20 steps: 21 ellipses
}

// A run that cannot show the ten points (the demo without its faults: no worn
// or failed motor) is judged so, and rse-demo exits 3 - or 0 with --any-outcome.
// A ground on a real bus commands later than the lockstep runner (the vcan
// mission's GOTO came at about 2.2 s of flight time, its simulator 0.3 s
// ahead): the demo must show its ten points whenever the GOTO comes in the
// first seconds, not only at 0.5 s. Measured over 0..5.6 s in 0.2 s steps: all
// in order (docs/mission.md, "The same mission from the ground"); these are the
// starts whose runs take other courses (a 4-leg plan and the rock seen before
// its leg; a merged leg whose power fail-up comes on the detour).
TEST(MissionDemoRun, TheTenPointsHoldWhenTheGroundCommandsLater) {
    for (const double at : {1.6, 2.4}) {  // aarch64 at 3.5 s: points 9, 10 missing (libm-level differences); see docs/mission.md
        MissionOptions later;
        CHECK(ParseOutcome::kRun == parse({"--quiet"}, &later, &error));
        later.commandAtS = at;
        const MissionSummary s = sim::runMission(later, out);
        if (!s.tenPointsInOrder) {
            FAIL(("GOTO at " + std::to_string(at) + " s: " + s.record.verdict).c_str());
        }
        CHECK(s.outcome == sim::MissionOutcome::kCalledHome);
        LONGS_EQUAL(static_cast<long>(msg::CallHomeReason::kNoPlanWithinRisk), static_cast<long>(s.callHome));
        LONGS_EQUAL(0, s.collisions);
    }
}

TEST(MissionDemoRun, ARunWithoutTheFaultsMissesPointsAndExitsThree) {
    std::FILE* err = std::tmpfile();
    CHECK(out != nullptr && err != nullptr);
    const char* noFaults[] = {"rse-demo", "--no-faults", "--quiet", "--no-report"};
    LONGS_EQUAL(3, sim::missionMain(4, noFaults, out, err));
    const std::string errText = readAll(err);
    CHECK_TRUE(contains(errText, "ten points: NOT all in order; missing 6, 7, 8, 9, 10"));
    CHECK_TRUE(contains(readAll(out), "outcome:    goal (20.00, 0.00) reached"));
    const char* anyOutcome[] = {"rse-demo", "--no-faults", "--quiet", "--no-report", "--any-outcome", "--duration", "20"};
    LONGS_EQUAL(0, sim::missionMain(7, anyOutcome, out, err));
    std::fclose(err);
}
