// The site map in force (site_map.hpp): a 1 km x 1 km field of 5 000 rocks
// loads, every query near a segment lists exactly the rocks a scan of the
// whole map finds (each once) at a cost of the rocks nearby, a refused
// image leaves the map as it was, a map staged in small steps is the map in
// force, untouched, until it is whole and put in force, and the memory is
// what docs/site_map.md says.
#include <algorithm>
#include <cstdint>
#include <random>
#include <set>
#include <vector>

#include "fsw/site_map/site_map.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::site_map;
using rse::geometry::Point2;

namespace {

SiteMap* map = nullptr;   // ~1 MB: static storage, as in flight
SiteQuery* query = nullptr;

// Every rock whose box is within reach of a -> b, by scanning them all.
std::set<std::uint16_t> scan(const SiteMap& m, Point2 a, Point2 b, double reach) {
    std::set<std::uint16_t> near;
    for (std::size_t r = 0; r < m.rockCount(); ++r) {
        const Rock& k = m.rock(r);
        const Point2 c[4] = {{k.minX, k.minY}, {k.maxX, k.minY}, {k.maxX, k.maxY}, {k.minX, k.maxY}};
        double best = INFINITY;
        for (std::size_t e = 0; e < 4; ++e) {
            best = std::min(best, rse::geometry::segmentSegmentDistanceSquared(a, b, c[e], c[(e + 1) % 4]));
        }
        const bool inside = (a.x >= k.minX && a.x <= k.maxX && a.y >= k.minY && a.y <= k.maxY);
        if (inside || best <= reach * reach) {
            near.insert(static_cast<std::uint16_t>(r));
        }
    }
    return near;
}

}  // namespace

TEST_GROUP(SiteMap) {
    void setup() override {
        static SiteMap storage;
        static SiteQuery scratch;
        map = &storage;
        query = &scratch;
        map->clear();
    }
};

TEST(SiteMap, FiveThousandRocksOnAKilometreLoadAndEveryQueryMatchesAScanOfTheWholeMap) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(5000, 1000.0F, 31));
    SiteMapCheck check;
    const std::uint32_t before = map->revision();
    CHECK(map->load(image.data(), image.size(), &check) == rse::core::Status::kOk);
    CHECK_TRUE(map->loaded());
    LONGS_EQUAL(5000, map->rockCount());
    CHECK(map->revision() != before);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> where(-20.0, 1020.0);
    std::uniform_real_distribution<double> length(0.0, 40.0);
    std::uniform_real_distribution<double> angle(0.0, 6.283185307179586);
    std::uniform_real_distribution<double> reachOf(0.0, 8.0);
    static std::uint16_t out[kMaxSiteRocks];
    std::uint32_t mostRefs = 0;
    for (int q = 0; q < 300; ++q) {
        const Point2 a{where(rng), where(rng)};
        const double l = length(rng);
        const double th = angle(rng);
        const Point2 b{a.x + l * std::cos(th), a.y + l * std::sin(th)};
        const double reach = reachOf(rng);
        QueryStats stats;
        const std::size_t n = map->rocksNearSegment(a, b, reach, query, out, kMaxSiteRocks, &stats);
        const std::set<std::uint16_t> expected = scan(*map, a, b, reach);
        const std::set<std::uint16_t> got(out, out + n);
        LONGS_EQUAL(expected.size(), n);  // each once
        CHECK_TRUE(expected == got);
        CHECK_FALSE(stats.overflow);
        mostRefs = std::max(mostRefs, stats.refsExamined);
    }
    // A 40 m segment with 8 m of reach sweeps ~ 56 m x 16 m plus a cell's
    // margin: a few dozen rocks of the 5 000, never the map.
    CHECK_TEXT(mostRefs < 200, "a query examined more references than its band holds");
}

TEST(SiteMap, ALongDiagonalQueryCostsItsBandNotTheMap) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(5000, 1000.0F, 7));
    CHECK(map->load(image.data(), image.size(), nullptr) == rse::core::Status::kOk);
    static std::uint16_t out[kMaxSiteRocks];
    QueryStats stats;
    const std::size_t n = map->rocksNearSegment({0, 0}, {1000, 1000}, 2.0, query, out, kMaxSiteRocks, &stats);
    LONGS_EQUAL(scan(*map, {0, 0}, {1000, 1000}, 2.0).size(), n);
    // The band is 1414 m x ~4 m of the 1 000 000 m^2: its cells are a small share of the grid.
    const std::uint32_t cells = map->grid().columns * map->grid().rows;
    CHECK(stats.cellsVisited < cells / 40);
    CHECK(stats.refsExamined < 500);
}

TEST(SiteMap, ABufferTooSmallIsSaidNotSilentlyCut) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(5000, 1000.0F, 3));
    CHECK(map->load(image.data(), image.size(), nullptr) == rse::core::Status::kOk);
    std::uint16_t out[4];
    QueryStats stats;
    const std::size_t n = map->rocksNearSegment({0, 500}, {1000, 500}, 5.0, query, out, 4, &stats);
    LONGS_EQUAL(4, n);
    CHECK_TRUE(stats.overflow);
    CHECK(stats.found > 4);
}

// A question not asked properly is refused, never answered "nothing near".
TEST(SiteMap, AQueryWithAReachOrPointNotFiniteOrFarBeyondAnySiteIsRefused) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(200, 100.0F, 6));
    CHECK(map->load(image.data(), image.size(), nullptr) == rse::core::Status::kOk);
    std::uint16_t out[8];
    QueryStats stats;
    LONGS_EQUAL(0, map->rocksNearSegment({0, 0}, {100, 100}, INFINITY, query, out, 8, &stats));
    CHECK_TRUE(stats.refused);
    LONGS_EQUAL(0, map->rocksNearSegment({0, 0}, {100, 100}, -1.0, query, out, 8, &stats));
    CHECK_TRUE(stats.refused);
    LONGS_EQUAL(0, map->rocksNearSegment({0, 0}, {1e300, 100}, 1.0, query, out, 8, &stats));
    CHECK_TRUE(stats.refused);
    LONGS_EQUAL(0, map->rocksNearSegment({NAN, 0}, {10, 10}, 1.0, query, out, 8, &stats));
    CHECK_TRUE(stats.refused);
    // Asked properly, the same segment finds rocks.
    CHECK(map->rocksNearSegment({0, 0}, {100, 100}, 3.0, query, out, 8, &stats) > 0);
    CHECK_FALSE(stats.refused);
}

TEST(SiteMap, ARefusedImageLeavesTheMapInForce) {
    const std::vector<std::uint8_t> good = rse::ground::encodeSiteMap(rse::test::randomField(50, 100.0F, 1));
    CHECK(map->load(good.data(), good.size(), nullptr) == rse::core::Status::kOk);
    const std::uint32_t revision = map->revision();
    const Rock first = map->rock(0);
    rse::ground::SiteMapSpec spec = rse::test::randomField(60, 100.0F, 2);
    std::reverse(spec.rocks[59].begin(), spec.rocks[59].end());  // the last rock clockwise
    const std::vector<std::uint8_t> bad = rse::ground::encodeSiteMap(spec);
    SiteMapCheck check;
    CHECK(map->load(bad.data(), bad.size(), &check) == rse::core::Status::kInvalidArgument);
    LONGS_EQUAL(static_cast<int>(SiteMapReject::kClockwise), static_cast<int>(check.reason));
    LONGS_EQUAL(59, check.item);
    LONGS_EQUAL(revision, map->revision());
    LONGS_EQUAL(50, map->rockCount());
    MEMCMP_EQUAL(&first, &map->rock(0), sizeof first);
}

TEST(SiteMap, TheQueryStampsSurviveTheirWrapAround) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(200, 100.0F, 4));
    CHECK(map->load(image.data(), image.size(), nullptr) == rse::core::Status::kOk);
    static std::uint16_t out[kMaxSiteRocks];
    const std::size_t expected = scan(*map, {0, 50}, {100, 50}, 3.0).size();
    query->current = 65534;
    for (int i = 0; i < 4; ++i) {
        LONGS_EQUAL(expected, map->rocksNearSegment({0, 50}, {100, 50}, 3.0, query, out, kMaxSiteRocks, nullptr));
    }
}

// A map staged a few work units a step (as MAP_COMMIT's slices do) leaves
// the map in force, its revision, rocks and answers, as they were until it is
// put in force; then it is the map load() makes of the same image, query for
// query.
TEST(SiteMap, AMapStagedInStepsIsNotInForceUntilWholeThenEqualsOneLoaded) {
    const std::vector<std::uint8_t> old = rse::ground::encodeSiteMap(rse::test::randomField(300, 400.0F, 11));
    CHECK(map->load(old.data(), old.size(), nullptr) == rse::core::Status::kOk);
    const std::uint32_t revision = map->revision();
    static std::uint16_t out[kMaxSiteRocks];
    const Point2 a{10, 200}, b{390, 210};
    const std::set<std::uint16_t> before = scan(*map, a, b, 4.0);
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(5000, 1000.0F, 12));
    CHECK_TRUE(checkSiteMapImage(image.data(), image.size()).ok());
    map->beginStaging(image.data(), image.size());
    CHECK_TRUE(map->staging());
    CHECK_FALSE(map->putStagedInForce());  // not whole yet
    std::size_t steps = 0;
    while (!map->stage(700)) {
        ++steps;
        CHECK(steps < 1000);
        LONGS_EQUAL(revision, map->revision());
        LONGS_EQUAL(300, map->rockCount());
        const std::size_t n = map->rocksNearSegment(a, b, 4.0, query, out, kMaxSiteRocks, nullptr);
        CHECK_TRUE(std::set<std::uint16_t>(out, out + n) == before);
    }
    // Decoded, counted and filed 700 units a step: 5 000 rocks decoded, each
    // rock's cells counted and filed (one at least), and the grid's cells
    // cleared and summed (two passes of about 64 000 / kCellsPerStageUnit).
    CHECK(steps >= (3 * 5000 + 2 * 65536 / kCellsPerStageUnit) / 700);
    CHECK_TRUE(map->putStagedInForce());
    CHECK_FALSE(map->staging());
    CHECK(map->revision() != revision);
    LONGS_EQUAL(5000, map->rockCount());
    std::mt19937 rng(8);
    std::uniform_real_distribution<double> where(0.0, 1000.0);
    for (int q = 0; q < 25; ++q) {   // each checked against a scan of the 5 000 (slow under qemu)
        const Point2 p{where(rng), where(rng)}, r{where(rng), where(rng)};
        const std::size_t n = map->rocksNearSegment(p, r, 3.0, query, out, kMaxSiteRocks, nullptr);
        CHECK_TRUE(std::set<std::uint16_t>(out, out + n) == scan(*map, p, r, 3.0));
    }
    // A staging dropped never reaches the map in force.
    const std::uint32_t now = map->revision();
    map->beginStaging(old.data(), old.size());
    (void)map->stage(100);
    map->dropStaged();
    CHECK_FALSE(map->putStagedInForce());
    LONGS_EQUAL(now, map->revision());
    LONGS_EQUAL(5000, map->rockCount());
}

// docs/site_map.md states these.
TEST(SiteMap, MemoryIsWhatTheDocsSay) {
    LONGS_EQUAL(84, SiteMap::kBytesPerRock);
    CHECK(kSiteMapSlotBytes <= 2400000);
    CHECK(kSiteMapBytes <= 2 * kSiteMapSlotBytes + 256);   // two slots: in force and staged
    CHECK(kSiteMapSlotBytes >= kMaxSiteRocks * SiteMap::kBytesPerRock);
    CHECK(kSiteMapSlotBytes / kMaxSiteRocks <= 113);  // "113 bytes a rock" a slot
    CHECK(kMaxSiteRocks >= 20000);                // the growth table's largest row
    LONGS_EQUAL(1339552, kMaxSiteMapImageSize);
    CHECK(sizeof(SiteQuery) <= 41000);
}
