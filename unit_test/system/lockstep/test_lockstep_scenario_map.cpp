// Scenario files are what the rover flies (issue 17): the mission runner
// uplinks the scenario's site and known rocks as the COARSE_MAP table over the
// authenticated ground link before the GOTO, so the flight software plans on
// the scenario's map, not the compiled-in demo map. A goal beyond a smaller
// site's edge is refused (goal unreachable) instead of being driven into the
// edge; a rock the scenario marks known is planned round from the start.
#include <cstdio>
#include <string>

#include "sim_stub/lockstep/mission_runner.hpp"
#include "unit_test/support/mission_console.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;
using sim::Scenario;

namespace {

using Console = test::MissionConsole;

MissionOptions options(const char* gotoArg) {
    MissionOptions o;
    const char* argv[] = {"rse-demo", "--no-faults", "--goto", gotoArg};
    std::string error;
    CHECK_TRUE_TEXT(sim::parseMissionArgs(4, argv, &o, &error) == sim::ParseOutcome::kRun, error.c_str());
    o.durationS = 200.0;
    return o;
}

std::size_t count(const std::string& text, const char* what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
        ++n;
    }
    return n;
}

}  // namespace

TEST_GROUP(LockstepScenarioMap){};

// The site ends at x = 15 m: the rover is told so, and a goal at (20, 0) is
// off its site: called home before it moves, not driven into the edge.
TEST(LockstepScenarioMap, AGoalBeyondASmallerSitesEdgeIsRefusedNotDrivenIntoTheEdge) {
    MissionOptions o = options("20,0");
    o.editScenario = [](Scenario& s) { s.map.xMax = 15.0; };
    Console console;
    const MissionSummary s = sim::runMission(o, console.file);
    const std::string text = console.str();
    CHECK_TRUE_TEXT(s.outcome == MissionOutcome::kCalledHome, text.c_str());
    CHECK(s.callHome == msg::CallHomeReason::kGoalUnreachable);
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.distanceM < 0.5);
    LONGS_EQUAL(1, count(text, "ground: COARSE_MAP of the scenario (4 known obstacles"));
    LONGS_EQUAL(1, count(text, "EVT 562 INFO  table COARSE_MAP image loaded"));
}

// The demo's hidden rock made known: on the orbital map the rover is given,
// the first plan already goes round it (five obstacles, not four).
TEST(LockstepScenarioMap, ARockTheScenarioMarksKnownIsOnTheMapTheRoverPlansWith) {
    MissionOptions o = options("20,0");
    o.editScenario = [](Scenario& s) {
        for (sim::Obstacle& r : s.obstacles) {
            r.known = true;
        }
    };
    Console console;
    const MissionSummary s = sim::runMission(o, console.file);
    const std::string text = console.str();
    CHECK_TRUE_TEXT(s.outcome == MissionOutcome::kGoalReached, text.c_str());
    LONGS_EQUAL(0, s.collisions);
    LONGS_EQUAL(1, count(text, "ground: COARSE_MAP of the scenario (5 known obstacles"));
    CHECK_TRUE_TEXT(count(text, "risk 0.001, 5 obstacles, 0 seen") >= 1, text.c_str());
    LONGS_EQUAL(0, count(text, "risk 0.001, 4 obstacles"));
}
