// rse-demo's logic (sim_stub/lockstep/mission_runner.hpp): its command line
// (the goal checked against the dictionary's GOTO ranges), its exit codes, the
// summary's wording, and short lockstep missions judged against the truth the
// summary reports. The full 20 m mission and its call home are in
// test_lockstep_deliberative.cpp.
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fsw/core/byte_codec.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"

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

TEST(MissionDemoOptions, NoArgumentsIsTheDemoMissionToTwentyMetres) {
    CHECK(ParseOutcome::kRun == parse({}, &o, &error));
    STRCMP_EQUAL("sim_stub/scenarios/demo_mission.toml", o.scenarioPath.c_str());
    CHECK_FALSE(o.clearFaults);
    CHECK_FALSE(o.quiet);
    DOUBLES_EQUAL(180.0, o.durationS, 0.0);
    checkGotoArgs(o, 20.0, 0.0, 1e-3);
}

TEST(MissionDemoOptions, EveryOptionIsTaken) {
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
