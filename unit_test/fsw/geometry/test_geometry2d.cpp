// Plane geometry shared by the planners (fsw/geometry/geometry2d.hpp): heading
// differences and the segment distances the collision checks are built from.
#include <cmath>
#include <limits>

#include "fsw/geometry/geometry2d.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

TEST_GROUP(Geometry2d){};

TEST(Geometry2d, WrapAngleStaysInMinusPiToPi) {
    DOUBLES_EQUAL(kPi, geometry::wrapAngleRad(kPi), 1e-12);
    DOUBLES_EQUAL(kPi, geometry::wrapAngleRad(-kPi), 1e-12);
    DOUBLES_EQUAL(-kPi / 2.0, geometry::wrapAngleRad(3.0 * kPi / 2.0), 1e-12);
    DOUBLES_EQUAL(0.5, geometry::wrapAngleRad(0.5 + 8.0 * kPi), 1e-9);
    CHECK(std::isnan(geometry::wrapAngleRad(std::numeric_limits<double>::quiet_NaN())));
}

TEST(Geometry2d, SegmentsThatCrossOrTouchAreZeroApart) {
    DOUBLES_EQUAL(0.0, geometry::segmentSegmentDistanceSquared({0, 0}, {2, 2}, {0, 2}, {2, 0}), 0.0);
    // An endpoint on the other segment: touching counts as meeting.
    DOUBLES_EQUAL(0.0, geometry::segmentSegmentDistanceSquared({0, 0}, {1, 0}, {1, 0}, {1, 5}), 0.0);
    // Parallel, one apart.
    DOUBLES_EQUAL(1.0, geometry::segmentSegmentDistanceSquared({0, 0}, {2, 0}, {0, 1}, {2, 1}), 1e-12);
}

TEST(Geometry2d, PointToSegmentUsesTheNearestEndWhenBeyondIt) {
    DOUBLES_EQUAL(4.0, geometry::pointSegmentDistanceSquared({3, 0}, {-1, 0}, {1, 0}), 1e-12);
    DOUBLES_EQUAL(9.0, geometry::pointSegmentDistanceSquared({0, 3}, {-1, 0}, {1, 0}), 1e-12);
    // A degenerate segment is its point.
    DOUBLES_EQUAL(2.0, geometry::pointSegmentDistanceSquared({1, 1}, {0, 0}, {0, 0}), 1e-12);
}

TEST(Geometry2d, ASegmentAndAConvexPolygonAreZeroApartWhenTheyMeetAndElseTheNearestEdgeDistance) {
    const Point2 square[4] = {{0.0, 0.0}, {2.0, 0.0}, {2.0, 2.0}, {0.0, 2.0}};
    // An end inside, the segment through it with both ends outside, touching a corner.
    DOUBLES_EQUAL(0.0, geometry::segmentConvexPolygonDistanceSquared({1.0, 1.0}, {5.0, 5.0}, square, 4), 0.0);
    DOUBLES_EQUAL(0.0, geometry::segmentConvexPolygonDistanceSquared({-1.0, 1.0}, {3.0, 1.0}, square, 4), 0.0);
    DOUBLES_EQUAL(0.0, geometry::segmentConvexPolygonDistanceSquared({-1.0, 3.0}, {3.0, -1.0}, square, 4), 0.0);
    // Apart: above the top edge, and beyond a corner.
    DOUBLES_EQUAL(1.0, geometry::segmentConvexPolygonDistanceSquared({-1.0, 3.0}, {3.0, 3.0}, square, 4), 1e-12);
    DOUBLES_EQUAL(2.0, geometry::segmentConvexPolygonDistanceSquared({3.0, 3.0}, {3.0, 3.0}, square, 4), 1e-12);
}
