// The map builder: coarse-map polygons into the local map, hazard sightings
// into site-frame discs, known-obstacle suppression, the fixed table's
// replacement rule (fsw/habitual/map_builder.hpp).
#include <cmath>
#include <limits>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::LocalMap;
using habitual::MapBuilder;
using habitual::SightingOutcome;

namespace {

constexpr double kPi = 3.14159265358979323846;

// The default coarse map (tables/coarse_map.toml): site x -5..30, y -10..10,
// rock 0 the square x 5..6.5, y 1.8..3.2, and three more.
tables::CoarseMapTable defaultCoarseMap() {
    tables::CoarseMapTable t{};
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& ref = tables::kDefaultTableImages[i];
        if (tables::decodeTable(ref.data, ref.length, &t).ok()) {
            return t;
        }
    }
    FAIL("no default coarse map image");
    return t;
}

msg::HazardSightingTlm sighting(std::uint8_t id, double range, double bearing, double halfWidth) {
    msg::HazardSightingTlm s{};
    s.obstacleId = id;
    s.rangeM = range;
    s.bearingRad = bearing;
    s.halfWidthM = halfWidth;
    return s;
}

const habitual::RememberedHazard* findId(const MapBuilder& b, std::uint8_t id) {
    for (std::size_t i = 0; i < habitual::kMaxMapDiscs; ++i) {
        if (b.slot(i).used && b.slot(i).obstacleId == id) {
            return &b.slot(i);
        }
    }
    return nullptr;
}

}  // namespace

TEST_GROUP(MapBuilder) {
    tables::CoarseMapTable coarse = defaultCoarseMap();
    MapBuilder builder;
    LocalMap map;
};

TEST(MapBuilder, CoarsePolygonsAndBoundsGoIntoTheMapInflatedByTheClearance) {
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    LONGS_EQUAL(coarse.obstacle_count, map.polygonCount());
    LONGS_EQUAL(0, map.discCount());
    DOUBLES_EQUAL(-5.0, map.min().x, 1e-6);
    DOUBLES_EQUAL(30.0, map.max().x, 1e-6);
    DOUBLES_EQUAL(-10.0, map.min().y, 1e-6);
    DOUBLES_EQUAL(10.0, map.max().y, 1e-6);
    DOUBLES_EQUAL(0.6, map.clearance(), 1e-12);
    CHECK_FALSE(map.pointFree(Point2{5.75, 2.5}));  // inside rock 0
    CHECK_FALSE(map.pointFree(Point2{5.75, 1.3}));  // 0.5 m south of it: inside the inflation
    CHECK_TRUE(map.pointFree(Point2{5.75, 1.1}));   // 0.7 m south: free
    CHECK_TRUE(map.pointFree(Point2{0.0, 0.0}));
    CHECK_FALSE(map.pointFree(Point2{31.0, 0.0}));  // off the site
    // The triangle (rock 1) is there too: its top vertex is (10.2, -1.6).
    CHECK_FALSE(map.pointFree(Point2{10.2, -1.1}));
    CHECK_TRUE(map.pointFree(Point2{10.2, -0.9}));
}

TEST(MapBuilder, SightingBecomesADiscInTheSiteFrame) {
    // Rover at (2, 1) facing north; an obstacle 2 m away on its right (east),
    // 0.5 m half width: centre 2.5 m east of the rover.
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{2.0, 1.0}, kPi / 2.0, sighting(7, 2.0, -kPi / 2.0, 0.5)));
    const habitual::RememberedHazard* h = findId(builder, 7);
    CHECK(h != nullptr);
    DOUBLES_EQUAL(4.5, h->centre.x, 1e-9);
    DOUBLES_EQUAL(1.0, h->centre.y, 1e-9);
    // The habitual layer's cover (sqrt(5) half widths) and the seen disc (1.5), one centre.
    const double radius = habitual::kCoverRadiusFactor * 0.5;
    DOUBLES_EQUAL(radius, h->radiusM, 1e-12);
    DOUBLES_EQUAL(habitual::kSightingRadiusFactor * 0.5, h->seenRadiusM, 1e-12);
    DOUBLES_EQUAL(h->centre.x, h->seenCentre.x, 1e-12);
    DOUBLES_EQUAL(h->centre.y, h->seenCentre.y, 1e-12);
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    LONGS_EQUAL(1, map.discCount());
    CHECK_FALSE(map.pointFree(Point2{4.5, 1.0}));
    CHECK_FALSE(map.pointFree(Point2{4.5 + radius + 0.55, 1.0}));  // within radius + clearance 0.6
    CHECK_TRUE(map.pointFree(Point2{4.5 - radius - 0.65, 1.0}));
    // The segment the rover would drive east now crosses it.
    CHECK_FALSE(map.segmentFree(Point2{2.0, 1.0}, Point2{8.0, 1.0}));
}

TEST(MapBuilder, ZeroHalfWidthGetsTheRadiusFloor) {
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, -5.0}, 0.0, sighting(3, 1.0, 0.0, 0.0)));
    const habitual::RememberedHazard* h = findId(builder, 3);
    CHECK(h != nullptr);
    DOUBLES_EQUAL(habitual::kMinHazardRadiusM, h->radiusM, 1e-12);
    DOUBLES_EQUAL(habitual::kMinHazardRadiusM, h->seenRadiusM, 1e-12);
    DOUBLES_EQUAL(1.0, h->centre.x, 1e-12);
}

TEST(MapBuilder, ResightingsOfAnIdGrowItsDiscToEncloseEveryView) {
    // From (0, 0) facing east: a disc at (3.2, 0), radius 0.3.
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, 0.0}, 0.0, sighting(9, 2.9, 0.0, 0.3)));
    std::uint32_t revision = builder.revision();
    // The same view again (within the disc): nothing changes, not even the revision.
    CHECK(SightingOutcome::kUnchanged == builder.remember(coarse, Point2{0.0, 0.0}, 0.0, sighting(9, 3.0, 0.0, 0.15)));
    LONGS_EQUAL(revision, builder.revision());
    // Another part of it, seen from further on: the disc round both views.
    CHECK(SightingOutcome::kUpdated == builder.remember(coarse, Point2{2.0, -1.0}, kPi / 2.0, sighting(9, 1.2, 0.0, 0.2)));
    CHECK(builder.revision() != revision);
    LONGS_EQUAL(1, builder.rememberedCount());
    const habitual::RememberedHazard* h = findId(builder, 9);
    // Views: (3.2, 0) r 0.3 F and (2.0, 0.4) r 0.2 F (F = kCoverRadiusFactor for
    // the cover, kSightingRadiusFactor for the seen disc); each enclosing radius
    // (d + 0.3 F + 0.2 F) / 2.
    const double f = habitual::kCoverRadiusFactor;
    const double fs = habitual::kSightingRadiusFactor;
    const double d = std::hypot(1.2, 0.4);
    DOUBLES_EQUAL(0.5 * (d + 0.5 * f), h->radiusM, 1e-9);
    CHECK(std::hypot(h->centre.x - 3.2, h->centre.y - 0.0) + 0.3 * f <= h->radiusM + 1e-9);
    CHECK(std::hypot(h->centre.x - 2.0, h->centre.y - 0.4) + 0.2 * f <= h->radiusM + 1e-9);
    DOUBLES_EQUAL(0.5 * (d + 0.5 * fs), h->seenRadiusM, 1e-9);
    CHECK(std::hypot(h->seenCentre.x - 3.2, h->seenCentre.y - 0.0) + 0.3 * fs <= h->seenRadiusM + 1e-9);
    CHECK(std::hypot(h->seenCentre.x - 2.0, h->seenCentre.y - 0.4) + 0.2 * fs <= h->seenRadiusM + 1e-9);
    // A view enclosing the remembered disc replaces it.
    revision = builder.revision();
    CHECK(SightingOutcome::kUpdated == builder.remember(coarse, Point2{0.0, 0.0}, 0.0, sighting(9, 1.0, 0.0, 1.9)));
    DOUBLES_EQUAL(2.9, findId(builder, 9)->centre.x, 1e-9);
    DOUBLES_EQUAL(1.9 * f, findId(builder, 9)->radiusM, 1e-9);
    DOUBLES_EQUAL(2.9, findId(builder, 9)->seenCentre.x, 1e-9);
    DOUBLES_EQUAL(1.9 * fs, findId(builder, 9)->seenRadiusM, 1e-9);
    LONGS_EQUAL(2, builder.updated());
    LONGS_EQUAL(1, builder.unchanged());
    LONGS_EQUAL(1, builder.added());
}

TEST(MapBuilder, ARockSeenEdgeOnAtItsCornerLiesInsideTheCoverWhereverItsWidthLies) {
    // Monte Carlo seed 52's case (docs/montecarlo.md): a 0.5 m square boulder
    // seen from 3 m straight at its corner, all of it on one side of the line
    // of sight. From (0, -8) facing east the detector reports the corner (3, -8):
    // range 3, bearing 0, half width 0.25 (the rock's extent across the line).
    // It cannot say on which side the width lies: the rock may be y -8.5..-8.0,
    // -8.25..-7.75 or -8.0..-7.5, and as deep as 0.5 m (no deeper than wide).
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, -8.0}, 0.0, sighting(4, 3.0, 0.0, 0.25)));
    const habitual::RememberedHazard* h = findId(builder, 4);
    CHECK(h != nullptr);
    const Point2 corners[] = {{3.0, -8.5}, {3.5, -8.5}, {3.0, -7.5}, {3.5, -7.5}, {3.5, -8.0}, {3.0, -8.0}};
    for (const Point2& c : corners) {
        CHECK(std::hypot(c.x - h->centre.x, c.y - h->centre.y) <= h->radiusM + 1e-9);
    }
    // The seen disc (1.5 half widths, the model before) leaves the far corner of
    // a one-sided rock 0.18 m outside: the rover planned round it and touched it.
    const double farCorner = std::hypot(3.5 - h->seenCentre.x, -8.5 - h->seenCentre.y);
    CHECK(farCorner > h->seenRadiusM + 0.15);
    // A rover passing 0.6 m (its footprint) clear of the cover clears the rock.
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    CHECK_FALSE(map.pointFree(Point2{3.5, -8.5 - 0.55}));
    CHECK_FALSE(map.pointFree(Point2{3.5, -7.5 + 0.55}));
}

TEST(MapBuilder, ALegEndWithinACoverIsPlannedToAgainstThatHazardsSeenDiscOnly) {
    // Two hazards, each half width 0.25: cover 0.559 m, seen disc 0.375 m.
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, -8.0}, 0.0, sighting(4, 3.0, 0.0, 0.25)));
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{20.0, -8.0}, 0.0, sighting(8, 2.0, 0.0, 0.25)));
    // A leg end 1.05 m south of the first's centre: inside its cover grown by
    // the 0.6 m footprint (1.159 m), outside its seen disc grown so (0.975 m),
    // where the deliberative layer (told the seen disc) may put it.
    const Point2 end{3.25, -9.05};
    const Point2 besideOther{22.25, -9.05};
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    CHECK_FALSE(map.pointFree(end));
    CHECK_FALSE(map.pointFree(besideOther));
    habitual::MapRelief relief;
    relief.seenAt = end;
    relief.hasSeenAt = true;
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map, &relief));
    CHECK_TRUE(map.pointFree(end));
    CHECK_FALSE(map.pointFree(Point2{3.25, -8.0 - 0.95}));  // the seen disc is still there
    CHECK_FALSE(map.pointFree(besideOther));                // the other hazard keeps its cover
}

TEST(MapBuilder, ASightingWhoseNearestPointIsOnAMappedRockKeepsTheSeenDiscAsItsCover) {
    // Rock 0 spans x 5..6.5, y 1.8..3.2. From (3, 2) the nearest point seen is
    // (5, 1.55), within the 0.3 m margin of the rock's south-west corner; a wide
    // half width (0.6) puts the centre 0.38 m off the rock, so it is added. The
    // nearest point is the mapped rock's surface: the map has the rock whole and
    // the cover is not grown past the seen disc.
    const double dx = 2.0;
    const double dy = -0.45;
    const double range = std::hypot(dx, dy);
    CHECK(SightingOutcome::kAdded ==
          builder.remember(coarse, Point2{3.0, 2.0}, 0.0, sighting(6, range, std::atan2(dy, dx), 0.6)));
    const habitual::RememberedHazard* h = findId(builder, 6);
    CHECK(h != nullptr);
    CHECK(geometry::distanceToCoarseMap(coarse, h->centre) > habitual::kKnownObstacleMarginM);
    DOUBLES_EQUAL(habitual::kSightingRadiusFactor * 0.6, h->radiusM, 1e-12);
    DOUBLES_EQUAL(h->seenRadiusM, h->radiusM, 1e-12);
}

TEST(MapBuilder, AnIdSeenFarFromItsDiscIsAnotherObstacle) {
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, 0.0}, 0.0, sighting(5, 2.0, 0.0, 0.5)));
    // 10 m away: the disc round both would exceed kMaxMergedRadiusM, so the new view replaces it.
    CHECK(SightingOutcome::kUpdated == builder.remember(coarse, Point2{10.0, -6.0}, 0.0, sighting(5, 2.0, 0.0, 0.5)));
    const habitual::RememberedHazard* h = findId(builder, 5);
    DOUBLES_EQUAL(12.5, h->centre.x, 1e-9);
    DOUBLES_EQUAL(-6.0, h->centre.y, 1e-9);
    DOUBLES_EQUAL(habitual::kCoverRadiusFactor * 0.5, h->radiusM, 1e-12);
    DOUBLES_EQUAL(habitual::kSightingRadiusFactor * 0.5, h->seenRadiusM, 1e-12);
}

TEST(MapBuilder, SightingOnOrNearACoarsePolygonIsAKnownObstacle) {
    // Rock 0 spans y 1.8..3.2 at x 5..6.5. From (5.75, 0) facing north:
    // centre inside the rock.
    CHECK(SightingOutcome::kKnownObstacle ==
          builder.remember(coarse, Point2{5.75, 0.0}, kPi / 2.0, sighting(1, 1.8, 0.0, 0.7)));
    // Surface 0.2 m and centre 0.1 m south of the rock's edge: within the 0.3 m margin.
    CHECK(SightingOutcome::kKnownObstacle ==
          builder.remember(coarse, Point2{5.75, 0.0}, kPi / 2.0, sighting(1, 1.6, 0.0, 0.1)));
    LONGS_EQUAL(0, builder.rememberedCount());
    LONGS_EQUAL(2, builder.knownObstacles());
    // Centre 0.25 m off but the surface seen 0.35 m in front: something else, added.
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{5.75, 0.0}, kPi / 2.0, sighting(1, 1.45, 0.0, 0.1)));
    LONGS_EQUAL(1, builder.rememberedCount());
    DOUBLES_EQUAL(0.25, geometry::distanceToCoarseMap(coarse, findId(builder, 1)->centre), 1e-6);
}

TEST(MapBuilder, AHiddenRockBesideAMappedOneIsNotTakenForIt) {
    // Rock 0 spans x 5..6.5, y 1.8..3.2. A hidden rock just south-west of its
    // corner, seen from the west: its centre estimate lies 0.21 m from the
    // rock (within the margin) but the surface seen, its west side, 0.36 m
    // from it: it is another rock, remembered.
    const Point2 rover{3.0, 1.6};
    const double range = 1.7;       // surface at (4.7, 1.6)
    const double halfWidth = 0.25;  // centre estimate (4.95, 1.6)
    CHECK(geometry::distanceToCoarseMap(coarse, Point2{4.95, 1.6}) <= habitual::kKnownObstacleMarginM);
    CHECK(geometry::distanceToCoarseMap(coarse, Point2{4.7, 1.6}) > habitual::kKnownObstacleMarginM);
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, rover, 0.0, sighting(9, range, 0.0, halfWidth)));
    LONGS_EQUAL(0, builder.knownObstacles());
    const habitual::RememberedHazard* h = findId(builder, 9);
    CHECK(h != nullptr);
    DOUBLES_EQUAL(4.95, h->centre.x, 1e-9);
}

TEST(MapBuilder, FullTableReplacesTheSightingSeenLongestAgo) {
    for (std::uint8_t id = 1; id <= habitual::kMaxMapDiscs; ++id) {
        // A row of small obstacles south of the rocks, 0.5 m apart.
        const SightingOutcome o =
            builder.remember(coarse, Point2{-4.0 + 0.5 * id, -8.0}, kPi / 2.0, sighting(id, 0.5, 0.0, 0.1));
        CHECK(SightingOutcome::kAdded == o);
    }
    LONGS_EQUAL(habitual::kMaxMapDiscs, builder.rememberedCount());
    // id 1 is seen again, so id 2 becomes the oldest.
    CHECK(SightingOutcome::kUnchanged == builder.remember(coarse, Point2{-3.5, -8.0}, kPi / 2.0, sighting(1, 0.5, 0.0, 0.1)));
    CHECK(SightingOutcome::kReplacedOldest ==
          builder.remember(coarse, Point2{20.0, -8.0}, kPi / 2.0, sighting(200, 0.5, 0.0, 0.1)));
    LONGS_EQUAL(habitual::kMaxMapDiscs, builder.rememberedCount());
    LONGS_EQUAL(1, builder.replacedOldest());
    CHECK(findId(builder, 2) == nullptr);
    CHECK(findId(builder, 1) != nullptr);
    CHECK(findId(builder, 200) != nullptr);
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    LONGS_EQUAL(habitual::kMaxMapDiscs, map.discCount());
}

TEST(MapBuilder, ImplausibleSightingsAreRejectedAndChangeNothing) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    const std::uint32_t revision = builder.revision();
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(1, nan, 0.0, 0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(1, 1.0, nan, 0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(1, -0.1, 0.0, 0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(1, 1.0, 0.0, -0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(1, 60.0, 0.0, 0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(0, 1.0, 0.0, 0.3)));
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{nan, 0}, 0.0, sighting(1, 1.0, 0.0, 0.3)));
    LONGS_EQUAL(7, builder.rejected());
    LONGS_EQUAL(0, builder.rememberedCount());
    LONGS_EQUAL(revision, builder.revision());
}

TEST(MapBuilder, ForgetAllEmptiesTheMemory) {
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0, 0}, 0.0, sighting(4, 1.0, 0.0, 0.3)));
    builder.forgetAll();
    LONGS_EQUAL(0, builder.rememberedCount());
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    LONGS_EQUAL(0, map.discCount());
}

TEST(MapBuilder, BuildRefusesANullMap) {
    CHECK(core::Status::kInvalidArgument == builder.build(coarse, 0.6, nullptr));
}

TEST(MapBuilder, ReliefTakesTheMarginOffOnlyTheDiscsRoundTheGivenPoints) {
    // Two seen rocks on open ground south of the route (well clear of the coarse rocks).
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{0.0, -5.0}, 0.0, sighting(3, 2.0, 0.0, 0.3)));
    CHECK(SightingOutcome::kAdded == builder.remember(coarse, Point2{10.0, -5.0}, 0.0, sighting(4, 2.0, 0.0, 0.3)));
    const habitual::RememberedHazard* near = findId(builder, 3);
    const habitual::RememberedHazard* far = findId(builder, 4);
    CHECK(near != nullptr && far != nullptr);
    const double footprint = 0.6;
    const double margin = 0.25;
    // A start inside the near disc's margin but outside its bare footprint.
    const Point2 start = near->centre + Point2{0.0, near->radiusM + footprint + 0.1};
    const Point2 besideFar = far->centre + Point2{0.0, far->radiusM + footprint + 0.1};
    CHECK(core::isOk(builder.build(coarse, footprint + margin, &map)));
    CHECK_FALSE(map.pointFree(start));
    CHECK_FALSE(map.pointFree(besideFar));
    const habitual::MapRelief relief{{start, start}, 1, margin};
    CHECK(core::isOk(builder.build(coarse, footprint + margin, &map, &relief)));
    CHECK_TRUE(map.pointFree(start));        // the disc it is in keeps the bare footprint only
    CHECK_FALSE(map.pointFree(besideFar));   // every other obstacle keeps the whole margin
}

// A contact (ContactMsg) is a disc of its own: id 0, merged with no
// sighting, never the oldest a sighting replaces, at most kMaxContactDiscs.
TEST(MapBuilder, AContactIsRememberedApartFromSightingsAndOutlivesThem) {
    CHECK(SightingOutcome::kAdded == builder.rememberContact(Point2{10.0, 0.0}, 0.25, 0.48));
    const habitual::RememberedHazard* c = findId(builder, habitual::kContactObstacleId);
    CHECK(c != nullptr);
    DOUBLES_EQUAL(0.48, c->radiusM, 1e-12);
    DOUBLES_EQUAL(0.25, c->seenRadiusM, 1e-12);
    CHECK(core::Status::kOk == builder.build(coarse, 0.6, &map));
    CHECK_FALSE(map.pointFree(Point2{10.0, 0.0}));
    // A sighting with id 0 is still refused ("clear"), and touches nothing.
    CHECK(SightingOutcome::kRejected == builder.remember(coarse, Point2{8.0, 0.0}, 0.0, sighting(0, 1.5, 0.0, 0.2)));
    // Fill every other slot with sightings, then many more: the contact stays.
    for (int i = 0; i < 200; ++i) {
        const std::uint8_t id = static_cast<std::uint8_t>(1 + i % 250);
        (void)builder.remember(coarse, Point2{20.0, -8.0 + 0.05 * i}, 0.0, sighting(id, 2.0, 0.0, 0.1));
    }
    LONGS_EQUAL(habitual::kMaxMapDiscs, builder.rememberedCount());
    c = findId(builder, habitual::kContactObstacleId);
    CHECK(c != nullptr);
    DOUBLES_EQUAL(10.0, c->centre.x, 1e-12);
    // Contacts beyond kMaxContactDiscs replace the oldest contact, not a sighting.
    for (std::size_t k = 1; k <= habitual::kMaxContactDiscs; ++k) {
        (void)builder.rememberContact(Point2{10.0 + static_cast<double>(k), 5.0}, 0.25, 0.48);
    }
    std::size_t contacts = 0;
    bool firstKept = false;
    for (std::size_t i = 0; i < habitual::kMaxMapDiscs; ++i) {
        const habitual::RememberedHazard& h = builder.slot(i);
        if (h.used && h.obstacleId == habitual::kContactObstacleId) {
            ++contacts;
            firstKept = firstKept || (h.centre.x == 10.0 && h.centre.y == 0.0);
        }
    }
    LONGS_EQUAL(habitual::kMaxContactDiscs, contacts);
    CHECK_FALSE(firstKept);
    // Values not finite, or a cover smaller than the seen disc, are refused.
    CHECK(SightingOutcome::kRejected == builder.rememberContact(Point2{std::nan(""), 0.0}, 0.25, 0.48));
    CHECK(SightingOutcome::kRejected == builder.rememberContact(Point2{1.0, 0.0}, 0.5, 0.25));
}
