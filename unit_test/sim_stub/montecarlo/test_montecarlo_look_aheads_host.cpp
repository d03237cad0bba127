// A Monte Carlo row of a site-mode mission (rock_field_100m.toml, its field
// drawn for the seed): the next horizons the deliberative layer planned while
// the rover drove are counted apart (look_aheads), one for each the flight
// software started (PLAN look_aheads_started, as the mission's "site:" line
// prints it), and plan_s lists only the plans the rover waited for. Host only
// (SUITE_HOST_ONLY_sim_stub_montecarlo): a 100 m mission, 30 s a target under
// qemu-user for bookkeeping no architecture changes.
#include <cstdio>
#include <string>

#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "unit_test/support/mission_console.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;
using namespace rse::sim::mc;

TEST_GROUP(MonteCarloLookAheads) {};

TEST(MonteCarloLookAheads, LookAheadsAreCountedApartAndPlanLatenciesAreThePlansWaitedFor) {
    CampaignSpec spec;
    std::string error;
    CHECK_TRUE_TEXT(prepareCampaign({"--scenario", "sim_stub/scenarios/rock_field_100m.toml"}, &spec, &error),
                    error.c_str());
    rse::test::MissionConsole console;
    const SeedRun run = runSeed(spec, 1, console.file);
    Row row;
    CHECK_TRUE_TEXT(parseRow(run.row, &row, &error), error.c_str());
    STRCMP_EQUAL("goal_reached", row.outcome.c_str());
    const std::string out = console.str();
    const std::size_t at = out.find(" look-aheads started");
    CHECK_TEXT(at != std::string::npos, "no site: line in the mission's summary");
    const std::size_t from = out.rfind(' ', at - 1) + 1;
    const unsigned started = static_cast<unsigned>(std::stoul(out.substr(from, at - from)));
    CHECK(started > 0);
    LONGS_EQUAL(started, row.lookAheads);
    // The rest were waited for: fewer than the plans that drove the rover
    // (some of those were look-aheads taken at a horizon's end), one at least.
    CHECK(!row.planLatencyS.empty());
    CHECK(row.planLatencyS.size() < row.plans);
    LONGS_EQUAL(row.planLatencyS.size(), row.planSlices.size());
}
