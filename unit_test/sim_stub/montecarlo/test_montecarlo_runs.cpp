// Monte Carlo runs of the demo mission (sim_stub/montecarlo/campaign.hpp): a
// seed reproduces exactly (the same row, twice), another seed gives another
// run, and the row says what the seed varied and what the planner did.
#include <cstdint>
#include <string>
#include <vector>

#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;
using namespace rse::sim::mc;

namespace {

CampaignSpec demoCampaign() {
    CampaignSpec spec;
    std::string error;
    if (!prepareCampaign({}, &spec, &error)) {
        FAIL(error.c_str());
    }
    return spec;
}

}  // namespace

TEST_GROUP(MonteCarloRuns) {};

TEST(MonteCarloRuns, TheCampaignLineNamesTheMissionAndTheScenarioBytes) {
    CampaignSpec spec = demoCampaign();
    spec.firstSeed = 5;
    spec.seedCount = 20;
    const std::string line = campaignLine(spec);
    STRCMP_CONTAINS("scenario=sim_stub/scenarios/demo_mission.toml scenario_fnv=", line.c_str());
    STRCMP_CONTAINS(" goal=20,0 risk=0.001 duration=180 faults=on first=5 count=20", line.c_str());
    LONGS_EQUAL(16, spec.scenarioHash.size());
    CampaignSpec other;
    std::string error;
    CHECK_TRUE(prepareCampaign({"--no-faults", "--goto", "12,3,1e-2"}, &other, &error));
    STRCMP_CONTAINS(" goal=12,3 risk=0.01 duration=180 faults=off", campaignLine(other).c_str());
    CHECK_FALSE(prepareCampaign({"--goto", "1e9,0"}, &other, &error));
    CHECK_FALSE(prepareCampaign({"--quiet"}, &other, &error));
    CHECK_FALSE(prepareCampaign({"--scenario", "no/such.toml"}, &other, &error));
}

TEST(MonteCarloRuns, TheSameSeedGivesTheSameRowAndAnotherSeedAnother) {
    const CampaignSpec spec = demoCampaign();
    const SeedRun a = runSeed(spec, 5);
    const SeedRun b = runSeed(spec, 5);
    STRCMP_EQUAL(a.row.c_str(), b.row.c_str());
    const SeedRun c = runSeed(spec, 6);
    CHECK(a.row != c.row);

    Row r;
    std::string error;
    CHECK_TRUE(parseRow(a.row, &r, &error));
    LONGS_EQUAL(5, r.seed);
    CHECK(r.outcome == "goal_reached" || r.outcome == "called_home" || r.outcome == "timed_out");
    CHECK(r.plans >= 1);
    CHECK(!r.planLatencyS.empty());
    for (std::size_t i = 0; i < r.planLatencyS.size(); ++i) {
        // Every plan waits at least one deliberative run (10 Hz) and steps the planner.
        CHECK(r.planLatencyS[i] >= 0.1 - 1e-9);
        CHECK(r.planSlices[i] >= 1);
    }
    CHECK(r.rocks != "-");   // the demo's hidden rock moved
    CHECK(r.faults != "-");  // and its faults' times drawn
    Timing t;
    CHECK_TRUE(parseTiming(a.timing, &t, &error));
    LONGS_EQUAL(5, t.seed);
    LONGS_EQUAL(r.planLatencyS.size(), t.planHostMs.size());
    CHECK(t.wallS > 0.0);
}

// A seed's edit that does not fit (a field drawn afresh that the world cannot
// take) is a setup failure with its reason, not a worker killed by an
// uncaught exception.
TEST(MonteCarloRuns, AnEditThatDoesNotFitIsASetupFailureWithItsReason) {
    MissionOptions o = demoCampaign().mission;
    o.quiet = true;
    o.editScenario = [](Scenario&) { throw ScenarioError("field: more known rocks than the site map holds"); };
    const MissionSummary m = runMission(o, nullptr);
    CHECK(m.outcome == MissionOutcome::kSetupFailed);
    STRCMP_CONTAINS("more known rocks", m.setupError.c_str());
}
