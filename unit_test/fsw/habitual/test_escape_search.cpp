// Where a rover that cannot plan from where it stands backs out to
// (fsw/habitual/escape_search.hpp): out of a remembered hazard's disc grown by
// the footprint (straight away, else turned), back onto the site from off it,
// and the checks of the end and the way there. Pure geometry on the default
// coarse map (site x -5..30, y -10..10; rock 0 the square x 5..6.5, y 1.8..3.2).
#include <cmath>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/habitual/escape_search.hpp"
#include "fsw/habitual/planning_session.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::EscapeSearch;
using habitual::kEscapeExtraM;
using habitual::kPlanMarginM;

namespace {

constexpr double kFootprint = 0.6;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

TEST_GROUP(EscapeSearch) {
    tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    habitual::MapBuilder hazards;
    habitual::LocalMap map;

    // A hazard disc centred halfWidth beyond `range` ahead of a rover at (x, y) facing heading.
    const habitual::RememberedHazard& see(std::uint8_t id, double x, double y, double heading, double range,
                                          double halfWidth) {
        CHECK(habitual::SightingOutcome::kAdded ==
              hazards.remember(coarse, Point2{x, y}, heading, test::sighting(id, range, 0.0, halfWidth)));
        const habitual::RememberedHazard* found = nullptr;
        for (std::size_t k = 0; k < habitual::kMaxMapDiscs; ++k) {
            found = hazards.slot(k).used && hazards.slot(k).obstacleId == id ? &hazards.slot(k) : found;
        }
        CHECK(found != nullptr);
        return *found;
    }
    // The planning map at the bare footprint, as the planning session builds it before it backs out.
    EscapeSearch search() {
        CHECK(core::Status::kOk == hazards.build(coarse, kFootprint, &map));
        return EscapeSearch(map, hazards, coarse, kFootprint, kPlanMarginM);
    }
};

TEST(EscapeSearch, BacksStraightAwayFromTheDiscCentreToTheFirstClearPoint) {
    const habitual::RememberedHazard& h = see(7, 18.0, -6.0, 0.0, 1.6, 0.4);  // centre (20, -6)
    DOUBLES_EQUAL(20.0, h.centre.x, 1e-9);
    const Point2 start{19.0, -6.0};  // 1.0 m from the centre: inside the cover grown by the footprint
    const EscapeSearch s = search();
    CHECK_FALSE(map.pointFree(start));
    CHECK_FALSE(s.offSite(start));
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(s.findEscape(start, 0.0, &exit));
    // Directly away from the centre, clear of the disc by footprint + margin + the extra.
    DOUBLES_EQUAL(-6.0, exit.y, 1e-9);
    DOUBLES_EQUAL(h.radiusM + kFootprint + kPlanMarginM + kEscapeExtraM, distance(exit, h.centre), 1e-9);
    CHECK(exit.x < start.x);
    CHECK_TRUE(map.pointFree(exit));
}

TEST(EscapeSearch, TurnsWhenStraightAwayRunsTowardsAnotherDisc) {
    const habitual::RememberedHazard& h = see(7, 18.0, -6.0, 0.0, 1.6, 0.4);   // centre (20, -6)
    const habitual::RememberedHazard& other = see(8, 15.0, -6.0, 0.0, 1.6, 0.4);  // centre (17, -6), behind the start
    const Point2 start{19.0, -6.0};
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(search().findEscape(start, 0.0, &exit));
    // Not straight back (every point that way lies within the other disc's
    // keep): turned, by 60 degrees (the 30-degree ways pass 1.46 m from the
    // other disc's centre, inside its cover grown by the footprint, 1.49 m).
    const double away = std::atan2(exit.y - h.centre.y, exit.x - h.centre.x);
    DOUBLES_EQUAL(kPi / 3.0, std::fabs(std::fabs(away) - kPi), 1e-3);
    CHECK(distance(exit, h.centre) >= h.radiusM + kFootprint + kPlanMarginM + kEscapeExtraM - 1e-9);
    CHECK(distance(exit, other.centre) >= other.radiusM + kFootprint + kPlanMarginM);
    CHECK(distance(exit, start) <= habitual::kMaxEscapeM);
    for (int i = 0; i <= 100; ++i) {
        const Point2 q = start + (static_cast<double>(i) / 100.0) * (exit - start);
        CHECK(distance(q, other.centre) >= other.radiusM + kFootprint - 1e-9);
    }
}

TEST(EscapeSearch, AStartBlockedByAMappedRockHasNoDiscToLeave) {
    const Point2 start{5.75, 1.5};  // within the footprint of rock 0, in no hazard disc
    Point2 exit{0.0, 0.0};
    const EscapeSearch s = search();
    CHECK_FALSE(map.pointFree(start));
    CHECK_FALSE(s.findEscape(start, 0.0, &exit));
}

TEST(EscapeSearch, AStartAtTheDiscCentreBacksOutBehindTheRover) {
    const habitual::RememberedHazard& h = see(7, 18.0, -6.0, 0.0, 1.6, 0.4);
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(search().findEscape(h.centre, kPi / 2.0, &exit));  // facing +y: out towards -y
    DOUBLES_EQUAL(h.centre.x, exit.x, 1e-9);
    CHECK(exit.y < h.centre.y);
}

TEST(EscapeSearch, OffTheSiteGoesToTheNearestPointInsideByTheKeep) {
    const Point2 start{-6.0, 0.0};  // 1 m west of the site
    const EscapeSearch s = search();
    CHECK_TRUE(s.offSite(start));
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(s.findReentry(start, &exit));
    DOUBLES_EQUAL(-5.0 + kFootprint + kPlanMarginM + kEscapeExtraM, exit.x, 1e-9);
    DOUBLES_EQUAL(0.0, exit.y, 1e-9);
}

TEST(EscapeSearch, ReentrySlidesAlongTheEdgeWhenARockStandsAtTheNearestPoint) {
    const habitual::RememberedHazard& h = see(9, -2.0, 0.0, kPi, 1.1, 0.4);  // centre (-3.5, 0)
    DOUBLES_EQUAL(-3.5, h.centre.x, 1e-9);
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(search().findReentry(Point2{-6.0, 0.0}, &exit));
    DOUBLES_EQUAL(-5.0 + kFootprint + kPlanMarginM + kEscapeExtraM, exit.x, 1e-9);
    // The first slide whose end keeps footprint + margin from the disc: 1.75 m along the edge.
    DOUBLES_EQUAL(1.75, exit.y, 1e-9);
    CHECK(distance(exit, h.centre) >= h.radiusM + kFootprint + kPlanMarginM);
}

TEST(EscapeSearch, NoReentryFartherThanTheLongestDriveBack) {
    Point2 exit{0.0, 0.0};
    CHECK_FALSE(search().findReentry(Point2{-20.0, 0.0}, &exit));  // 15.9 m from the nearest point
    CHECK_TRUE(search().findReentry(Point2{-14.0, 0.0}, &exit));   // 9.9 m
}

TEST(EscapeSearch, TheEndKeepsTheMarginFromEveryOtherObstacleAndTheWayTheFootprintFromTheRocks) {
    const habitual::RememberedHazard& h = see(7, 18.0, -6.0, 0.0, 1.6, 0.4);
    const EscapeSearch s = search();
    const Point2 start{19.0, -6.0};
    // Near the disc it leaves: clear only when that is the disc left.
    const Point2 near{19.0, -5.0};
    CHECK_TRUE(s.escapeClear(start, near, &h));
    CHECK_FALSE(s.escapeClear(start, near, nullptr));
    // An end too near rock 0 (x 5..6.5, y 1.8..3.2).
    CHECK_FALSE(s.escapeClear(Point2{4.0, 1.0}, Point2{4.5, 1.5}, nullptr));
    // An end clear of everything, but the way there crosses rock 0.
    CHECK(geometry::distanceToCoarseMap(coarse, Point2{5.75, 0.0}) >= kFootprint + kPlanMarginM);
    CHECK_FALSE(s.escapeClear(Point2{5.75, 4.5}, Point2{5.75, 0.0}, nullptr));
    CHECK_TRUE(s.escapeClear(Point2{3.0, 0.0}, Point2{3.0, -1.0}, nullptr));
}

// The way out keeps the bare footprint from every other remembered disc: a
// contact the follower felt lies on the straight way out of a big disc, its
// end clear of the contact's keep. Before, the way was checked against the
// mapped rocks only and drove through the contact (Snowdrift, after a
// trajectory change: 22 contacts with the same rock, one escape after another).
TEST(EscapeSearch, TheWayOutKeepsTheFootprintFromEveryOtherRememberedDisc) {
    const habitual::RememberedHazard& h = see(7, 12.0, -6.0, 0.0, 2.0, 0.7);   // centre (14.7, -6), cover 1.57 m
    const Point2 start = h.centre + Point2{-0.2, 0.0};
    // Straight away, with nothing else remembered: along -x.
    Point2 straight{0.0, 0.0};
    CHECK_TRUE(search().findEscape(start, 0.0, &straight));
    DOUBLES_EQUAL(start.y, straight.y, 1e-9);
    const double wayM = distance(start, straight);
    CHECK(wayM > 2.0);
    CHECK(wayM <= habitual::kMaxEscapeM);
    // A contact 1.0 m along that way and 0.3 m aside: the start is outside its
    // footprint keep and the straight end clear of its planning keep, but the way passes 0.3 m off it.
    const Point2 contact = start + Point2{-1.0, 0.3};
    CHECK(habitual::SightingOutcome::kAdded == hazards.rememberContact(contact, 0.1, 0.15));
    CHECK(distance(start, contact) > 0.15 + kFootprint);
    CHECK(distance(straight, contact) > 0.15 + kFootprint + kPlanMarginM);
    const EscapeSearch s = search();
    CHECK_FALSE(s.escapeClear(start, straight, &h));
    Point2 exit{0.0, 0.0};
    CHECK_TRUE(s.findEscape(start, 0.0, &exit));
    // Another way out, every point of it the footprint off the contact.
    CHECK(distance(exit, straight) > 0.1);
    for (int i = 0; i <= 100; ++i) {
        const Point2 q = start + (static_cast<double>(i) / 100.0) * (exit - start);
        CHECK(distance(q, contact) >= 0.15 + kFootprint - 1e-9);
    }
}
