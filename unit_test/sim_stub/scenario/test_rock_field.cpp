// Rock fields from Golombek and Rapp's size-frequency model (rock_field.hpp):
// the model's own numbers, a drawn field's counts and covered area against
// it, the known / hidden split at the orbital resolution, every rock a convex
// counter-clockwise polygon on the site that the site map takes, and the same
// field for the same seed.
#include <cmath>
#include <vector>

#include "fsw/site_map/site_map_image.hpp"
#include "ground/site_map_encoder.hpp"
#include "sim_stub/scenario/rock_field.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;

namespace {

double polygonArea(const std::vector<RockVertex>& v) {
    double twice = 0.0;
    for (std::size_t i = 0; i < v.size(); ++i) {
        const RockVertex& a = v[i];
        const RockVertex& b = v[(i + 1) % v.size()];
        twice += a.x * b.y - b.x * a.y;
    }
    return 0.5 * twice;
}

RockFieldParams field(double k, double side, std::uint64_t seed) {
    RockFieldParams p;
    p.k = k;
    p.xMax = side;
    p.yMax = side;
    p.seed = seed;
    return p;
}

}  // namespace

TEST_GROUP(RockField){};

// F_k(0) = k; q(0.10) = 3.31; n integrates to F's fall, area for area.
TEST(RockField, TheModelsNumbersAreGolombekAndRapps) {
    DOUBLES_EQUAL(0.10, rockAreaFraction(0.10, 0.0), 1e-15);
    DOUBLES_EQUAL(3.31, golombekRappQ(0.10), 1e-12);
    DOUBLES_EQUAL(0.10 * std::exp(-3.31), rockAreaFraction(0.10, 1.0), 1e-15);
    // Rocks per km^2 of 1 m or more at k = 0.10: about 3 075 (a numerical
    // integral of n to 10 m gives 3 074.6).
    DOUBLES_EQUAL(3074.6, 1e6 * rocksPerSquareMetre(0.10, 1.0, 10.0), 3.0);
    DOUBLES_EQUAL(372.8, 1e6 * rocksPerSquareMetre(0.05, 1.0, 10.0), 0.5);
    DOUBLES_EQUAL(0.0, rocksPerSquareMetre(0.0, 1.0, 2.0), 0.0);
    DOUBLES_EQUAL(0.0, rocksPerSquareMetre(0.1, 2.0, 1.0), 0.0);
}

// A 400 m x 400 m field at k = 0.10: the counts at or above 0.5, 1 and 2 m
// are the model's within four Poisson standard deviations, and the area the
// rocks of 1 m or more cover is F_k(1) within 10 % (the shapes are hulls of
// points inside their circle: about 0.82 of its area, allowed for).
TEST(RockField, ADrawnFieldHasTheModelsCountsAndArea) {
    const RockFieldParams p = field(0.10, 400.0, 3);
    const std::vector<FieldRock> rocks = generateRockField(p);
    const double area = 400.0 * 400.0;
    for (double d : {0.5, 1.0, 2.0}) {
        std::size_t n = 0;
        for (const FieldRock& r : rocks) {
            n += r.diameterM >= d ? 1U : 0U;
        }
        const double expected = area * rocksPerSquareMetre(p.k, d, p.maxDiameterM);
        CHECK_TEXT(std::fabs(static_cast<double>(n) - expected) <= 4.0 * std::sqrt(expected) + 1.0,
                   "count at a diameter off the model");
    }
    double circles = 0.0;
    double shapes = 0.0;
    for (const FieldRock& r : rocks) {
        if (r.diameterM >= 1.0) {
            circles += 3.14159265358979 * r.diameterM * r.diameterM / 4.0;
            shapes += polygonArea(r.vertices);
        }
    }
    const double modelled = area * (rockAreaFraction(p.k, 1.0) - rockAreaFraction(p.k, p.maxDiameterM));
    DOUBLES_EQUAL(1.0, circles / modelled, 0.10);
    CHECK(shapes < circles && shapes > 0.7 * circles);
}

TEST(RockField, RocksAtTheOrbitalResolutionAreKnownSmallerOnesHidden) {
    const std::vector<FieldRock> rocks = generateRockField(field(0.10, 200.0, 4));
    std::size_t known = 0;
    for (const FieldRock& r : rocks) {
        CHECK_EQUAL(r.diameterM >= 1.0, r.known);
        known += r.known ? 1U : 0U;
    }
    CHECK(known > 0 && known < rocks.size());
}

// Every rock: 3 to 8 vertices, convex and counter-clockwise, inside the site,
// as the site map's check wants; the known ones of a 1 km x 1 km field at
// k = 0.13 (over 5 000) make a map image that passes.
TEST(RockField, EveryRockIsASiteMapRockAndAKilometreFieldMakesAMap) {
    RockFieldParams p = field(0.13, 1000.0, 5);
    const std::vector<FieldRock> rocks = generateRockField(p);
    rse::ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 1000.0F, 1000.0F};
    for (const FieldRock& r : rocks) {
        CHECK(r.vertices.size() >= 3 && r.vertices.size() <= rse::site_map::kMaxRockVertices);
        if (!r.known) {
            continue;
        }
        std::vector<rse::ground::MapVertex> v;
        for (const RockVertex& x : r.vertices) {
            v.push_back({static_cast<float>(x.x), static_cast<float>(x.y)});
        }
        spec.rocks.push_back(v);
    }
    CHECK_TEXT(spec.rocks.size() >= 5000, "a 1 km^2 field at k = 0.13 holds fewer than 5 000 known rocks");
    CHECK(spec.rocks.size() <= rse::site_map::kMaxSiteRocks);
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(spec);
    const rse::site_map::SiteMapCheck c = rse::site_map::checkSiteMapImage(image.data(), image.size());
    CHECK_TEXT(c.ok(), rse::site_map::toString(c.reason));
}

TEST(RockField, TheSameSeedGivesTheSameFieldAnotherSeedAnother) {
    const std::vector<FieldRock> a = generateRockField(field(0.05, 100.0, 9));
    const std::vector<FieldRock> b = generateRockField(field(0.05, 100.0, 9));
    const std::vector<FieldRock> c = generateRockField(field(0.05, 100.0, 10));
    LONGS_EQUAL(a.size(), b.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        DOUBLES_EQUAL(a[i].x, b[i].x, 0.0);
        DOUBLES_EQUAL(a[i].diameterM, b[i].diameterM, 0.0);
    }
    CHECK(a.size() != c.size() || (a.size() > 0 && a[0].x != c[0].x));
}

TEST(RockField, ParametersOutOfRangeGiveNoField) {
    RockFieldParams p = field(0.0, 100.0, 1);
    CHECK_TRUE(generateRockField(p).empty());
    p = field(0.1, 100.0, 1);
    p.maxDiameterM = p.minDiameterM;
    CHECK_TRUE(generateRockField(p).empty());
    p = field(0.1, 100.0, 1);
    p.xMax = p.xMin;
    CHECK_TRUE(generateRockField(p).empty());
}
