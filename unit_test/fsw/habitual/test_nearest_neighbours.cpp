// The RRT* point grid against brute force: nearest and k-nearest-within-radius
// answers, in a rotated frame, after re-gridding, for clustered points and for
// queries far outside the occupied cells.
#include <algorithm>
#include <cmath>
#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/nearest_neighbours.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::habitual::Neighbour;
using rse::geometry::Point2;

namespace {

constexpr std::size_t kCapacity = 4096;
using Grid = rse::habitual::PointGrid<kCapacity>;
Grid grid;
Point2 points[kCapacity];
std::uint8_t keep[kCapacity];

struct Random {
    std::uint64_t state;
    double uniform() {
        state = state * 6364136223846793005ULL + 1442695040888963407ULL;
        return static_cast<double>(state >> 11) * 0x1.0p-53;
    }
};

// The k-th smallest distance among points[0..n) within radius (or +inf), and how many lie within.
double kthDistance(Point2 q, std::size_t n, double radius, std::size_t k, std::size_t* within) {
    static double d2[kCapacity];
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = rse::geometry::distanceSquared(q, points[i]);
        if (d <= radius * radius) {
            d2[m++] = d;
        }
    }
    *within = m;
    if (m == 0) {
        return INFINITY;
    }
    std::sort(d2, d2 + m);
    return d2[std::min(k, m) - 1];
}

void checkQueries(Random& rng, std::size_t n, Point2 lo, Point2 hi, int queries) {
    Neighbour out[64];
    for (int t = 0; t < queries; ++t) {
        // Queries also well outside the points' box.
        const Point2 q{lo.x - 5.0 + (hi.x - lo.x + 10.0) * rng.uniform(), lo.y - 5.0 + (hi.y - lo.y + 10.0) * rng.uniform()};
        std::size_t within = 0;
        const std::uint32_t nearest = grid.nearest(q);
        CHECK(nearest < n);
        DOUBLES_EQUAL(kthDistance(q, n, INFINITY, 1, &within), rse::geometry::distanceSquared(q, points[nearest]), 0.0);
        const double radius = 3.0 * rng.uniform();
        const std::size_t k = 1 + static_cast<std::size_t>(63.0 * rng.uniform());
        const std::size_t got = grid.nearestWithin(q, radius, k, out);
        const double kth = kthDistance(q, n, radius, k, &within);
        LONGS_EQUAL(std::min(k, within), got);
        double largest = 0.0;
        for (std::size_t i = 0; i < got; ++i) {
            CHECK(out[i].id < n);
            DOUBLES_EQUAL(rse::geometry::distanceSquared(q, points[out[i].id]), out[i].distanceSquared, 0.0);
            CHECK(out[i].distanceSquared <= radius * radius);
            for (std::size_t j = 0; j < i; ++j) {
                CHECK(out[i].id != out[j].id);
            }
            largest = std::max(largest, out[i].distanceSquared);
        }
        if (got > 0) {
            DOUBLES_EQUAL(kth, largest, 0.0);  // exactly the k nearest (ties aside, the same distances)
        }
    }
}

}  // namespace

TEST_GROUP(PointGrid){};

TEST(PointGrid, RefusesBadFramesAndPointsOutsideTheBox) {
    CHECK(Status::kInvalidArgument == grid.reset(Point2{0, 0}, Point2{2.0, 0.0}, Point2{0, 0}, Point2{1, 1}, 16));
    CHECK(Status::kInvalidArgument == grid.reset(Point2{0, 0}, Point2{1.0, 0.0}, Point2{1, 0}, Point2{1, 1}, 16));
    CHECK(Status::kInvalidArgument == grid.reset(Point2{0, 0}, Point2{1.0, 0.0}, Point2{0, 0}, Point2{1, 1}, 0));
    CHECK(Status::kInvalidArgument ==
          grid.reset(Point2{0, 0}, Point2{1.0, 0.0}, Point2{0, 0}, Point2{1, 1}, Grid::kMaxCells + 1));
    CHECK(Status::kInvalidArgument == grid.reset(Point2{std::nan(""), 0}, Point2{1.0, 0.0}, Point2{0, 0}, Point2{1, 1}, 16));
    CHECK(Status::kOk == grid.reset(Point2{0, 0}, Point2{1.0, 0.0}, Point2{0, 0}, Point2{10, 10}, 16));
    CHECK(grid.cellCount() <= 16);
    std::uint32_t id = 99;
    CHECK(Status::kInvalidArgument == grid.insert(Point2{10.5, 5.0}, &id));
    CHECK(grid.nearest(Point2{1.0, 1.0}) == Grid::kNone);
    CHECK(Status::kOk == grid.insert(Point2{10.0, 10.0}, &id));
    LONGS_EQUAL(0, id);
    for (std::size_t i = 1; i < kCapacity; ++i) {
        CHECK(Status::kOk == grid.insert(Point2{5.0, 5.0}, nullptr));
    }
    CHECK(Status::kFull == grid.insert(Point2{5.0, 5.0}, &id));
    LONGS_EQUAL(kCapacity, grid.size());
}

TEST(PointGrid, MatchesBruteForceInARotatedFrameAsPointsAreAdded) {
    Random rng{7};
    const double angle = 0.7;
    const Point2 axis{std::cos(angle), std::sin(angle)};
    const Point2 origin{3.0, -2.0};
    // The box of the square [0, 20]^2 seen in that frame.
    Point2 lo{INFINITY, INFINITY};
    Point2 hi{-INFINITY, -INFINITY};
    const Point2 corners[4] = {{0, 0}, {20, 0}, {20, 20}, {0, 20}};
    for (const Point2 c : corners) {
        const Point2 d = c - origin;
        const Point2 l{rse::geometry::dot(d, axis), rse::geometry::cross(axis, d)};
        lo = Point2{std::min(lo.x, l.x), std::min(lo.y, l.y)};
        hi = Point2{std::max(hi.x, l.x), std::max(hi.y, l.y)};
    }
    CHECK(Status::kOk == grid.reset(origin, axis, lo, hi, 1024));
    std::size_t n = 0;
    for (std::size_t batch : {1U, 10U, 100U, 1000U, 3000U}) {
        for (; n < batch; ++n) {
            // Half uniform, half in a tight cluster (many points per cell).
            points[n] = n % 2 == 0 ? Point2{20.0 * rng.uniform(), 20.0 * rng.uniform()}
                                   : Point2{12.0 + 0.3 * rng.uniform(), 4.0 + 0.3 * rng.uniform()};
            std::uint32_t id = 0;
            CHECK(Status::kOk == grid.insert(points[n], &id));
            LONGS_EQUAL(n, id);
        }
        checkQueries(rng, n, Point2{0, 0}, Point2{20, 20}, 200);
    }
}

TEST(PointGrid, RegridKeepsTheChosenPointsRenumberedInOrder) {
    Random rng{11};
    CHECK(Status::kOk == grid.reset(Point2{0, 0}, Point2{1.0, 0.0}, Point2{0, 0}, Point2{20, 20}, 256));
    const std::size_t n = 2000;
    for (std::size_t i = 0; i < n; ++i) {
        points[i] = Point2{20.0 * rng.uniform(), 20.0 * rng.uniform()};
        CHECK(Status::kOk == grid.insert(points[i], nullptr));
        keep[i] = (i % 3 != 0) ? 1 : 0;
    }
    // A box smaller than the kept points' spread: it must widen to hold them.
    grid.regrid(keep, Point2{5, 5}, Point2{6, 6}, 4096);
    std::size_t m = 0;
    for (std::size_t i = 0; i < n; ++i) {
        if (keep[i] != 0) {
            points[m++] = points[i];
        }
    }
    LONGS_EQUAL(m, grid.size());
    for (std::size_t i = 0; i < m; ++i) {
        CHECK(grid.point(static_cast<std::uint32_t>(i)).x == points[i].x);
        CHECK(grid.point(static_cast<std::uint32_t>(i)).y == points[i].y);
    }
    CHECK(grid.cellCount() <= 4096);
    CHECK(grid.cellCount() > 1024);
    checkQueries(rng, m, Point2{0, 0}, Point2{20, 20}, 300);
    // And points keep coming after it.
    for (std::size_t i = m; i < m + 500; ++i) {
        points[i] = Point2{19.0 * rng.uniform(), 19.0 * rng.uniform()};
        CHECK(Status::kOk == grid.insert(points[i], nullptr));
    }
    checkQueries(rng, m + 500, Point2{0, 0}, Point2{20, 20}, 300);
}
