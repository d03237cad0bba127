#include <cmath>
#include <vector>

#include "sim_stub/world/geometry.hpp"
#include "sim_stub/world/terrain.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;

namespace {

ConvexPolygon box(double x0, double y0, double x1, double y1) {
    ConvexPolygon p;
    p.v[0] = {x0, y0};
    p.v[1] = {x1, y0};
    p.v[2] = {x1, y1};
    p.v[3] = {x0, y1};
    p.n = 4;
    return p;
}

}  // namespace

TEST_GROUP(SimGeometry){};

TEST(SimGeometry, ConvexCounterClockwisePolygonsAreAcceptedOthersRejected) {
    const Vec2 ccw[] = {{0, 0}, {1, 0}, {1, 1}, {0, 1}};
    const Vec2 cw[] = {{0, 0}, {0, 1}, {1, 1}, {1, 0}};
    const Vec2 concave[] = {{0, 0}, {2, 0}, {1, 0.5}, {2, 2}, {0, 2}};
    const Vec2 collinear[] = {{0, 0}, {1, 0}, {2, 0}, {1, 1}};
    const Vec2 repeated[] = {{0, 0}, {1, 0}, {1, 0}, {0, 1}};
    // A pentagram turns left at every vertex but winds twice.
    Vec2 star[5];
    for (int i = 0; i < 5; ++i) {
        const double a = 2.0 * kPi * (2.0 * i) / 5.0;
        star[i] = {std::cos(a), std::sin(a)};
    }
    CHECK_TRUE(isConvexCcw(ccw, 4));
    CHECK_FALSE(isConvexCcw(cw, 4));
    CHECK_FALSE(isConvexCcw(concave, 5));
    CHECK_FALSE(isConvexCcw(collinear, 4));
    CHECK_FALSE(isConvexCcw(repeated, 4));
    CHECK_FALSE(isConvexCcw(star, 5));
    CHECK_FALSE(isConvexCcw(ccw, 2));
}

TEST(SimGeometry, PointInPolygonIncludesTheBoundary) {
    const ConvexPolygon b = box(0, 0, 2, 1);
    CHECK_TRUE(pointInPolygon({1.0, 0.5}, b));
    CHECK_TRUE(pointInPolygon({2.0, 0.5}, b));  // on an edge
    CHECK_TRUE(pointInPolygon({0.0, 0.0}, b));  // a vertex
    CHECK_FALSE(pointInPolygon({2.01, 0.5}, b));
    CHECK_FALSE(pointInPolygon({-1.0, -1.0}, b));
}

TEST(SimGeometry, DistanceAndClosestPoint) {
    const ConvexPolygon b = box(0, 0, 2, 1);
    DOUBLES_EQUAL(0.0, distanceToPolygon({1.0, 0.5}, b), 1e-12);
    DOUBLES_EQUAL(1.0, distanceToPolygon({3.0, 0.5}, b), 1e-12);
    DOUBLES_EQUAL(std::sqrt(2.0), distanceToPolygon({3.0, 2.0}, b), 1e-12);  // nearest is the corner
    const Vec2 q = closestPoint({1.0, -3.0}, b);
    DOUBLES_EQUAL(1.0, q.x, 1e-12);
    DOUBLES_EQUAL(0.0, q.y, 1e-12);
}

TEST(SimGeometry, CircleAndSegmentQueries) {
    const ConvexPolygon b = box(0, 0, 2, 1);
    CHECK_TRUE(circleIntersectsPolygon({3.0, 0.5}, 1.0, b));    // touching
    CHECK_FALSE(circleIntersectsPolygon({3.0, 0.5}, 0.99, b));
    CHECK_TRUE(circleIntersectsPolygon({1.0, 0.5}, 0.01, b));   // centre inside
    CHECK_TRUE(circleIntersectsPolygon({2.5, 1.5}, 0.71, b));   // near the corner
    CHECK_FALSE(circleIntersectsPolygon({2.5, 1.5}, 0.70, b));
    CHECK_TRUE(segmentIntersectsPolygon({-1.0, 0.5}, {3.0, 0.5}, b));  // crosses, both ends out
    CHECK_TRUE(segmentIntersectsPolygon({1.0, 0.5}, {1.5, 0.5}, b));   // wholly inside
    CHECK_FALSE(segmentIntersectsPolygon({-1.0, 2.0}, {3.0, 2.0}, b));
    CHECK_TRUE(segmentIntersectsPolygon({-1.0, 1.0}, {3.0, 1.0}, b));  // along an edge
}

TEST(SimGeometry, WrapAngleAndBodyFrame) {
    DOUBLES_EQUAL(0.0, wrapAngle(2.0 * kPi), 1e-12);
    DOUBLES_EQUAL(kPi, wrapAngle(-kPi), 1e-12);
    DOUBLES_EQUAL(-kPi / 2.0, wrapAngle(3.0 * kPi / 2.0), 1e-12);
    DOUBLES_EQUAL(0.5, wrapAngle(0.5), 0.0);
    const Pose2 pose{1.0, 1.0, kPi / 2.0};  // facing +y
    const Vec2 ahead = toBodyFrame(pose, {1.0, 3.0});
    DOUBLES_EQUAL(2.0, ahead.x, 1e-12);
    DOUBLES_EQUAL(0.0, ahead.y, 1e-12);
    const Vec2 left = toBodyFrame(pose, {0.0, 1.0});
    DOUBLES_EQUAL(0.0, left.x, 1e-12);
    DOUBLES_EQUAL(1.0, left.y, 1e-12);
}

TEST(SimGeometry, TerrainQueriesFindTheRightObstacle) {
    Obstacle a;
    a.id = 7;
    a.shape = box(2, -1, 3, 1);
    Obstacle b;
    b.id = 9;
    b.known = false;
    b.shape = box(5, 2, 6, 3);
    const Terrain t(MapBounds{-10, 10, -10, 10}, std::vector<Obstacle>{a, b});
    LONGS_EQUAL(2, t.obstacleCount());
    LONGS_EQUAL(1, t.findById(9));
    CHECK(kNoObstacle == t.findById(3));
    LONGS_EQUAL(0, t.obstacleAt({2.5, 0.0}));
    CHECK(kNoObstacle == t.obstacleAt({4.0, 0.0}));
    LONGS_EQUAL(1, t.firstOverlap({4.5, 2.5}, 0.6));
    CHECK(kNoObstacle == t.firstOverlap({4.0, 0.0}, 0.5));
    LONGS_EQUAL(0, t.firstOnSegment({0, 0}, {10, 0}));
    DOUBLES_EQUAL(1.0, t.clearance({1.0, 0.0}), 1e-12);
    CHECK_TRUE(t.bounds().containsDisc({9.0, 0.0}, 1.0));
    CHECK_FALSE(t.bounds().containsDisc({9.5, 0.0}, 1.0));
}
