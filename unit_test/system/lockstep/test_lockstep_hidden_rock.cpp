// Lockstep: whole missions (rse-demo's runner) with the demo's hidden rock
// moved along the route, and the demo itself at other risk bounds and another
// seed (issue 13, "No path after a small hidden rock ends the mission"). The
// rock is a 1 m x 1 m square centred on (x, 0) for x = 2 .. 18: there is open
// ground round every one of them, so every mission must reach the goal
// (20, 0) without contact. Before the seen hazards reached the deliberative
// layer, 13 of the 17 ended in a call home "replans exhausted (no path)".
// Here every fourth metre (2, 6, 10, 14, 18), on every target; the twelve
// between on the host (test_lockstep_hidden_rock_sweep_host.cpp).
//
// Each variant is the demo scenario's text with one line changed, written to a
// temporary file and run like `rse-demo --no-faults --scenario FILE`
// (hidden_rock_runs.hpp). The sweep prints its wall time.
#include <string>

#include "unit_test/system/lockstep/hidden_rock_runs.hpp"

using namespace rse;
using namespace rse::test::hidden_rock;

TEST_GROUP(LockstepHiddenRock) {};

// Every fourth metre on every target; the metres between on the host
// (test_lockstep_hidden_rock_sweep_host.cpp): the sweep is about the
// planners' answers, which the five cover on the emulated targets.
TEST(LockstepHiddenRock, ARockOnTheRouteAtEveryFourthMetreFromTwoToEighteenIsPassedAndTheGoalReached) {
    sweep({2, 6, 10, 14, 18});
}

TEST(LockstepHiddenRock, TheDemoWithoutFaultsReachesTheGoalAtEveryRiskBound) {
    const char* const risks[] = {"1e-2", "1e-4", "1e-6"};
    for (const char* risk : risks) {
        const std::string what = std::string("risk ") + risk;
        CHECK_TRUE_TEXT(reachedCleanly(runDemo(sim::kDefaultMissionScenario, risk), what.c_str()), what.c_str());
    }
}

TEST(LockstepHiddenRock, TheDemoWithoutFaultsReachesTheGoalWithSeedOne) {
    const std::string path = variant(kSeedLine, "seed = 1");
    CHECK_FALSE(path.empty());
    const MissionSummary s = runDemo(path, "1e-3");
    std::remove(path.c_str());
    CHECK_TRUE(reachedCleanly(s, "seed 1"));
}
