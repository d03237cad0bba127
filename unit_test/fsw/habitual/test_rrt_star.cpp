// k-nearest RRT* on the local map: solutions and their validity, anytime
// improvement towards the optimum, determinism, the tree's invariants after
// rewiring and pruning, the k cap, a full pool, unsolvable queries and zero heap
// use per query.
#include <cmath>
#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/habitual/rrt_star.hpp"
#include "unit_test/bench/rrt_bench_maps.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using rse::core::Status;
using rse::habitual::kMaxRrtNodes;
using rse::habitual::LocalMap;
using rse::geometry::Point2;
using rse::habitual::RrtStar;
using rse::habitual::RrtStarParams;

namespace {

// ~1 MiB each: static storage, as in flight.
RrtStar planner;
RrtStar twin;
LocalMap maps[rse::test::kBenchMapCount];
LocalMap walled;
Point2 path[kMaxRrtNodes + 1];
Point2 otherPath[kMaxRrtNodes + 1];

constexpr RrtStarParams kParams{2.0, 0.05, 0.1, 64};

const LocalMap& benchMap(int index) {
    static bool built[rse::test::kBenchMapCount] = {};
    if (!built[index]) {
        CHECK(rse::test::buildBenchMap(index, &maps[index]));
        built[index] = true;
    }
    return maps[index];
}

bool samePoint(Point2 a, Point2 b) { return a.x == b.x && a.y == b.y; }

// Every node hangs from a parent that exists, its cost is its parent's plus the
// edge, its edge is free, and following parents reaches the start.
void checkTree(const RrtStar& p, const LocalMap& map) {
    const std::size_t n = p.nodeCount();
    CHECK(n >= 1);
    CHECK(p.nodeParent(0) == RrtStar::kNoNode);
    DOUBLES_EQUAL(0.0, p.nodeCost(0), 0.0);
    for (std::size_t id = 1; id < n; ++id) {
        const std::uint32_t parent = p.nodeParent(id);
        CHECK(parent < n);
        const double edge = rse::geometry::distance(p.nodePoint(parent), p.nodePoint(id));
        DOUBLES_EQUAL(p.nodeCost(parent) + edge, p.nodeCost(id), 1e-9 * (1.0 + p.nodeCost(id)));
        CHECK(map.segmentFree(p.nodePoint(parent), p.nodePoint(id)));
        std::size_t hops = 0;
        for (std::uint32_t u = static_cast<std::uint32_t>(id); u != 0 && hops <= n; u = p.nodeParent(u)) {
            ++hops;
        }
        CHECK(hops <= n);
    }
}

// start .. goal, every segment free, its length the reported cost.
std::size_t checkSolution(const RrtStar& p, const LocalMap& map, Point2 start, Point2 goal) {
    CHECK(p.solved());
    const std::size_t count = p.bestPath(path, kMaxRrtNodes + 1);
    CHECK(count >= 2);
    LONGS_EQUAL(p.bestPathPointCount(), count);
    CHECK(samePoint(start, path[0]));
    CHECK(samePoint(goal, path[count - 1]));
    for (std::size_t i = 1; i < count; ++i) {
        CHECK(map.segmentFree(path[i - 1], path[i]));
    }
    DOUBLES_EQUAL(p.bestCost(), rse::habitual::pathLength(path, count), 1e-9 * p.bestCost());
    return count;
}

}  // namespace

TEST_GROUP(RrtStar){};

TEST(RrtStar, StartRefusesBadParametersAndBlockedEnds) {
    const LocalMap& open = benchMap(0);
    const LocalMap& clutter = benchMap(1);
    const Point2 s{1.0, 1.0};
    const Point2 g{19.0, 19.0};
    const RrtStarParams bad[] = {
        {0.0, 0.05, 0.1, 12},  {-1.0, 0.05, 0.1, 12}, {std::nan(""), 0.05, 0.1, 12}, {INFINITY, 0.05, 0.1, 12},
        {2.0, -0.1, 0.1, 12},  {2.0, 1.0, 0.1, 12},   {2.0, std::nan(""), 0.1, 12},  {2.0, 0.05, -0.1, 12},
        {2.0, 0.05, INFINITY, 12}, {2.0, 0.05, 0.1, 0}, {2.0, 0.05, 0.1, 65},
    };
    for (const RrtStarParams& params : bad) {
        CHECK(Status::kInvalidArgument == planner.start(open, s, g, params, 1));
        CHECK(!planner.started());
        LONGS_EQUAL(0, planner.iterate(100));
        CHECK(!planner.solved());
    }
    CHECK(Status::kInvalidArgument == planner.start(open, Point2{-1.0, 1.0}, g, kParams, 1));  // out of bounds
    CHECK(Status::kOk == planner.start(open, s, Point2{0.2, 19.0}, kParams, 1));  // the bounds are not inflated
    CHECK(planner.started());
    // A goal inside an inflated obstacle of the cluttered field.
    Point2 blocked{1.0, 1.0};
    for (int i = 0; i < 1600 && clutter.pointFree(blocked); ++i) {
        blocked = Point2{0.5 * (i % 40), 0.5 * (i / 40)};
    }
    CHECK(!clutter.pointFree(blocked));
    CHECK(Status::kInvalidArgument == planner.start(clutter, s, blocked, kParams, 1));
    CHECK(Status::kInvalidArgument == planner.start(clutter, blocked, g, kParams, 1));
    static LocalMap unset;
    CHECK(Status::kInvalidArgument == planner.start(unset, s, g, kParams, 1));
    CHECK(!planner.started());
    LONGS_EQUAL(0, planner.iterate(10));
}

TEST(RrtStar, OpenMapCostFallsMonotonicallyToTheStraightLine) {
    const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[0];
    const LocalMap& map = benchMap(0);
    const double straight = rse::geometry::distance(m.start, m.goal);
    CHECK(Status::kOk == planner.start(map, m.start, m.goal, kParams, 7));
    double previous = INFINITY;
    int improvements = 0;
    for (int slice = 0; slice < 40; ++slice) {
        LONGS_EQUAL(100, planner.iterate(100));
        const double cost = planner.bestCost();
        CHECK(cost <= previous);
        improvements += cost < previous ? 1 : 0;
        previous = cost;
    }
    LONGS_EQUAL(4000, planner.iterations());
    CHECK(planner.solved());
    CHECK(planner.firstSolutionIteration() < 200);
    CHECK(improvements >= 3);
    CHECK(planner.bestCost() >= straight);
    CHECK(planner.bestCost() <= 1.005 * straight);  // within 0.5 % after 4000 samples
    CHECK(planner.rewires() > 0);
    checkSolution(planner, map, m.start, m.goal);
    checkTree(planner, map);
}

TEST(RrtStar, ClutteredAndNarrowMapsAreSolvedWithFreePaths) {
    for (int mi = 1; mi < 3; ++mi) {
        const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[mi];
        const LocalMap& map = benchMap(mi);
        CHECK(!map.segmentFree(m.start, m.goal));  // no straight shot
        for (std::uint64_t seed = 1; seed <= 4; ++seed) {
            CHECK(Status::kOk == planner.start(map, m.start, m.goal, kParams, seed));
            for (int slice = 0; slice < 50 && !planner.solved(); ++slice) {
                planner.iterate(100);
            }
            checkSolution(planner, map, m.start, m.goal);
            planner.iterate(2000);
            checkSolution(planner, map, m.start, m.goal);
            checkTree(planner, map);
        }
    }
}

TEST(RrtStar, SameSeedSamePlanAndAnotherSeedAnother) {
    const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[1];
    const LocalMap& map = benchMap(1);
    CHECK(Status::kOk == planner.start(map, m.start, m.goal, kParams, 42));
    CHECK(Status::kOk == twin.start(map, m.start, m.goal, kParams, 42));
    for (int slice = 0; slice < 6; ++slice) {  // the same work in different slices
        planner.iterate(500);
    }
    twin.iterate(1000);
    twin.iterate(1999);
    twin.iterate(0);
    twin.iterate(1);
    LONGS_EQUAL(planner.iterations(), twin.iterations());
    LONGS_EQUAL(planner.nodeCount(), twin.nodeCount());
    CHECK(planner.bestCost() == twin.bestCost());
    const std::size_t n = planner.bestPath(path, kMaxRrtNodes + 1);
    LONGS_EQUAL(n, twin.bestPath(otherPath, kMaxRrtNodes + 1));
    for (std::size_t i = 0; i < n; ++i) {
        CHECK(samePoint(path[i], otherPath[i]));
    }
    CHECK(Status::kOk == twin.start(map, m.start, m.goal, kParams, 43));
    twin.iterate(3000);
    CHECK(twin.bestCost() != planner.bestCost() || twin.nodeCount() != planner.nodeCount());
}

TEST(RrtStar, WalledOffGoalGivesNoPathAndAFullPoolEndsTheQuery) {
    CHECK(Status::kOk == walled.reset(Point2{0.0, 0.0}, Point2{20.0, 20.0}, 0.6));
    // A closed square fence of four thin walls around the goal (15, 15).
    const Point2 walls[4][4] = {
        {{12.0, 12.0}, {18.0, 12.0}, {18.0, 12.2}, {12.0, 12.2}},
        {{12.0, 17.8}, {18.0, 17.8}, {18.0, 18.0}, {12.0, 18.0}},
        {{12.0, 12.0}, {12.2, 12.0}, {12.2, 18.0}, {12.0, 18.0}},
        {{17.8, 12.0}, {18.0, 12.0}, {18.0, 18.0}, {17.8, 18.0}},
    };
    for (const auto& wall : walls) {
        CHECK(Status::kOk == walled.addPolygon(wall, 4));
    }
    const Point2 start{2.0, 2.0};
    const Point2 goal{15.0, 15.0};
    CHECK(Status::kOk == planner.start(walled, start, goal, kParams, 3));
    LONGS_EQUAL(3000, planner.iterate(3000));
    CHECK(!planner.solved());
    CHECK(std::isinf(planner.bestCost()));
    LONGS_EQUAL(0, planner.bestPath(path, kMaxRrtNodes + 1));
    LONGS_EQUAL(0, planner.bestPathPointCount());
    // Without a solution nothing can be pruned: the pool fills and iterate()
    // returns short, then does nothing.
    std::uint32_t lastDone = 0;
    for (int call = 0; call < 100 && !planner.poolFull(); ++call) {
        lastDone = planner.iterate(5000);
    }
    CHECK(planner.poolFull());
    LONGS_EQUAL(kMaxRrtNodes, planner.nodeCount());
    CHECK(lastDone < 5000);
    const std::uint32_t iterations = planner.iterations();
    LONGS_EQUAL(0, planner.iterate(100));
    LONGS_EQUAL(iterations, planner.iterations());
    CHECK(!planner.solved());
    // Nodes never got inside the fence.
    for (std::size_t id = 0; id < planner.nodeCount(); ++id) {
        const Point2 p = planner.nodePoint(id);
        CHECK(!(p.x > 12.2 && p.x < 17.8 && p.y > 12.2 && p.y < 17.8));
    }
}

TEST(RrtStar, AFullPoolWithASolutionIsPrunedAndKeepsImproving) {
    const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[2];
    const LocalMap& map = benchMap(2);
    CHECK(Status::kOk == planner.start(map, m.start, m.goal, kParams, 5));
    double previous = INFINITY;
    std::uint32_t total = 0;
    for (int call = 0; call < 30; ++call) {
        const std::uint32_t done = planner.iterate(2000);
        total += done;
        CHECK(planner.bestCost() <= previous);
        previous = planner.bestCost();
        if (done < 2000) {
            break;
        }
    }
    CHECK(planner.regrids() > 0);
    CHECK(planner.prunedNodes() > 0);
    CHECK(total > kMaxRrtNodes);  // more samples than the pool holds nodes
    CHECK(planner.nodeCount() <= kMaxRrtNodes);
    LONGS_EQUAL(total, planner.iterations());
    checkSolution(planner, map, m.start, m.goal);
    checkTree(planner, map);
    // Every node left could still lie on a shorter path (or is on the best one).
    const double best = planner.bestCost();
    for (std::size_t id = 0; id < planner.nodeCount(); ++id) {
        const Point2 p = planner.nodePoint(id);
        CHECK(rse::geometry::distance(m.start, p) + rse::geometry::distance(p, m.goal) <= best + 1e-9);
    }
}

TEST(RrtStar, KFollowsTheRuleAndNeverPassesTheCap) {
    const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[0];
    const LocalMap& map = benchMap(0);
    CHECK(Status::kOk == planner.start(map, m.start, m.goal, kParams, 11));
    LONGS_EQUAL(1, planner.iterate(1));  // one node in the tree when k is taken
    LONGS_EQUAL(static_cast<long>(std::ceil(RrtStar::kRrt * std::log(2.0))), planner.largestK());
    planner.iterate(3000);
    LONGS_EQUAL(64, planner.largestK());
    CHECK(planner.largestNeighbourSet() <= 65);
    for (std::uint16_t cap : {1, 5, 12}) {
        const RrtStarParams capped{2.0, 0.05, 0.1, cap};
        CHECK(Status::kOk == planner.start(map, m.start, m.goal, capped, 11));
        planner.iterate(2000);
        LONGS_EQUAL(cap, planner.largestK());
        CHECK(planner.largestNeighbourSet() <= cap + 1);
        CHECK(planner.solved());
        checkTree(planner, map);
    }
}

TEST(RrtStar, AGoalNodeNeedsAFreeSegmentToTheGoal) {
    // A wide goal tolerance reaching across a wall: nodes on the far side are
    // within it but must not count; the path has to go round the wall's end.
    CHECK(Status::kOk == walled.reset(Point2{0.0, 0.0}, Point2{20.0, 20.0}, 0.6));
    const Point2 wall[4] = {{10.0, 0.0}, {10.4, 0.0}, {10.4, 16.0}, {10.0, 16.0}};
    CHECK(Status::kOk == walled.addPolygon(wall, 4));
    const Point2 start{2.0, 10.0};
    const Point2 goal{11.5, 10.0};
    const RrtStarParams wide{2.0, 0.05, 3.0, 64};
    for (std::uint64_t seed = 1; seed <= 3; ++seed) {
        CHECK(Status::kOk == planner.start(walled, start, goal, wide, seed));
        planner.iterate(3000);
        const std::size_t n = checkSolution(planner, walled, start, goal);
        CHECK(n >= 3);
        CHECK(planner.bestCost() > 2.0 * 6.0);  // up past y = 16.6 and back down
    }
}

TEST(RrtStar, StartWithinTheGoalToleranceIsSolvedAtOnce) {
    const LocalMap& map = benchMap(0);
    const Point2 start{5.0, 5.0};
    const Point2 goal{5.05, 5.0};
    CHECK(Status::kOk == planner.start(map, start, goal, kParams, 1));
    CHECK(planner.solved());
    LONGS_EQUAL(0, planner.firstSolutionIteration());
    DOUBLES_EQUAL(0.05, planner.bestCost(), 1e-12);
    LONGS_EQUAL(2, planner.bestPath(path, 2));
    CHECK(samePoint(start, path[0]));
    CHECK(samePoint(goal, path[1]));
    LONGS_EQUAL(0, planner.bestPath(path, 1));  // too small a buffer
    LONGS_EQUAL(0, planner.bestPath(nullptr, 10));
    CHECK(Status::kOk == planner.start(map, start, start, kParams, 1));
    LONGS_EQUAL(1, planner.bestPath(path, 2));
    DOUBLES_EQUAL(0.0, planner.bestCost(), 0.0);
}

TEST(RrtStar, NoHeapAllocationPerQuery) {
    for (int mi = 0; mi < rse::test::kBenchMapCount; ++mi) {
        benchMap(mi);  // built before watching
    }
    rse::test::AllocationWatch watch;
    for (int mi = 0; mi < rse::test::kBenchMapCount; ++mi) {
        const rse::test::RrtBenchMap& m = rse::test::kBenchMaps[mi];
        for (std::uint64_t seed = 1; seed <= 3; ++seed) {
            CHECK(Status::kOk == planner.start(maps[mi], m.start, m.goal, kParams, seed));
            planner.iterate(seed == 3 ? 40000 : 3000);  // seed 3 fills and prunes the pool
            const std::size_t n = planner.bestPath(path, kMaxRrtNodes + 1);
            CHECK(n >= 2);
            const std::size_t shortened = rse::habitual::shortcutPath(maps[mi], path, n);
            CHECK(shortened >= 2);
        }
    }
    LONGS_EQUAL(0, watch.count());
}
