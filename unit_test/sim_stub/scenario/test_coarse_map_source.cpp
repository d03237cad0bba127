// The scenario's orbital map as the rover is told it (coarse_map_source.hpp):
// the demo scenario's is the default COARSE_MAP table byte for byte (so the
// compiled-in map and the demo cannot drift apart); hidden rocks are left
// out; a scenario whose known rocks do not fit the table is refused.
#include <cmath>
#include <string>

#include "fsw/tables/table_image.hpp"
#include "ground/table_compiler.hpp"
#include "sim_stub/scenario/coarse_map_source.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::Obstacle;
using sim::Scenario;

namespace {

Obstacle square(std::uint8_t id, double x, double y, bool known, std::size_t vertices = 4) {
    Obstacle o;
    o.id = id;
    o.known = known;
    o.shape.n = vertices;
    for (std::size_t k = 0; k < vertices; ++k) {
        const double a = 6.283185307179586 * static_cast<double>(k) / static_cast<double>(vertices);
        o.shape.v[k] = {x + std::cos(a), y + std::sin(a)};
    }
    return o;
}

}  // namespace

TEST_GROUP(CoarseMapSource){};

TEST(CoarseMapSource, TheDemoScenariosMapIsTheDefaultTableByteForByte) {
    const Scenario s = sim::loadScenarioFile("sim_stub/scenarios/demo_mission.toml");
    const auto fromScenario = ground::compileTableText(sim::coarseMapSource(s), "demo");
    const auto shipped = ground::compileTableFile("tables/coarse_map.toml");
    CHECK(fromScenario.image == shipped.image);
    CHECK_TRUE(tables::checkTableImage(fromScenario.image.data(), fromScenario.image.size()).ok());
}

TEST(CoarseMapSource, HiddenRocksAreLeftOutAndTheBoundsAreTheScenarios) {
    Scenario s;
    s.name = "t";
    s.map = sim::MapBounds{-3.0, 12.5, -4.0, 6.25};
    s.obstacles = {square(7, 5.0, 0.0, true), square(8, 8.0, 1.0, false), square(9, 9.0, -2.0, true, 6)};
    const std::string text = sim::coarseMapSource(s);
    const auto t = ground::compileTableText(text, "t");
    CHECK_TRUE(tables::checkTableImage(t.image.data(), t.image.size()).ok());
    CHECK(text.find("x_max_m = 12.5000") != std::string::npos);
    CHECK(text.find("y_max_m = 6.2500") != std::string::npos);
    CHECK(text.find("obstacle_count = 2") != std::string::npos);
    CHECK(text.find("vertex_count = [4, 6, 0,") != std::string::npos);
    CHECK(text.find("scenario obstacle 7") != std::string::npos);
    CHECK(text.find("scenario obstacle 9") != std::string::npos);
    CHECK(text.find("scenario obstacle 8") == std::string::npos);  // hidden
}

// More known rocks than the table holds go with the site map (issue 31):
// COARSE_MAP keeps the site's bounds alone, the site map has every known rock.
TEST(CoarseMapSource, MoreKnownRocksThanTheTableHoldsGoWithTheSiteMap) {
    Scenario s;
    s.name = "crowded";
    for (std::uint8_t i = 1; i <= 17; ++i) {
        s.obstacles.push_back(square(i, 3.0 * i, 0.0, true));
    }
    s.obstacles.push_back(square(40, 0.0, 9.0, false));   // hidden: on neither
    CHECK_TRUE(s.usesSiteMap());
    const std::string text = sim::coarseMapSource(s);
    CHECK(text.find("obstacle_count = 0") != std::string::npos);
    CHECK(text.find("its known rocks go with the site map") != std::string::npos);
    const ground::SiteMapSpec spec = sim::siteMapSpec(s);
    LONGS_EQUAL(17, spec.rocks.size());
    DOUBLES_EQUAL(s.map.xMax, spec.site.xMax, 1e-6);
    DOUBLES_EQUAL(3.0 * 17 + 1.0, spec.rocks[16][0].x, 1e-4);   // its first vertex
}

TEST(CoarseMapSource, KnownRocksThatDoNotFitTheTableAreRefused) {
    Scenario s;
    s.name = "crowded";
    for (std::uint8_t i = 1; i <= 16; ++i) {
        s.obstacles.push_back(square(i, 3.0 * i, 0.0, true));
    }
    s.obstacles.push_back(square(30, 0.0, 9.0, false));  // a 17th, hidden: fine
    CHECK(!sim::coarseMapSource(s).empty());
    s.obstacles[0] = square(1, 3.0, 0.0, true, 9);  // 9 vertices
    CHECK_THROWS(sim::CoarseMapError, sim::coarseMapSource(s));
}
