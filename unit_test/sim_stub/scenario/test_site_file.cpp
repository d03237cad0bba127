// Site files (sim_stub/scenario/site_file.hpp): a scenario's rocks written by
// rse-sim --site-file read back as the same rocks, to the last bit, when a
// scenario names the file with [site] file; the shipped 100 m site is what
// the generator writes for rock_field_100m.toml; and every way a site file
// can be wrong is refused with its file, line and reason.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <unistd.h>

#include "sim_stub/scenario/field_rocks.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "sim_stub/scenario/site_file.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;

namespace {

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// The same rocks: ids, flags, vertices (within toleranceM; 0: to the bit).
void expectSameRocks(const Scenario& a, const Scenario& b, double toleranceM = 0.0) {
    LONGS_EQUAL(a.obstacles.size(), b.obstacles.size());
    for (std::size_t i = 0; i < a.obstacles.size(); ++i) {
        const Obstacle& p = a.obstacles[i];
        const Obstacle& q = b.obstacles[i];
        LONGS_EQUAL(p.id, q.id);
        CHECK_EQUAL(p.known, q.known);
        CHECK_EQUAL(p.detectable, q.detectable);
        LONGS_EQUAL(p.shape.n, q.shape.n);
        for (std::size_t k = 0; k < p.shape.n; ++k) {
            DOUBLES_EQUAL(p.shape.v[k].x, q.shape.v[k].x, toleranceM);
            DOUBLES_EQUAL(p.shape.v[k].y, q.shape.v[k].y, toleranceM);
        }
    }
}

}  // namespace

TEST_GROUP(SiteFile) {
    std::string dir;
    void setup() override {
        char pattern[] = "/tmp/rse_site_file_XXXXXX";
        dir = mkdtemp(pattern);
    }
    void teardown() override { std::filesystem::remove_all(dir); }

    // A scenario on the open 20 m x 20 m site naming a site file with body
    // (after the header and map lines, unless raw): the error it gets ("" for none).
    std::string errorWith(const std::string& body, bool raw = false) {
        const std::string header = raw ? "" : "rse-site 1\nmap -10 -10 10 10\n";
        std::ofstream(dir + "/s.site") << header << body;
        std::ofstream(dir + "/s.toml") << rse::test::kOpenSiteScenario << "[site]\nfile = \"s.site\"\n";
        Scenario s;
        std::string error;
        return tryLoadScenarioFile(dir + "/s.toml", &s, &error) ? "" : error;
    }
};

// rock_field_100m.toml's generated field written as a site file and named by
// a scenario: the same rocks (ids, known, seen, every vertex to the bit),
// flown with the site map.
TEST(SiteFile, AFieldWrittenAsASiteFileReadsBackAsTheSameRocks) {
    const Scenario field = loadScenarioFile("sim_stub/scenarios/rock_field_100m.toml");
    CHECK(field.obstacles.size() >= 300);
    std::ofstream(dir + "/field.site") << siteFileText(field);
    std::string scenario = readFile("sim_stub/scenarios/rock_field_100m.toml");
    scenario = scenario.substr(0, scenario.find("[field]")) + "[site]\nfile = \"field.site\"\n";
    std::ofstream(dir + "/field.toml") << scenario;
    const Scenario site = loadScenarioFile(dir + "/field.toml");
    expectSameRocks(field, site);
    CHECK_TRUE(site.usesSiteMap());
    STRCMP_EQUAL((dir + "/field.site").c_str(), site.siteFile.c_str());
    LONGS_EQUAL(fieldCounts(field).known, fieldCounts(site).known);
}

// The shipped site file is the generator's output for the shipped field
// (`rse-sim --site-file sim_stub/scenarios/rock_field_100m.toml`, written on
// x86-64; byte for byte on the host in unit_test/integration/rse_sim_cli_test.sh),
// and the scenario naming it is the field's scenario in all a flight depends
// on (its map, start, mission, seed, duration and rocks), so it flies the same
// mission (test_lockstep_rock_field.cpp flies that one). Other targets draw
// the field with their own libm, its last bits another's (s390x): the rocks
// agree within 0.1 mm there, not to the bit.
TEST(SiteFile, TheShippedSiteIsWhatTheGeneratorWritesForTheShippedField) {
    const Scenario field = loadScenarioFile("sim_stub/scenarios/rock_field_100m.toml");
    const Scenario site = loadScenarioFile("sim_stub/scenarios/rock_field_100m_site.toml");
    expectSameRocks(field, site, 1e-4);
    STRCMP_EQUAL("sim_stub/scenarios/sites/rock_field_100m.site", site.siteFile.c_str());
    CHECK_TRUE(site.map.xMin == field.map.xMin && site.map.xMax == field.map.xMax && site.map.yMin == field.map.yMin &&
               site.map.yMax == field.map.yMax);
    CHECK_TRUE(site.start.x == field.start.x && site.start.y == field.start.y && site.start.theta == field.start.theta);
    CHECK_TRUE(site.mission.goalX == field.mission.goalX && site.mission.goalY == field.mission.goalY &&
               site.mission.riskBound == field.mission.riskBound);
    CHECK_TRUE(site.seed == field.seed && site.durationS == field.durationS);
    CHECK_TRUE(site.usesSiteMap() && field.usesSiteMap());
}

TEST(SiteFile, EveryFaultOfASiteFileIsRefusedWithItsLineAndReason) {
    const std::string file = dir + "/s.site";
    const std::string tri = " 1 1 2 1 1 2\n";
    struct Case {
        std::string body;
        bool raw;
        std::string message;
    };
    const Case cases[] = {
        {"rse-sit 1\n", true, file + ":1: not a site file (it starts with 'rse-site 1')"},
        {"# a comment\n\nrse-site 2\n", true, file + ":3: site file version 2; this rse-sim reads version 1"},
        {"rse-site 1\n", true, file + ": ends before its map line"},
        {"", true, file + ": ends before its 'rse-site 1' line"},
        {"rse-site 1\nmap -10 -10 10 11\n", true,
         file + ":2: the site file is for the map -10 -10 10 11; the scenario's [map] is -10 -10 10 10"},
        {"rse-site 1\nrock known seen" + tri, true, file + ":2: the second line is 'map X_MIN Y_MIN X_MAX Y_MAX'"},
        {"boulder known seen" + tri, false,
         file + ":3: unknown line 'boulder' (a rock line is 'rock known|hidden seen|unseen X0 Y0 ...')"},
        {"rock known maybe" + tri, false, file + ":3: a rock line is 'rock known|hidden seen|unseen X0 Y0 ...'"},
        {"rock known seen 1 1 2 1 1\n", false, file + ":3: an odd number of coordinates (5): vertices are x y pairs"},
        {"rock hidden seen 1 1 2 1\n", false, file + ":3: needs 3 to 16 vertices (got 2)"},
        {"rock known seen 1 1 2 one 1 2\n", false, file + ":3: 'one' is not a number"},
        {"rock known seen 1 1 2 nan 1 2\n", false, file + ":3: 'nan' is not finite"},
        {"rock known seen 1 1 12 1 1 2\n", false, file + ":3: vertex 1 (12, 1) is outside the map"},
        {"rock known seen 1 1 1 2 2 1\n", false, file + ":3: the rock is not convex and counter-clockwise"},
        {"rock known seen 2 0 2.5 0.1 3 0.3 3.3 0.7 3.4 1.2 3.3 1.7 3 2.1 2.5 2.3 2 2.4\n", false,
         file + ":3: a known rock goes up on the site map: at most 8 vertices (got 9)"},
        {"rock known seen 1 1 2 1 2.000000001 1.5 2 2\n", false,
         file + ":3: as the site map's f32 numbers the rock is not convex and counter-clockwise"},
        {"rock known seen -1 -1 1 -1 0 1\n", false, file + ":3: the rock overlaps the rover's footprint at the start"},
        {"rock known seen" + tri + "rock hidden unseen 5 5 6 5 5 6 # fine\nrock known seen 1 1\n", false,
         file + ":5: needs 3 to 16 vertices (got 1)"},
    };
    for (const Case& c : cases) {
        STRCMP_EQUAL_TEXT(c.message.c_str(), errorWith(c.body, c.raw).c_str(), c.body.c_str());
    }
    // A hidden rock stays in the simulator: up to 16 vertices.
    STRCMP_EQUAL("", errorWith("rock hidden seen 2 0 2.5 0.1 3 0.3 3.3 0.7 3.4 1.2 3.3 1.7 3 2.1 2.5 2.3 2 2.4\n").c_str());
    // Good: two rocks, one hidden and unseen, a comment; ids from 256.
    STRCMP_EQUAL("", errorWith("rock known seen" + tri + "# a hidden one\nrock hidden unseen 5 5 6 5 5 6\n").c_str());
    const Scenario s = loadScenarioFile(dir + "/s.toml");
    LONGS_EQUAL(2, s.obstacles.size());
    LONGS_EQUAL(kFirstFieldRockId + 1, s.obstacles[1].id);
    CHECK_FALSE(s.obstacles[1].known);
    CHECK_FALSE(s.obstacles[1].detectable);
}

TEST(SiteFile, AMissingFileOrASiteBesideAFieldIsRefused) {
    std::ofstream(dir + "/m.toml") << rse::test::kOpenSiteScenario << "[site]\nfile = \"nowhere.site\"\n";
    Scenario s;
    std::string error;
    CHECK_FALSE(tryLoadScenarioFile(dir + "/m.toml", &s, &error));
    STRCMP_EQUAL((dir + "/nowhere.site: cannot read the site file").c_str(), error.c_str());
    CHECK_FALSE(tryParseScenario(rse::test::kOpenSiteScenario + "[field]\nk = 0.1\n[site]\nfile = \"x.site\"\n",
                                 "both.toml", &s, &error));
    STRCMP_CONTAINS("a scenario has a [field] or a [site] file, not both", error.c_str());
    CHECK_FALSE(tryParseScenario(rse::test::kOpenSiteScenario + "[site]\nfile = \"\"\n", "empty.toml", &s, &error));
    STRCMP_CONTAINS("must name a site file", error.c_str());
}
