// Line-of-sight shortcutting: never longer, never through an obstacle, ends
// kept; and the cut that ends a path where it enters a goal region.
#include <cmath>
#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/habitual/rrt_star.hpp"
#include "unit_test/bench/rrt_bench_maps.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::habitual::LocalMap;
using rse::habitual::pathLength;
using rse::geometry::Point2;
using rse::habitual::shortcutPath;

namespace {

rse::habitual::RrtStar planner;
LocalMap field;
Point2 raw[rse::habitual::kMaxRrtNodes + 1];

bool samePoint(Point2 a, Point2 b) { return a.x == b.x && a.y == b.y; }

}  // namespace

TEST_GROUP(PathShortcut) {
    LocalMap map;
    void setup() override {
        CHECK(Status::kOk == map.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, 0.5));
        const Point2 square[4] = {{4.0, 4.0}, {6.0, 4.0}, {6.0, 6.0}, {4.0, 6.0}};
        CHECK(Status::kOk == map.addPolygon(square, 4));
    }
};

TEST(PathShortcut, PathLengthSumsTheSegments) {
    const Point2 p[3] = {{0.0, 0.0}, {3.0, 4.0}, {3.0, 6.0}};
    DOUBLES_EQUAL(7.0, pathLength(p, 3), 1e-12);
    DOUBLES_EQUAL(0.0, pathLength(p, 1), 0.0);
    DOUBLES_EQUAL(0.0, pathLength(nullptr, 3), 0.0);
}

TEST(PathShortcut, ZigZagInTheOpenBecomesOneSegment) {
    Point2 p[6] = {{1.0, 1.0}, {2.0, 2.5}, {3.0, 1.0}, {1.5, 8.0}, {3.0, 9.0}, {2.0, 9.0}};
    const double before = pathLength(p, 6);
    LONGS_EQUAL(2, shortcutPath(map, p, 6));
    CHECK(samePoint(Point2{1.0, 1.0}, p[0]));
    CHECK(samePoint(Point2{2.0, 9.0}, p[1]));
    CHECK(pathLength(p, 2) < before);
}

TEST(PathShortcut, DetourAroundTheObstacleKeepsACornerAndStaysFree) {
    // Around the inflated square from (2, 5) to (8, 5) through points well clear of it.
    Point2 p[7] = {{2.0, 5.0}, {2.5, 6.5}, {3.5, 7.2}, {5.0, 7.5}, {6.5, 7.2}, {7.5, 6.5}, {8.0, 5.0}};
    const double before = pathLength(p, 7);
    const std::size_t n = shortcutPath(map, p, 7);
    CHECK(n >= 3);
    CHECK(n < 7);
    CHECK(samePoint(Point2{2.0, 5.0}, p[0]));
    CHECK(samePoint(Point2{8.0, 5.0}, p[n - 1]));
    for (std::size_t i = 1; i < n; ++i) {
        CHECK(map.segmentFree(p[i - 1], p[i]));
    }
    CHECK(pathLength(p, n) <= before);
}

TEST(PathShortcut, ShortInputsAndBlockedInputSegmentsAreLeftAlone) {
    Point2 two[2] = {{1.0, 5.0}, {9.0, 5.0}};  // blocked, but nothing to shortcut
    LONGS_EQUAL(2, shortcutPath(map, two, 2));
    LONGS_EQUAL(0, shortcutPath(map, nullptr, 5));
    // The middle segment crosses the obstacle: no shortcut may skip past it
    // through the obstacle, and the result is no longer than the input.
    Point2 p[4] = {{1.0, 5.0}, {3.0, 5.0}, {7.0, 5.0}, {9.0, 5.0}};
    const std::size_t n = shortcutPath(map, p, 4);
    LONGS_EQUAL(4, n);  // no segment skipping a point is free
    DOUBLES_EQUAL(8.0, pathLength(p, n), 1e-12);
    CHECK(samePoint(Point2{9.0, 5.0}, p[n - 1]));
    for (std::size_t i = 1; i < n; ++i) {  // each kept segment is free or was in the input
        const bool wasInput = (samePoint(p[i - 1], Point2{3.0, 5.0}) && samePoint(p[i], Point2{7.0, 5.0}));
        CHECK(map.segmentFree(p[i - 1], p[i]) || wasInput);
    }
}

TEST(PathShortcut, RrtPathsOnTheClutteredFieldGetShorterAndStayFree) {
    CHECK(rse::test::buildBenchMap(1, &field));
    const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[1];
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
        CHECK(Status::kOk == planner.start(field, m.start, m.goal, rse::habitual::RrtStarParams{2.0, 0.05, 0.1, 12}, seed));
        planner.iterate(1500);
        const std::size_t count = planner.bestPath(raw, rse::habitual::kMaxRrtNodes + 1);
        CHECK(count >= 3);
        const double before = pathLength(raw, count);
        const std::size_t n = shortcutPath(field, raw, count);
        CHECK(n >= 2);
        CHECK(n <= count);
        CHECK(pathLength(raw, n) <= before + 1e-12);
        CHECK(samePoint(m.start, raw[0]));
        CHECK(samePoint(m.goal, raw[n - 1]));
        for (std::size_t i = 1; i < n; ++i) {
            CHECK(field.segmentFree(raw[i - 1], raw[i]));
        }
    }
}

// A goal region: the path ends where it first comes within the radius of the
// centre, on the segment that gets there (interpolated), a prefix of the input.
TEST(PathShortcut, APathIsCutWhereItFirstEntersTheDisc) {
    using rse::habitual::cutPathAtDisc;
    // Straight in along x: enters the 2.5 m disc round (10, 0) at (7.5, 0).
    Point2 line[2] = {{0.0, 0.0}, {10.0, 0.0}};
    LONGS_EQUAL(2, cutPathAtDisc(line, 2, Point2{10.0, 0.0}, 2.5));
    DOUBLES_EQUAL(7.5, line[1].x, 1e-12);
    DOUBLES_EQUAL(0.0, line[1].y, 1e-12);
    // A dog-leg whose second segment enters the disc round (6, 4) of radius
    // 1: its last point dropped, the entry on the second segment at (6, 3).
    Point2 leg[3] = {{0.0, 0.0}, {6.0, 0.0}, {6.0, 4.0}};
    LONGS_EQUAL(3, cutPathAtDisc(leg, 3, Point2{6.0, 4.0}, 1.0));
    CHECK(samePoint(Point2{6.0, 0.0}, leg[1]));
    DOUBLES_EQUAL(6.0, leg[2].x, 1e-12);
    DOUBLES_EQUAL(3.0, leg[2].y, 1e-12);
    // The first entry counts, even on a chord that leaves the disc again: the
    // path skims past (5, 1) within 1.5 m before turning back to it.
    Point2 skim[4] = {{0.0, 0.0}, {10.0, 0.0}, {10.0, 5.0}, {5.0, 1.0}};
    LONGS_EQUAL(2, cutPathAtDisc(skim, 4, Point2{5.0, 1.0}, 1.5));
    DOUBLES_EQUAL(5.0 - std::sqrt(1.5 * 1.5 - 1.0), skim[1].x, 1e-12);
    DOUBLES_EQUAL(0.0, skim[1].y, 1e-12);
    DOUBLES_EQUAL(1.5, rse::geometry::distance(skim[1], Point2{5.0, 1.0}), 1e-12);
}

TEST(PathShortcut, APathNotEnteringTheDiscOrStartingInItIsLeftWhole) {
    using rse::habitual::cutPathAtDisc;
    Point2 p[3] = {{0.0, 0.0}, {4.0, 0.0}, {4.0, 4.0}};
    LONGS_EQUAL(3, cutPathAtDisc(p, 3, Point2{9.0, 9.0}, 2.0));  // never within 2 m
    CHECK(samePoint(Point2{4.0, 4.0}, p[2]));
    LONGS_EQUAL(3, cutPathAtDisc(p, 3, Point2{0.5, 0.0}, 1.0));  // starts inside: nothing to cut to
    LONGS_EQUAL(3, cutPathAtDisc(p, 3, Point2{4.0, 4.0}, 0.0));  // radius 0: the point itself
    CHECK(samePoint(Point2{4.0, 4.0}, p[2]));
    LONGS_EQUAL(3, cutPathAtDisc(p, 3, Point2{4.0, 4.0}, -1.0));
    LONGS_EQUAL(1, cutPathAtDisc(p, 1, Point2{4.0, 4.0}, 1.0));
    LONGS_EQUAL(0, cutPathAtDisc(nullptr, 3, Point2{4.0, 4.0}, 1.0));
}
