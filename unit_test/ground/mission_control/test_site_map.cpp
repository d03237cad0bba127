// The site map of /api/map (ground/mission_control/site_map.hpp) from the
// COARSE_MAP source of a tables folder, compiled by the table compiler.
#include <string>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/mission_control/site_map.hpp"
#include "ground/table_compiler.hpp"
#include "unit_test/ground/mission_control/mc_test_support.hpp"

#include "CppUTest/TestHarness.h"

using rse::ground::mission_control::loadSiteMap;
using rse::ground::mission_control::SiteMap;
using rse::test::mc::ScratchDir;

TEST_GROUP(SiteMap){};

TEST(SiteMap, TheRepositorysTablesGiveSiteAndRocks) {
    const SiteMap map = loadSiteMap("tables");
    CHECK_TEXT(map.json.has_value(), map.error.c_str());
    const auto& json = *map.json;
    // tables/coarse_map.toml: site -5..30 x -10..10, four rocks.
    DOUBLES_EQUAL(-5.0, json["site"]["x_min"].get<double>(), 0.0);
    DOUBLES_EQUAL(30.0, json["site"]["x_max"].get<double>(), 0.0);
    DOUBLES_EQUAL(-10.0, json["site"]["y_min"].get<double>(), 0.0);
    DOUBLES_EQUAL(10.0, json["site"]["y_max"].get<double>(), 0.0);
    // Against the compiled table itself, slot by slot.
    const std::vector<std::uint8_t> image = rse::ground::compileTableSource("tables/coarse_map.toml");
    rse::tables::CoarseMapTable table{};
    CHECK_TRUE(rse::tables::decodeTable(image.data(), image.size(), &table).ok());
    const std::size_t slots = rse::geometry::coarseMapSlotsUsed(table);
    CHECK_TRUE(slots >= 1);
    CHECK_EQUAL(slots, json["rocks"].size());
    for (std::size_t slot = 0; slot < slots; ++slot) {
        const auto& rock = json["rocks"][slot];
        CHECK_EQUAL(slot, rock["id"].get<std::size_t>());
        CHECK_EQUAL(rse::geometry::coarseMapVerticesUsed(table, slot), rock["points"].size());
        const rse::geometry::Point2 first = rse::geometry::coarseMapVertex(table, slot, 0);
        DOUBLES_EQUAL(first.x, rock["points"][0][0].get<double>(), 1e-6);
        DOUBLES_EQUAL(first.y, rock["points"][0][1].get<double>(), 1e-6);
    }
    // Written as the source writes them (the float 1.8 as 1.8).
    DOUBLES_EQUAL(1.8, json["rocks"][0]["points"][0][1].get<double>(), 0.0);
}

TEST(SiteMap, AMissingOrBadMapSaysWhich) {
    ScratchDir dir;
    const SiteMap missing = loadSiteMap(dir.path());
    CHECK_FALSE(missing.json.has_value());
    STRCMP_CONTAINS((dir.path() + "/coarse_map.toml").c_str(), missing.error.c_str());

    dir.write("coarse_map.toml", "table = \"COARSE_MAP\"\nversion = 1\n[values]\nx_min_m = 5.0\n");
    const SiteMap bad = loadSiteMap(dir.path());
    CHECK_FALSE(bad.json.has_value());
    STRCMP_CONTAINS("coarse_map.toml", bad.error.c_str());
}
