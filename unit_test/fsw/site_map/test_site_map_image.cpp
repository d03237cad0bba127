// The site map image check (site_map_image.hpp): a good image passes, and each
// way of spoiling one is refused with its own reason and the rock it is about;
// the check in steps of a record (MAP_COMMIT's slices) says the same as the
// whole check of every image here.
#include <cstdint>
#include <cstring>
#include <limits>
#include <vector>

#include "fsw/site_map/site_grid.hpp"
#include "fsw/site_map/site_map_image.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::site_map;
using rse::ground::encodeSiteMap;
using rse::ground::SiteMapSpec;

namespace {

SiteMapSpec threeRocks() {
    SiteMapSpec spec;
    spec.site = {-50.0F, -50.0F, 50.0F, 50.0F};
    spec.rocks.push_back(rse::test::regularRock(0.0F, 0.0F, 1.0F));
    spec.rocks.push_back(rse::test::regularRock(10.0F, 5.0F, 0.5F, 3));
    spec.rocks.push_back(rse::test::regularRock(-20.0F, 30.0F, 1.5F, 8));
    SiteMapSpec::Zone zone;
    zone.kind = KeepOutKind::kSoft;
    zone.vertices = rse::test::regularRock(30.0F, -30.0F, 10.0F, 16);
    spec.keepOuts.push_back(zone);
    return spec;
}

// The check one record a step: the verdict it ends with.
SiteMapCheck checkedInSteps(const std::vector<std::uint8_t>& image, std::size_t* steps) {
    SiteMapImageCheck check;
    check.begin(image.data(), image.size());
    *steps = 0;
    std::size_t records = check.recordsChecked();
    while (!check.step(1)) {
        ++*steps;
        CHECK(check.recordsChecked() == records + 1);
        records = check.recordsChecked();
    }
    return check.result();
}

// The whole check's reason, after checking the stepwise check agrees.
int reasonOf(const std::vector<std::uint8_t>& image) {
    const SiteMapCheck whole = checkSiteMapImage(image.data(), image.size());
    std::size_t steps = 0;
    const SiteMapCheck stepped = checkedInSteps(image, &steps);
    LONGS_EQUAL(static_cast<int>(whole.reason), static_cast<int>(stepped.reason));
    LONGS_EQUAL(whole.item, stepped.item);
    CHECK_EQUAL(whole.keepOut, stepped.keepOut);
    LONGS_EQUAL(whole.rocks, stepped.rocks);
    return static_cast<int>(whole.reason);
}
int reasonOf(SiteMapReject r) { return static_cast<int>(r); }

}  // namespace

TEST_GROUP(SiteMapImage){};

TEST(SiteMapImage, AGoodImagePassesAndSaysWhatItHolds) {
    const std::vector<std::uint8_t> image = encodeSiteMap(threeRocks());
    const SiteMapCheck c = checkSiteMapImage(image.data(), image.size());
    CHECK_TRUE(c.ok());
    LONGS_EQUAL(3, c.rocks);
    LONGS_EQUAL(1, c.keepOuts);
    STRCMP_EQUAL("ok", toString(c.reason));
}

TEST(SiteMapImage, TheHeaderIsCheckedFirst) {
    std::vector<std::uint8_t> image = encodeSiteMap(threeRocks());
    LONGS_EQUAL(reasonOf(SiteMapReject::kTooShort), reasonOf(std::vector<std::uint8_t>(image.begin(), image.begin() + 31)));
    std::vector<std::uint8_t> bad = image;
    bad[0] = 'X';
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadMagic), reasonOf(bad));
    bad = image;
    bad[5] = 2;
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadVersion), reasonOf(bad));
    bad = image;
    bad[7] = 1;  // flags
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadHeader), reasonOf(bad));
    bad = image;
    bad[31] = 1;  // reserved
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadHeader), reasonOf(bad));
    CHECK_EQUAL(0, checkSiteMapImage(nullptr, 100).rocks);
    LONGS_EQUAL(reasonOf(SiteMapReject::kTooShort), static_cast<int>(checkSiteMapImage(nullptr, 100).reason));
}

TEST(SiteMapImage, ASiteEmptyNotFiniteOrTooLargeIsRefused) {
    SiteMapSpec spec = threeRocks();
    spec.site.xMax = spec.site.xMin;
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadSite), reasonOf(encodeSiteMap(spec)));
    spec = threeRocks();
    spec.site.yMax = std::numeric_limits<float>::quiet_NaN();
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadSite), reasonOf(encodeSiteMap(spec)));
    spec = threeRocks();
    spec.site.xMax = spec.site.xMin + static_cast<float>(kMaxSiteExtentM) + 1.0F;
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadSite), reasonOf(encodeSiteMap(spec)));
}

TEST(SiteMapImage, TooManyRocksOrZonesAreRefusedBeforeAnyIsRead) {
    std::vector<std::uint8_t> image = encodeSiteMap(threeRocks());
    // rock_count (bytes 24..27) = kMaxSiteRocks + 1
    const std::uint32_t n = kMaxSiteRocks + 1;
    image[24] = static_cast<std::uint8_t>(n >> 24);
    image[25] = static_cast<std::uint8_t>(n >> 16);
    image[26] = static_cast<std::uint8_t>(n >> 8);
    image[27] = static_cast<std::uint8_t>(n);
    LONGS_EQUAL(reasonOf(SiteMapReject::kTooManyRocks), reasonOf(image));
    image = encodeSiteMap(threeRocks());
    image[28] = 0;
    image[29] = static_cast<std::uint8_t>(kMaxKeepOuts + 1);
    LONGS_EQUAL(reasonOf(SiteMapReject::kTooManyKeepOuts), reasonOf(image));
}

// Each spoiled rock is named by its index.
TEST(SiteMapImage, ABadRockIsRefusedWithItsReasonAndIndex) {
    struct Case {
        SiteMapReject why;
        void (*spoil)(SiteMapSpec*);
    };
    const Case cases[] = {
        {SiteMapReject::kBadVertexCount, [](SiteMapSpec* s) { s->rocks[1].resize(2); }},
        {SiteMapReject::kBadVertexCount, [](SiteMapSpec* s) { s->rocks[1] = rse::test::regularRock(10, 5, 1, 9); }},
        {SiteMapReject::kNotFinite, [](SiteMapSpec* s) { s->rocks[1][0].x = std::numeric_limits<float>::infinity(); }},
        {SiteMapReject::kOutsideSite, [](SiteMapSpec* s) { s->rocks[1] = rse::test::regularRock(49.8F, 5, 0.5F); }},
        {SiteMapReject::kClockwise,
         [](SiteMapSpec* s) { s->rocks[1] = std::vector<rse::ground::MapVertex>(s->rocks[1].rbegin(), s->rocks[1].rend()); }},
        {SiteMapReject::kNotConvex, [](SiteMapSpec* s) { s->rocks[1] = {{0, 20}, {4, 20}, {1, 21}, {0, 24}}; }},
        // A pentagram: every turn left, but it winds twice.
        {SiteMapReject::kNotConvex,
         [](SiteMapSpec* s) {
             const auto star = rse::test::regularRock(10, 5, 1, 5);
             s->rocks[1] = {star[0], star[2], star[4], star[1], star[3]};
         }},
    };
    for (const Case& c : cases) {
        SiteMapSpec spec = threeRocks();
        c.spoil(&spec);
        const std::vector<std::uint8_t> image = encodeSiteMap(spec);
        const SiteMapCheck check = checkSiteMapImage(image.data(), image.size());
        LONGS_EQUAL(reasonOf(c.why), reasonOf(image));
        LONGS_EQUAL(1, check.item);
        CHECK_FALSE(check.keepOut);
    }
}

TEST(SiteMapImage, ABadZoneIsRefusedAndNamed) {
    SiteMapSpec spec = threeRocks();
    spec.keepOuts[0].kind = static_cast<KeepOutKind>(7);
    std::vector<std::uint8_t> image = encodeSiteMap(spec);
    SiteMapCheck check = checkSiteMapImage(image.data(), image.size());
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadKind), reasonOf(image));
    CHECK_TRUE(check.keepOut);
    spec = threeRocks();
    spec.keepOuts[0].vertices = rse::test::regularRock(30, -30, 5, 17);
    image = encodeSiteMap(spec);
    check = checkSiteMapImage(image.data(), image.size());
    LONGS_EQUAL(reasonOf(SiteMapReject::kBadVertexCount), static_cast<int>(check.reason));
    CHECK_TRUE(check.keepOut);
}

TEST(SiteMapImage, ATruncatedOrPaddedImageIsRefused) {
    const std::vector<std::uint8_t> image = encodeSiteMap(threeRocks());
    for (std::size_t cut = 32; cut < image.size(); cut += 7) {
        LONGS_EQUAL(reasonOf(SiteMapReject::kTooShort), reasonOf(std::vector<std::uint8_t>(image.begin(), image.begin() + cut)));
    }
    std::vector<std::uint8_t> padded = image;
    padded.push_back(0);
    LONGS_EQUAL(reasonOf(SiteMapReject::kTrailingBytes), reasonOf(padded));
}

// Rocks so wide that their boxes span more cells than the index holds (the
// check does not forbid overlapping rocks: 900 squares of 127 m, ~17 x 17
// cells each at 7.8 m cells, half as much again as the index).
TEST(SiteMapImage, RocksSpanningTooManyCellsAreRefused) {
    SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 2000.0F, 2000.0F};
    for (std::size_t i = 0; i < 900; ++i) {
        const float x = 100.0F + static_cast<float>(i % 30) * 60.0F;
        const float y = 100.0F + static_cast<float>(i / 30) * 60.0F;
        spec.rocks.push_back(rse::test::regularRock(x, y, 90.0F, 4, 0.785398F));
    }
    LONGS_EQUAL(reasonOf(SiteMapReject::kIndexFull), reasonOf(encodeSiteMap(spec)));
    spec.rocks.resize(100);  // about 29 000 references: room
    LONGS_EQUAL(reasonOf(SiteMapReject::kOk), reasonOf(encodeSiteMap(spec)));
}

TEST(SiteMapImage, TheGridFitsAKilometreInTheCellsWithCellsNoSmallerThanTheFloor) {
    const GridShape km = gridFor(SiteBounds{0.0F, 0.0F, 1000.0F, 1000.0F});
    CHECK(static_cast<std::size_t>(km.columns) * km.rows <= kMaxGridCells);
    CHECK(km.cellM * km.columns >= 1000.0);
    CHECK(km.cellM < 4.0);
    const GridShape small = gridFor(SiteBounds{-5.0F, -15.0F, 35.0F, 15.0F});
    DOUBLES_EQUAL(kMinCellM, small.cellM, 0.0);
    LONGS_EQUAL(20, small.columns);
    LONGS_EQUAL(15, small.rows);
}

// A good image of 1 000 rocks and a zone checked 64 records a step: 16
// steps, and the verdict of the whole check.
TEST(SiteMapImage, TheCheckInStepsTakesItsRecordsAStepAtATime) {
    SiteMapSpec spec = rse::test::randomField(1000, 300.0F, 21);
    SiteMapSpec::Zone zone;
    zone.kind = KeepOutKind::kSteep;
    zone.vertices = rse::test::regularRock(150.0F, 150.0F, 10.0F, 6);
    spec.keepOuts.push_back(zone);
    const std::vector<std::uint8_t> image = encodeSiteMap(spec);
    SiteMapImageCheck check;
    check.begin(image.data(), image.size());
    CHECK_FALSE(check.ended());
    std::size_t steps = 1;
    while (!check.step(64)) {
        LONGS_EQUAL(64 * steps, check.recordsChecked());
        ++steps;
    }
    LONGS_EQUAL(16, steps);   // 1 001 records
    LONGS_EQUAL(1001, check.recordsChecked());
    CHECK_TRUE(check.result().ok());
    LONGS_EQUAL(1000, check.result().rocks);
    CHECK_TRUE(check.step(64));   // ended stays ended
}
