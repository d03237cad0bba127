// A generated rock field flown in lockstep (issue 31, "In make test"): a
// 100 m traverse through Golombek and Rapp's k = 0.10 field of over 300
// rocks (sim_stub/scenarios/rock_field_100m.toml): the known ones uplinked as
// the site map, the hidden ones found by the hazard detector. The rover
// routes over the site map, plans horizon after horizon along the route,
// reaches the goal and touches no rock.
#include <cstdio>
#include <string>

#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/support/mission_console.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

constexpr const char* kScenario = "sim_stub/scenarios/rock_field_100m.toml";

std::size_t count(const std::string& text, const char* what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) {
        ++n;
    }
    return n;
}

}  // namespace

TEST_GROUP(LockstepRockField){};

TEST(LockstepRockField, AHundredMetresThroughThreeHundredRocksReachesTheGoalWithoutAContact) {
    const sim::Scenario scenario = sim::loadScenarioFile(kScenario);
    const sim::FieldCounts field = sim::fieldCounts(scenario);
    CHECK(field.rocks >= 300);
    CHECK(field.known > 10);
    CHECK(field.known < field.rocks);
    CHECK_TRUE(scenario.usesSiteMap());

    sim::MissionOptions o;
    const char* argv[] = {"rse-demo", "--scenario", kScenario, "--no-report"};
    std::string error;
    CHECK_TRUE_TEXT(sim::parseMissionArgs(4, argv, &o, &error) == sim::ParseOutcome::kRun, error.c_str());
    test::MissionConsole console;
    const sim::MissionSummary s = sim::runMission(o, console.file);
    const std::string out = console.str();

    CHECK_TRUE_TEXT(s.outcome == sim::MissionOutcome::kGoalReached, out.substr(out.size() > 4000 ? out.size() - 4000 : 0).c_str());
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.leastClearanceM > 0.0);
    CHECK(s.goalDistanceM < 0.5);
    // The known rocks went up as the site map, and the layer routed over it once.
    LONGS_EQUAL(1, count(out, "ground: site map of the scenario"));
    LONGS_EQUAL(1, count(out, "EVT 590 INFO  site_map: map 1 in force"));
    LONGS_EQUAL(1, count(out, "EVT 993 INFO  deliberative: route to goal 0"));
    LONGS_EQUAL(0, count(out, "EVT 994"));
    // Horizons: more than one plan for the one goal (100 m in 30 m horizons).
    CHECK(s.plansMade >= 4);
    LONGS_EQUAL(0, s.callHomes);
    // The path driven against the straight 100 m (the bound at worst: 1.46).
    CHECK(s.distanceM < 1.46 * 100.0);
}
