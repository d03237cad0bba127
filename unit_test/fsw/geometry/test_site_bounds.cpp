// The site (fsw/geometry/site_bounds.hpp): COARSE_MAP's bounds shrunk by an
// inset, how far a point lies outside them, and the nearest point inside.
// Until now only exercised through the health monitor's off-the-map fault and
// the planning layers' way back on; here alone, with figures by hand.
#include <cmath>

#include "fsw/geometry/site_bounds.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

// The site x in [-5, 30], y in [-10, 10].
tables::CoarseMapTable site() {
    tables::CoarseMapTable map{};
    map.x_min_m = -5.0F;
    map.x_max_m = 30.0F;
    map.y_min_m = -10.0F;
    map.y_max_m = 10.0F;
    return map;
}

}  // namespace

TEST_GROUP(SiteBounds){};

TEST(SiteBounds, TheBoxIsTheSiteShrunkByTheInset) {
    const geometry::SiteBox bounds = geometry::siteBox(site(), 0.0);
    DOUBLES_EQUAL(-5.0, bounds.minX, 0.0);
    DOUBLES_EQUAL(30.0, bounds.maxX, 0.0);
    DOUBLES_EQUAL(-10.0, bounds.minY, 0.0);
    DOUBLES_EQUAL(10.0, bounds.maxY, 0.0);
    const geometry::SiteBox shrunk = geometry::siteBox(site(), 0.5);
    DOUBLES_EQUAL(-4.5, shrunk.minX, 0.0);
    DOUBLES_EQUAL(29.5, shrunk.maxX, 0.0);
    DOUBLES_EQUAL(-9.5, shrunk.minY, 0.0);
    DOUBLES_EQUAL(9.5, shrunk.maxY, 0.0);
    // More than half the site's 20 m width: empty (min > max in y).
    const geometry::SiteBox empty = geometry::siteBox(site(), 10.5);
    CHECK(empty.minY > empty.maxY);
}

// Outside by the worse axis; inside, negative: the distance to the nearest edge.
TEST(SiteBounds, OutsideByIsTheWorseAxisAndInsideTheNearestEdge) {
    const geometry::SiteBox b = geometry::siteBox(site(), 0.0);
    DOUBLES_EQUAL(2.0, geometry::outsideBy(b, 32.0, 0.0), 1e-12);    // 2 m east
    DOUBLES_EQUAL(3.0, geometry::outsideBy(b, 31.0, -13.0), 1e-12);  // 1 m east, 3 m south: 3
    DOUBLES_EQUAL(0.0, geometry::outsideBy(b, -5.0, 4.0), 1e-12);    // on the west edge
    DOUBLES_EQUAL(-1.0, geometry::outsideBy(b, -4.0, 0.0), 1e-12);   // 1 m inside the west edge
    DOUBLES_EQUAL(-2.5, geometry::outsideBy(b, 10.0, 7.5), 1e-12);   // 2.5 m from the north edge
}

TEST(SiteBounds, TheNearestPointInsideIsThePointClampedToTheBox) {
    const geometry::SiteBox b = geometry::siteBox(site(), 1.0);  // x -4..29, y -9..9
    double x = 0.0;
    double y = 0.0;
    CHECK_TRUE(geometry::nearestInside(b, 35.0, -20.0, &x, &y));
    DOUBLES_EQUAL(29.0, x, 0.0);
    DOUBLES_EQUAL(-9.0, y, 0.0);
    CHECK_TRUE(geometry::nearestInside(b, -7.0, 3.0, &x, &y));
    DOUBLES_EQUAL(-4.0, x, 0.0);
    DOUBLES_EQUAL(3.0, y, 0.0);
    CHECK_TRUE(geometry::nearestInside(b, 12.5, -2.25, &x, &y));  // inside: itself
    DOUBLES_EQUAL(12.5, x, 0.0);
    DOUBLES_EQUAL(-2.25, y, 0.0);
    // An empty box or a point that is not finite: false, nothing written.
    x = 7.0;
    y = 8.0;
    CHECK_FALSE(geometry::nearestInside(geometry::siteBox(site(), 11.0), 0.0, 0.0, &x, &y));
    CHECK_FALSE(geometry::nearestInside(b, NAN, 0.0, &x, &y));
    CHECK_FALSE(geometry::nearestInside(b, 0.0, INFINITY, &x, &y));
    DOUBLES_EQUAL(7.0, x, 0.0);
    DOUBLES_EQUAL(8.0, y, 0.0);
}
