// The coarse map as the planners read it (fsw/geometry/coarse_map.hpp): the
// slots in use, their vertices, and the distance to the nearest polygon.
#include <cmath>

#include "fsw/geometry/coarse_map.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;

namespace {

// Slot slot as the polygon (x0, y0)..(x1, y1), counter-clockwise, or clockwise when cw.
void putBox(tables::CoarseMapTable* map, std::size_t slot, double x0, double y0, double x1, double y1,
            bool cw = false) {
    const double xs[4] = {x0, x1, x1, x0};
    const double ys[4] = {y0, y0, y1, y1};
    for (std::size_t v = 0; v < 4; ++v) {
        const std::size_t k = cw ? 3 - v : v;
        map->vertex_x_m[slot * geometry::kCoarseMapVerticesPerSlot + v] = static_cast<float>(xs[k]);
        map->vertex_y_m[slot * geometry::kCoarseMapVerticesPerSlot + v] = static_cast<float>(ys[k]);
    }
    map->vertex_count[slot] = 4;
}

}  // namespace

TEST_GROUP(CoarseMap){};

TEST(CoarseMap, NoPolygonsIsInfinitelyFar) {
    tables::CoarseMapTable map{};
    CHECK(std::isinf(geometry::distanceToCoarseMap(map, Point2{0.0, 0.0})));
}

TEST(CoarseMap, DistanceIsToTheNearestPolygonInEitherWindingAndZeroInside) {
    tables::CoarseMapTable map{};
    putBox(&map, 0, 0.0, 0.0, 1.0, 1.0);
    putBox(&map, 1, 5.0, 0.0, 6.0, 1.0, true);
    map.obstacle_count = 2;
    DOUBLES_EQUAL(0.0, geometry::distanceToCoarseMap(map, Point2{0.5, 0.5}), 0.0);
    DOUBLES_EQUAL(0.0, geometry::distanceToCoarseMap(map, Point2{5.5, 0.5}), 0.0);  // clockwise box
    DOUBLES_EQUAL(0.0, geometry::distanceToCoarseMap(map, Point2{1.0, 0.5}), 0.0);  // on the edge
    DOUBLES_EQUAL(1.0, geometry::distanceToCoarseMap(map, Point2{2.0, 0.5}), 1e-12);
    DOUBLES_EQUAL(1.0, geometry::distanceToCoarseMap(map, Point2{4.0, 0.5}), 1e-12);
    DOUBLES_EQUAL(std::sqrt(2.0), geometry::distanceToCoarseMap(map, Point2{7.0, 2.0}), 1e-12);
}

TEST(CoarseMap, OnlySlotsInUseWithThreeToEightVerticesCount) {
    tables::CoarseMapTable map{};
    putBox(&map, 0, 0.0, 0.0, 1.0, 1.0);
    putBox(&map, 1, 5.0, 0.0, 6.0, 1.0);
    map.obstacle_count = 1;  // slot 1 not in use
    LONGS_EQUAL(1, geometry::coarseMapSlotsUsed(map));
    DOUBLES_EQUAL(0.5, geometry::distanceToCoarseMap(map, Point2{1.5, 0.5}), 1e-12);
    DOUBLES_EQUAL(4.5, geometry::distanceToCoarseMap(map, Point2{5.5, 0.5}), 1e-12);
    map.obstacle_count = 2;
    map.vertex_count[1] = 9;  // more than a slot holds: left out, never read past the slot
    LONGS_EQUAL(0, geometry::coarseMapVerticesUsed(map, 1));
    DOUBLES_EQUAL(4.5, geometry::distanceToCoarseMap(map, Point2{5.5, 0.5}), 1e-12);
    map.vertex_count[1] = 2;
    LONGS_EQUAL(0, geometry::coarseMapVerticesUsed(map, 1));
    LONGS_EQUAL(0, geometry::coarseMapVerticesUsed(map, geometry::kCoarseMapSlots));
    map.obstacle_count = 200;  // beyond the table: bounded by its slots
    LONGS_EQUAL(geometry::kCoarseMapSlots, geometry::coarseMapSlotsUsed(map));
}

TEST(CoarseMap, VerticesAreReadFromTheirSlotsRow) {
    tables::CoarseMapTable map{};
    putBox(&map, 3, 2.0, 4.0, 3.0, 5.0);
    map.obstacle_count = 4;
    const Point2 v = geometry::coarseMapVertex(map, 3, 2);
    DOUBLES_EQUAL(3.0, v.x, 0.0);
    DOUBLES_EQUAL(5.0, v.y, 0.0);
}
