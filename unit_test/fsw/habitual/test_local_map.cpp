// LocalMap: bounds, inflated convex polygons and discs, exact point and segment
// tests, and refusals that leave the map as it was.
#include <cmath>
#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "unit_test/bench/rrt_bench_maps.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::habitual::LocalMap;
using rse::geometry::Point2;

namespace {

// A 2 m square [4, 6] x [4, 6] on a 10 m map, clearance 0.5 m.
constexpr double kClearance = 0.5;
const Point2 kSquare[4] = {{4.0, 4.0}, {6.0, 4.0}, {6.0, 6.0}, {4.0, 6.0}};

bool sameFreedom(const LocalMap& a, const LocalMap& b) {
    for (int i = 0; i <= 40; ++i) {
        for (int j = 0; j <= 40; ++j) {
            const Point2 p{0.25 * i, 0.25 * j};
            if (a.pointFree(p) != b.pointFree(p)) {
                return false;
            }
        }
    }
    return true;
}

}  // namespace

TEST_GROUP(LocalMap) {
    LocalMap map;
    void setup() override {
        CHECK(Status::kOk == map.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, kClearance));
    }
};

TEST(LocalMap, ResetRefusesBadBoundsAndClearance) {
    LocalMap m;
    CHECK(!m.pointFree(Point2{1.0, 1.0}));  // never reset: nothing is free
    CHECK(Status::kNotInitialized == m.addDisc(Point2{1.0, 1.0}, 1.0));
    CHECK(Status::kInvalidArgument == m.reset(Point2{0.0, 0.0}, Point2{0.0, 10.0}, 0.5));
    CHECK(Status::kInvalidArgument == m.reset(Point2{0.0, 5.0}, Point2{10.0, 1.0}, 0.5));
    CHECK(Status::kInvalidArgument == m.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, -0.1));
    CHECK(Status::kInvalidArgument == m.reset(Point2{std::nan(""), 0.0}, Point2{10.0, 10.0}, 0.5));
    CHECK(Status::kInvalidArgument == m.reset(Point2{0.0, 0.0}, Point2{INFINITY, 10.0}, 0.5));
    CHECK(Status::kInvalidArgument == m.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, std::nan("")));
    CHECK(!m.valid());
    CHECK(!m.pointFree(Point2{1.0, 1.0}));
    LONGS_EQUAL(7, m.refusedCalls());  // the early addDisc and six resets
    CHECK(Status::kOk == m.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, 0.0));
    CHECK(m.valid());
    CHECK(m.pointFree(Point2{1.0, 1.0}));
    DOUBLES_EQUAL(0.0, m.clearance(), 0.0);
}

TEST(LocalMap, BoundsAreClosedAndConvex) {
    CHECK(map.pointFree(Point2{0.0, 0.0}));
    CHECK(map.pointFree(Point2{10.0, 5.0}));
    CHECK(!map.pointFree(Point2{10.000001, 5.0}));
    CHECK(!map.pointFree(Point2{5.0, -0.000001}));
    CHECK(map.segmentFree(Point2{0.0, 0.0}, Point2{10.0, 10.0}));
    CHECK(!map.segmentFree(Point2{1.0, 1.0}, Point2{11.0, 1.0}));
    CHECK(!map.segmentFree(Point2{-1.0, 1.0}, Point2{1.0, 1.0}));
}

TEST(LocalMap, PolygonIsInflatedByTheClearanceWithRoundCorners) {
    CHECK(Status::kOk == map.addPolygon(kSquare, 4));
    LONGS_EQUAL(1, map.polygonCount());
    CHECK(!map.pointFree(Point2{5.0, 5.0}));    // inside
    CHECK(!map.pointFree(Point2{6.0, 5.0}));    // on an edge
    CHECK(!map.pointFree(Point2{6.49, 5.0}));   // within the clearance of an edge
    CHECK(!map.pointFree(Point2{6.5, 5.0}));    // exactly at the clearance: blocked
    CHECK(map.pointFree(Point2{6.51, 5.0}));
    CHECK(!map.pointFree(Point2{3.51, 5.0}));
    CHECK(map.pointFree(Point2{3.49, 5.0}));
    // Corner: the inflated shape is rounded, not a bigger square.
    CHECK(!map.pointFree(Point2{6.35, 6.35}));  // 0.495 m from the corner
    CHECK(map.pointFree(Point2{6.36, 6.36}));   // 0.509 m
    CHECK(map.pointFree(Point2{6.45, 6.45}));   // inside the square-inflated box, 0.636 m away
    CHECK(map.pointFree(Point2{3.6, 3.6}));
}

TEST(LocalMap, SegmentsAreTestedExactlyAgainstTheInflatedPolygon) {
    CHECK(Status::kOk == map.addPolygon(kSquare, 4));
    // Passing beside the top edge at 0.51 m and at 0.49 m.
    CHECK(map.segmentFree(Point2{1.0, 6.51}, Point2{9.0, 6.51}));
    CHECK(!map.segmentFree(Point2{1.0, 6.49}, Point2{9.0, 6.49}));
    // Crossing the polygon with both ends far outside (no endpoint near it).
    CHECK(!map.segmentFree(Point2{1.0, 5.0}, Point2{9.0, 5.0}));
    CHECK(!map.segmentFree(Point2{1.0, 1.0}, Point2{9.0, 9.0}));
    // Wholly inside, farther than the clearance from every edge.
    CHECK(!map.segmentFree(Point2{4.5, 4.5}, Point2{5.5, 5.5}));
    CHECK(!map.segmentFree(Point2{4.9, 5.0}, Point2{5.1, 5.0}));
    // Grazing the rounded corner: the diagonal line x + y = c passes the corner
    // (6, 6) at distance |12 - c| / sqrt(2).
    const double c1 = 12.0 + 0.51 * std::sqrt(2.0);
    const double c2 = 12.0 + 0.49 * std::sqrt(2.0);
    CHECK(map.segmentFree(Point2{c1 - 9.0, 9.0}, Point2{9.0, c1 - 9.0}));
    CHECK(!map.segmentFree(Point2{c2 - 9.0, 9.0}, Point2{9.0, c2 - 9.0}));
    // A segment ending just short of the inflated edge, pointing at it.
    CHECK(map.segmentFree(Point2{9.0, 5.0}, Point2{6.51, 5.0}));
    CHECK(!map.segmentFree(Point2{9.0, 5.0}, Point2{6.49, 5.0}));
    // A zero-length segment is a point.
    CHECK(map.segmentFree(Point2{7.0, 7.0}, Point2{7.0, 7.0}));
    CHECK(!map.segmentFree(Point2{6.2, 5.0}, Point2{6.2, 5.0}));
}

TEST(LocalMap, EitherWindingGivesTheSameObstacle) {
    LocalMap clockwise;
    CHECK(Status::kOk == clockwise.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, kClearance));
    const Point2 cw[4] = {kSquare[3], kSquare[2], kSquare[1], kSquare[0]};
    CHECK(Status::kOk == clockwise.addPolygon(cw, 4));
    CHECK(Status::kOk == map.addPolygon(kSquare, 4));
    CHECK(sameFreedom(map, clockwise));
    CHECK(!clockwise.pointFree(Point2{6.4, 5.0}));
}

TEST(LocalMap, DiscsAreInflatedToo) {
    CHECK(Status::kOk == map.addDisc(Point2{5.0, 5.0}, 1.0));
    LONGS_EQUAL(1, map.discCount());
    CHECK(!map.pointFree(Point2{6.49, 5.0}));
    CHECK(map.pointFree(Point2{6.51, 5.0}));
    CHECK(map.segmentFree(Point2{1.0, 6.51}, Point2{9.0, 6.51}));   // tangent line at 1.51 m
    CHECK(!map.segmentFree(Point2{1.0, 6.49}, Point2{9.0, 6.49}));
    CHECK(!map.segmentFree(Point2{1.0, 1.0}, Point2{9.0, 9.0}));    // through the centre
    CHECK(Status::kInvalidArgument == map.addDisc(Point2{5.0, 5.0}, 0.0));
    CHECK(Status::kInvalidArgument == map.addDisc(Point2{5.0, 5.0}, -1.0));
    CHECK(Status::kInvalidArgument == map.addDisc(Point2{std::nan(""), 5.0}, 1.0));
    CHECK(Status::kInvalidArgument == map.addDisc(Point2{5.0, 5.0}, INFINITY));
    LONGS_EQUAL(1, map.discCount());
}

TEST(LocalMap, ZeroClearanceBlocksTouching) {
    CHECK(Status::kOk == map.reset(Point2{0.0, 0.0}, Point2{10.0, 10.0}, 0.0));
    CHECK(Status::kOk == map.addPolygon(kSquare, 4));
    CHECK(!map.pointFree(Point2{6.0, 5.0}));
    CHECK(map.pointFree(Point2{6.001, 5.0}));
    CHECK(!map.segmentFree(Point2{6.0, 0.0}, Point2{6.0, 9.0}));  // slides along an edge
    CHECK(!map.segmentFree(Point2{5.0, 7.0}, Point2{7.0, 5.0}));  // touches the corner (6, 6)
    CHECK(map.segmentFree(Point2{5.0, 7.01}, Point2{7.01, 5.0}));
}

TEST(LocalMap, BadPolygonsAreRefusedAndTheMapIsUnchanged) {
    CHECK(Status::kOk == map.addDisc(Point2{2.0, 8.0}, 0.5));
    LocalMap before = map;
    const Point2 dart[4] = {{4.0, 4.0}, {6.0, 5.0}, {4.0, 6.0}, {5.0, 5.0}};  // reflex vertex
    const Point2 star[5] = {{5.0, 8.0}, {6.76, 2.57}, {2.15, 5.93}, {7.85, 5.93}, {3.24, 2.57}};
    const Point2 repeated[4] = {{4.0, 4.0}, {6.0, 4.0}, {6.0, 4.0}, {4.0, 6.0}};
    const Point2 collinear[3] = {{1.0, 1.0}, {2.0, 2.0}, {3.0, 3.0}};
    const Point2 spike[4] = {{4.0, 4.0}, {6.0, 4.0}, {8.0, 4.0}, {6.0, 4.0}};
    const Point2 nanVertex[3] = {{1.0, 1.0}, {2.0, std::nan("")}, {1.0, 2.0}};
    Point2 nine[9];
    for (int i = 0; i < 9; ++i) {
        nine[i] = Point2{5.0 + std::cos(0.698 * i), 5.0 + std::sin(0.698 * i)};
    }
    CHECK(Status::kInvalidArgument == map.addPolygon(dart, 4));
    CHECK(Status::kInvalidArgument == map.addPolygon(star, 5));
    CHECK(Status::kInvalidArgument == map.addPolygon(repeated, 4));
    CHECK(Status::kInvalidArgument == map.addPolygon(collinear, 3));
    CHECK(Status::kInvalidArgument == map.addPolygon(spike, 4));
    CHECK(Status::kInvalidArgument == map.addPolygon(nanVertex, 3));
    CHECK(Status::kInvalidArgument == map.addPolygon(kSquare, 2));
    CHECK(Status::kInvalidArgument == map.addPolygon(nine, 9));
    CHECK(Status::kInvalidArgument == map.addPolygon(nullptr, 4));
    LONGS_EQUAL(0, map.polygonCount());
    CHECK(sameFreedom(map, before));
    CHECK(map.pointFree(Point2{5.0, 5.0}));
    // Collinear middle vertices are fine (a square with a midpoint on one edge).
    const Point2 withMidpoint[5] = {{4.0, 4.0}, {5.0, 4.0}, {6.0, 4.0}, {6.0, 6.0}, {4.0, 6.0}};
    CHECK(Status::kOk == map.addPolygon(withMidpoint, 5));
    CHECK(!map.pointFree(Point2{5.0, 5.0}));
    // Eight vertices are fine.
    CHECK(Status::kOk == map.addPolygon(nine, 8));
}

TEST(LocalMap, FullMapRefusesMoreAndStaysAsItWas) {
    for (std::size_t i = 0; i < rse::habitual::kMaxMapPolygons; ++i) {
        const double x = 0.2 * static_cast<double>(i % 40);
        const double y = i < 40 ? 9.0 : 9.5;
        const Point2 tri[3] = {{x, y}, {x + 0.1, y}, {x, y + 0.1}};
        CHECK(Status::kOk == map.addPolygon(tri, 3));
    }
    LocalMap before = map;
    CHECK(Status::kFull == map.addPolygon(kSquare, 4));
    LONGS_EQUAL(rse::habitual::kMaxMapPolygons, map.polygonCount());
    CHECK(map.pointFree(Point2{5.0, 5.0}));
    CHECK(sameFreedom(map, before));
    for (std::size_t i = 0; i < rse::habitual::kMaxMapDiscs; ++i) {
        CHECK(Status::kOk == map.addDisc(Point2{0.3 * static_cast<double>(i), 0.5}, 0.05));
    }
    CHECK(Status::kFull == map.addDisc(Point2{5.0, 5.0}, 1.0));
    CHECK(map.pointFree(Point2{5.0, 5.0}));
}

TEST(LocalMap, ObstaclesOutsideTheBoundsStillBlockNearTheEdge) {
    const Point2 outside[4] = {{10.2, 4.0}, {11.0, 4.0}, {11.0, 6.0}, {10.2, 6.0}};
    CHECK(Status::kOk == map.addPolygon(outside, 4));
    CHECK(!map.pointFree(Point2{9.8, 5.0}));  // 0.4 m from the polygon, inside the bounds
    CHECK(map.pointFree(Point2{9.6, 5.0}));
    CHECK(Status::kOk == map.addDisc(Point2{-5.0, -5.0}, 1.0));  // far away: harmless
    CHECK(map.pointFree(Point2{0.0, 0.0}));
}

// Exact, not sampled: against dense sampling of pointFree on the cluttered
// benchmark field, a free segment has no blocked sample, and a segment with a
// blocked sample is never called free.
TEST(LocalMap, SegmentFreeAgreesWithDenseSamplingOnTheClutteredField) {
    static LocalMap field;
    CHECK(rse::test::buildBenchMap(1, &field));
    LONGS_EQUAL(30, field.polygonCount());
    std::uint64_t state = 12345;
    const auto uniform = [&state]() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * 0x1.0p-53;
    };
    int freeSegments = 0;
    int blockedSegments = 0;
    for (int n = 0; n < 3000; ++n) {
        const Point2 a{20.0 * uniform(), 20.0 * uniform()};
        const double angle = 6.283185307179586 * uniform();
        const double length = 3.0 * uniform();
        const Point2 b{a.x + length * std::cos(angle), a.y + length * std::sin(angle)};
        bool sampledFree = true;
        for (int i = 0; i <= 600 && sampledFree; ++i) {
            const double t = i / 600.0;
            sampledFree = field.pointFree(Point2{a.x + t * (b.x - a.x), a.y + t * (b.y - a.y)});
        }
        const bool exact = field.segmentFree(a, b);
        if (exact) {
            CHECK(sampledFree);
            ++freeSegments;
        } else {
            ++blockedSegments;
        }
        if (!sampledFree) {
            CHECK(!exact);
        }
    }
    CHECK(freeSegments > 300);
    CHECK(blockedSegments > 300);
}
