#include "fsw/geometry/coarse_map.hpp"

#include <cmath>
#include <type_traits>

namespace rse::geometry {

static_assert(std::extent<decltype(tables::CoarseMapTable::vertex_count)>::value == kCoarseMapSlots,
              "table 9 layout: one vertex count per slot");
static_assert(std::extent<decltype(tables::CoarseMapTable::vertex_x_m)>::value ==
                  kCoarseMapSlots * kCoarseMapVerticesPerSlot,
              "table 9 layout: kCoarseMapVerticesPerSlot x per slot");
static_assert(std::extent<decltype(tables::CoarseMapTable::vertex_y_m)>::value ==
                  kCoarseMapSlots * kCoarseMapVerticesPerSlot,
              "table 9 layout: kCoarseMapVerticesPerSlot y per slot");

namespace {

// Distance from p to one convex polygon of the table, either winding; 0 inside.
double distanceToPolygon(const tables::CoarseMapTable& coarse, std::size_t slot, std::size_t count, Point2 p) {
    bool left = true;   // p left of (or on) every edge
    bool right = true;  // p right of (or on) every edge
    double best = INFINITY;
    for (std::size_t v = 0; v < count; ++v) {
        const Point2 a = coarseMapVertex(coarse, slot, v);
        const Point2 b = coarseMapVertex(coarse, slot, v + 1 == count ? 0 : v + 1);
        const double side = cross(b - a, p - a);
        left = left && side >= 0.0;
        right = right && side <= 0.0;
        const double d2 = pointSegmentDistanceSquared(p, a, b);
        best = d2 < best ? d2 : best;
    }
    return (left || right) ? 0.0 : std::sqrt(best);
}

}  // namespace

std::size_t coarseMapSlotsUsed(const tables::CoarseMapTable& coarse) {
    const std::size_t n = coarse.obstacle_count;
    return n <= kCoarseMapSlots ? n : kCoarseMapSlots;
}

std::size_t coarseMapVerticesUsed(const tables::CoarseMapTable& coarse, std::size_t slot) {
    if (slot >= kCoarseMapSlots) {
        return 0;
    }
    const std::size_t n = coarse.vertex_count[slot];
    return n >= 3 && n <= kCoarseMapVerticesPerSlot ? n : 0;
}

Point2 coarseMapVertex(const tables::CoarseMapTable& coarse, std::size_t slot, std::size_t vertex) {
    const std::size_t i = slot * kCoarseMapVerticesPerSlot + vertex;
    return Point2{static_cast<double>(coarse.vertex_x_m[i]), static_cast<double>(coarse.vertex_y_m[i])};
}

double distanceToCoarseMap(const tables::CoarseMapTable& coarse, Point2 p) {
    double best = INFINITY;
    const std::size_t slots = coarseMapSlotsUsed(coarse);
    for (std::size_t s = 0; s < slots; ++s) {
        const std::size_t n = coarseMapVerticesUsed(coarse, s);
        if (n == 0) {
            continue;
        }
        const double d = distanceToPolygon(coarse, s, n, p);
        best = d < best ? d : best;
    }
    return best;
}

}  // namespace rse::geometry
