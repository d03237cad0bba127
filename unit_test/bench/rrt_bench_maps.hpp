// The 2-D maps the RRT* benchmark (and the rrt_star unit tests) plan on: a
// 20 m x 20 m square, footprint clearance 0.6 m (the rover geometry table's
// footprint radius), obstacles as convex polygons inflated by the map.
//   open      no obstacle; start and goal at opposite corners
//   cluttered 30 convex polygons (3..8 vertices, 0.3..0.9 m radius) placed from
//             a fixed seed, none within reach of start or goal
//   narrow    a 0.5 m thick wall across the square with one 1.6 m gap: inflated,
//             the free corridor through it is 0.4 m wide and 1.7 m long; start
//             and goal on the same side, so the path must go to the gap and back
#pragma once

#include <cmath>
#include <cstdint>

#include "fsw/habitual/local_map.hpp"

namespace rse::test {

struct RrtBenchMap {
    const char* name;
    geometry::Point2 start;
    geometry::Point2 goal;
};

constexpr double kBenchSizeM = 20.0;
constexpr double kBenchClearanceM = 0.6;
constexpr int kBenchMapCount = 3;
constexpr RrtBenchMap kBenchMaps[kBenchMapCount] = {
    {"open", {1.0, 1.0}, {19.0, 19.0}},
    {"cluttered", {1.0, 1.0}, {19.0, 19.0}},
    {"narrow", {2.0, 4.0}, {18.0, 4.0}},
};

// Builds map `index` of kBenchMaps into map; false if something was refused.
inline bool buildBenchMap(int index, habitual::LocalMap* map) {
    using geometry::Point2;
    if (map->reset(Point2{0.0, 0.0}, Point2{kBenchSizeM, kBenchSizeM}, kBenchClearanceM) != core::Status::kOk) {
        return false;
    }
    if (index == 1) {
        std::uint64_t state = 0x5EED5EEDULL;  // fixed: the field is the same on every run
        const auto uniform = [&state]() {
            state = state * 6364136223846793005ULL + 1442695040888963407ULL;
            return static_cast<double>(state >> 11) * 0x1.0p-53;
        };
        const RrtBenchMap& m = kBenchMaps[1];
        int placed = 0;
        for (int attempt = 0; attempt < 10000 && placed < 30; ++attempt) {
            const Point2 c{1.0 + 18.0 * uniform(), 1.0 + 18.0 * uniform()};
            const double radius = 0.3 + 0.6 * uniform();
            const int n = 3 + static_cast<int>(6.0 * uniform());
            const double reach = radius + kBenchClearanceM + 0.3;
            if (geometry::distance(c, m.start) < reach || geometry::distance(c, m.goal) < reach) {
                continue;
            }
            Point2 v[habitual::kMaxPolygonVertices];
            const double phase = 6.283185307179586 * uniform();
            for (int i = 0; i < n; ++i) {  // evenly spread angles, jittered: convex
                const double a = phase + 6.283185307179586 * (i + 0.4 * uniform()) / n;
                v[i] = Point2{c.x + radius * std::cos(a), c.y + radius * std::sin(a)};
            }
            if (map->addPolygon(v, static_cast<std::size_t>(n)) != core::Status::kOk) {
                return false;
            }
            ++placed;
        }
        return placed == 30;
    }
    if (index == 2) {
        const Point2 lower[4] = {{9.75, 0.0}, {10.25, 0.0}, {10.25, 9.2}, {9.75, 9.2}};
        const Point2 upper[4] = {{9.75, 10.8}, {10.25, 10.8}, {10.25, 20.0}, {9.75, 20.0}};
        return map->addPolygon(lower, 4) == core::Status::kOk && map->addPolygon(upper, 4) == core::Status::kOk;
    }
    return index == 0;
}

}  // namespace rse::test
