// Monte Carlo result files and the table (sim_stub/montecarlo/results.hpp,
// docs/montecarlo.md): rows round-trip through their text, files are checked
// whole (campaign, end line, conflicting seeds), missing seeds are named, and
// the table depends on the rows only, not on how they were split into files.
#include <cstdint>
#include <string>
#include <vector>

#include "sim_stub/montecarlo/results.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim::mc;

namespace {

const std::string kCampaign =
    "C format=3 variation=2 scenario=s.toml scenario_fnv=00 goal=20,0 risk=0.001 duration=180 faults=on first=10 "
    "count=6";

Row row(std::uint64_t seed, const char* outcome = "goal_reached", std::uint32_t collisions = 0,
        std::uint32_t riskRelax = 0) {
    Row r;
    r.seed = seed;
    r.outcome = outcome;
    r.reason = std::string(outcome) == "called_home" ? "mobility_lost" : "-";
    r.outcomeS = 90.0 + static_cast<double>(seed);
    r.distanceM = 21.5;
    r.energyWh = 6.75 + 0.01 * static_cast<double>(seed);
    r.goalDistanceM = 0.04;
    r.clearanceM = 0.4;
    r.collisions = collisions;
    r.plans = 2;
    r.legsSent = 6;
    r.legsAchieved = 6;
    r.failUps = static_cast<std::uint32_t>(seed % 3);
    r.replans = 1;
    r.riskRelaxations = riskRelax;
    r.riskBound = 1e-3;
    r.riskInForce = riskRelax > 0 ? 1e-2 : 1e-3;
    r.riskUsed = 9.17e-6;
    r.planLatencyS = {0.4, 0.8};
    r.planSlices = {4, 8};
    r.planFound = {1, 1};
    r.rocks = "1.292,0.401";
    r.faults = "20.462,82.165";
    return r;
}

// A result file's text holding the given rows.
std::string file(const std::vector<Row>& rows, bool ended = true, const std::string& campaign = kCampaign) {
    std::string t = "# test\n" + campaign + "\nB first=10 count=6 task=- jobs=1 host=h slurm_job=-\n";
    for (const Row& r : rows) {
        Timing tm;
        tm.seed = r.seed;
        tm.wallS = 0.1;
        tm.planHostMs = {1.0, 2.0};
        t += formatRow(r) + "\n" + formatTiming(tm) + "\n";
    }
    if (ended) {
        t += "E rows=" + std::to_string(rows.size()) + "\n";
    }
    return t;
}

bool contains(const std::string& text, const std::string& what) { return text.find(what) != std::string::npos; }

}  // namespace

TEST_GROUP(MonteCarloResults) {
    ResultSet set;
    std::string error;
};

TEST(MonteCarloResults, ARowRoundTripsThroughItsText) {
    const Row r = row(12, "called_home", 1, 2);
    const std::string text = formatRow(r);
    Row back;
    CHECK_TRUE(parseRow(text, &back, &error));
    STRCMP_EQUAL(text.c_str(), formatRow(back).c_str());
    LONGS_EQUAL(12, back.seed);
    STRCMP_EQUAL("called_home", back.outcome.c_str());
    STRCMP_EQUAL("mobility_lost", back.reason.c_str());
    LONGS_EQUAL(1, back.collisions);
    LONGS_EQUAL(2, back.riskRelaxations);
    LONGS_EQUAL(2, back.planLatencyS.size());
    DOUBLES_EQUAL(0.8, back.planLatencyS[1], 1e-12);
    LONGS_EQUAL(8, back.planSlices[1]);
    STRCMP_EQUAL("20.462,82.165", back.faults.c_str());
    STRCMP_EQUAL("-", back.field.c_str());
    Row fielded = row(12);
    fielded.field = "3141592";
    CHECK_TRUE(contains(formatRow(fielded), " field=3141592 rocks="));
    CHECK_TRUE(parseRow(formatRow(fielded), &back, &error));
    STRCMP_EQUAL("3141592", back.field.c_str());
    CHECK_FALSE(parseRow(formatRow(r).replace(formatRow(r).find(" field=-"), 8, ""), &back, &error));
    fielded.field = "12x";
    CHECK_FALSE(parseRow(formatRow(fielded), &back, &error));
    STRCMP_CONTAINS("field", error.c_str());
    CHECK_FALSE(row(12, "called_home", 1, 2).withinRiskBound());
    CHECK_TRUE(row(1).withinRiskBound());
    // No plan at all: empty lists as "-".
    Row none = row(3);
    none.planLatencyS.clear();
    none.planSlices.clear();
    none.planFound.clear();
    CHECK_TRUE(contains(formatRow(none), " plan_s=- plan_slices=- plan_found=- "));
    CHECK_TRUE(parseRow(formatRow(none), &back, &error));
    LONGS_EQUAL(0, back.planLatencyS.size());
}

TEST(MonteCarloResults, BadRowsAreRefusedWithTheReason) {
    Row back;
    const std::string good = formatRow(row(5));
    std::string noSeed = good;
    noSeed.replace(noSeed.find("seed=5"), 6, "sd=5");
    CHECK_FALSE(parseRow(noSeed, &back, &error));
    std::string badCount = good;
    badCount.replace(badCount.find("replans=1"), 9, "replans=x");
    CHECK_FALSE(parseRow(badCount, &back, &error));
    CHECK_TRUE(contains(error, "replans"));
    std::string shortList = good;
    shortList.replace(shortList.find("plan_slices=4,8"), 15, "plan_slices=4");
    CHECK_FALSE(parseRow(shortList, &back, &error));
    CHECK_FALSE(parseRow("R seed=5 seed=6", &back, &error));
    CHECK_FALSE(parseRow("T seed=5", &back, &error));
}

TEST(MonteCarloResults, FilesMergeAndNameTheSeedsMissing) {
    CHECK_TRUE(addResultText(file({row(10), row(11), row(12)}), "a.txt", &set, &error));
    CHECK_TRUE(addResultText(file({row(14), row(15)}), "b.txt", &set, &error));
    LONGS_EQUAL(2, set.files);
    LONGS_EQUAL(10, set.firstSeed);
    LONGS_EQUAL(6, set.seedCount);
    const std::vector<std::uint64_t> missing = missingSeeds(set);
    LONGS_EQUAL(1, missing.size());
    LONGS_EQUAL(13, missing[0]);
    // The same seed again with the same row is no harm (a task run twice).
    CHECK_TRUE(addResultText(file({row(12)}), "c.txt", &set, &error));
    CHECK_TRUE(addResultText(file({row(13), row(16)}), "d.txt", &set, &error));
    LONGS_EQUAL(0, missingSeeds(set).size());
    const std::vector<std::uint64_t> strangers = strangerSeeds(set);
    LONGS_EQUAL(1, strangers.size());
    LONGS_EQUAL(16, strangers[0]);
}

TEST(MonteCarloResults, ABrokenOrForeignFileIsRefused) {
    CHECK_TRUE(addResultText(file({row(10)}), "a.txt", &set, &error));
    CHECK_FALSE(addResultText(file({row(11)}, false), "cut.txt", &set, &error));
    CHECK_TRUE(contains(error, "cut.txt") && contains(error, "no E line"));
    std::string miscounted = file({row(11)});
    miscounted.replace(miscounted.find("E rows=1"), 8, "E rows=2");
    CHECK_FALSE(addResultText(miscounted, "n.txt", &set, &error));
    std::string other = kCampaign;
    other.replace(other.find("risk=0.001"), 10, "risk=0.01");
    CHECK_FALSE(addResultText(file({row(11)}, true, other), "o.txt", &set, &error));
    CHECK_TRUE(contains(error, "another campaign"));
    Row changed = row(10);
    changed.collisions = 1;
    CHECK_FALSE(addResultText(file({changed}), "d.txt", &set, &error));
    CHECK_TRUE(contains(error, "seed 10 again with another result"));
    CHECK_FALSE(addResultText("R seed=1\n", "nc.txt", &set, &error));
    CHECK_TRUE(contains(error, "no C line"));
}

TEST(MonteCarloResults, TheTableDependsOnTheRowsNotOnTheFiles) {
    const std::vector<Row> rows = {row(10), row(11, "called_home"), row(12), row(13, "called_home", 2, 1),
                                   row(14), row(15, "timed_out")};
    ResultSet whole;
    CHECK_TRUE(addResultText(file(rows), "whole.txt", &whole, &error));
    ResultSet split;
    CHECK_TRUE(addResultText(file({rows[4], rows[5], rows[3]}), "b.txt", &split, &error));
    CHECK_TRUE(addResultText(file({rows[0], rows[1], rows[2]}), "a.txt", &split, &error));
    const std::string table = formatTable(whole);
    STRCMP_EQUAL(table.c_str(), formatTable(split).c_str());
    // What it says: outcomes, the collision by seed, the checks.
    CHECK_TRUE(contains(table, "6 runs of seeds 10..15"));
    CHECK_TRUE(contains(table, "  goal_reached                          3     50.0\n"));
    CHECK_TRUE(contains(table, "    mobility_lost                       2     33.3\n"));
    CHECK_TRUE(contains(table, "seed 13 (2 contacts, bound relaxed)"));
    CHECK_TRUE(contains(table, "to the goal (3 runs)"));
    CHECK_TRUE(contains(table, "planner: 12 plans, 12 found"));
    CHECK_TRUE(contains(table, "CHECK collisions in runs whose plans were within the risk bound: 0 (must be 0) PASS"));
    LONGS_EQUAL(0, failedChecks(whole));
    // A collision with every plan within the bound fails the check.
    ResultSet bad;
    CHECK_TRUE(addResultText(file({row(10), row(11, "goal_reached", 1)}), "bad.txt", &bad, &error));
    CHECK_TRUE(contains(formatTable(bad), "seed 11 (1 contact, within the bound)"));
    CHECK_TRUE(contains(formatTable(bad), "within the risk bound: 1 (must be 0) FAIL"));
    LONGS_EQUAL(1, failedChecks(bad));
    // The host timing is apart from the table.
    CHECK_FALSE(contains(table, "host timing"));
    CHECK_TRUE(contains(formatHostTiming(whole), "planner per plan (host ms)"));
}

TEST(MonteCarloResults, PercentilesAreNearestRank) {
    const std::vector<double> v = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    DOUBLES_EQUAL(5.0, percentile(v, 0.5), 0.0);
    DOUBLES_EQUAL(9.0, percentile(v, 0.9), 0.0);
    DOUBLES_EQUAL(10.0, percentile(v, 0.99), 0.0);
    DOUBLES_EQUAL(10.0, percentile(v, 1.0), 0.0);
    DOUBLES_EQUAL(1.0, percentile(v, 0.01), 0.0);
    DOUBLES_EQUAL(7.0, percentile({7.0}, 0.5), 0.0);
}
