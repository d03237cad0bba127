// k-nearest RRT* (Karaman & Frazzoli 2011) on the local map, statically
// allocated: a fixed node pool, a fixed grid for nearest neighbours, every
// scratch buffer a member. Anytime: iterate() may be called in slices (the
// habitual task spreads a query over its 10 Hz frames; a benchmark calls it in
// small chunks between clock reads) and the best solution so far is kept and
// improved by rewiring. No clock is read here: work is bounded by iterations.
//
// One iteration:
//   1. sample: the goal with probability goalBias (and once, right after a node
//      lands within one step of the goal while no node sits on the goal yet);
//      else uniform over the bounds, or, once a solution of cost c exists,
//      uniform over the ellipse {p : |p - start| + |p - goal| < c} clipped to the
//      bounds (informed sampling, Gammell et al. 2014: only those points can
//      shorten the path, so it is still RRT*, only faster to improve);
//   2. steer from the nearest node at most stepM towards the sample; drop the
//      point if the segment is not free, or if a solution exists and
//      |start - p| + |p - goal| >= c (it cannot be on a better path);
//   3. neighbours: the k nearest nodes within stepM, k = min(kCap,
//      ceil(k_rrt ln(n + 1))), k_rrt as OMPL (kRrt below); the nearest node is
//      always a candidate;
//   4. parent: candidates in increasing cost-through order, the first whose
//      segment is free (collision checks delayed, as OMPL's delayCC);
//   5. rewire: a neighbour reached more cheaply through the new node gets it as
//      parent; the cost change is pushed down its subtree by a threaded walk of
//      the child lists (no recursion, no stack: at most 2 x pool steps).
// A node within goalToleranceM of the goal whose straight segment to the goal is
// free is a goal node; a solution is start .. goal node, goal, of cost
// cost(node) + |node - goal|. Costs only ever fall, so the best is kept
// incrementally (each cost change is seen in step 5).
//
// Fixed memory: the pool never grows. When it is full and a solution of cost c
// exists, the nodes that can no longer lie on a shorter path (cost +
// |p - goal| > c; their subtrees go with them) are pruned, the rest compacted
// and renumbered, and the neighbour grid re-cut over the ellipse's box (the
// same pruning and re-gridding also run whenever the ellipse's box halves).
// If pruning would free less than 1/8 of the pool, or there is no solution,
// the query is over: iterate() returns short and poolFull() is true. The grid
// is also re-cut (nothing pruned) as the tree grows past its cell count.
//
// Bounds: per iteration one nearest query, one radius-k query, at most
// kMaxRrtNeighbours + 1 parent checks and as many rewire checks, one subtree
// walk of at most the pool; per rebuild O(pool + grid cells). iterate(N) does N
// iterations unless the pool fills. Measured on the x86-64 development host
// (bench_rrt_star maps): mean 1.0-1.2 us per iteration with k <= 12, 2.4-3.2 us
// with k <= 64; a single iteration up to ~0.4 ms (a rewire near the root walks
// a large subtree), a rebuild of a full pool up to ~0.75 ms. Rebuilds come three
// times while the tree grows, once per halving of the ellipse's box, and at
// most once per kMaxRrtNodes / 8 new nodes once full.
//
// Pure math: no bus, no events. The habitual task reports what it refuses and
// counts; this class counts its own work (largest k, rewires, checks).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/nearest_neighbours.hpp"

namespace rse::habitual {

// Node pool. The habitual table runs 2000 samples per local run by default
// (rrt_iterations, at most one node each); 16384 nodes let a run go 8x longer,
// or take several repair runs, before the pool fills (and a full pool is
// pruned, see above). Memory: 32 B of tree data + 24 B of grid entry + 1 B of
// prune flag per node = 912 KiB, plus 64 KiB of grid cell heads:
// sizeof(RrtStar) = 1 002 000 B on x86-64 and aarch64, so it lives in static
// storage (a task member), never on a stack.
constexpr std::size_t kMaxRrtNodes = 16384;
// Hard cap on k: the scratch buffers per iteration are sized by it, and the
// work per iteration (parent and rewire checks) is proportional. OMPL's
// uncapped k would be 248 at n = 1000 and 348 at a full pool; with a static
// pool the rewiring gains little beyond a few dozen neighbours (the benchmark's
// cap 64 reaches the straight-line optimum on the open map), so 64 bounds the
// worst case at 65 parent + 64 rewire checks per iteration. The table's
// rrt_k_cap (default 12, <= 64) sets the working cap.
constexpr std::uint16_t kMaxRrtNeighbours = 64;

struct RrtStarParams {
    double stepM;           // steer range: a new node is at most this far from its nearest (> 0)
    double goalBias;        // probability a sample is the goal, [0, 1)
    double goalToleranceM;  // a node within this of the goal (and connected to it) solves the query (>= 0)
    std::uint16_t kCap;     // k = min(kCap, ceil(kRrt * ln(n + 1))), 1..kMaxRrtNeighbours
};

class RrtStar {
public:
    // k_rrt as OMPL 1.5's RRTstar computes it for d = 2: rewire factor 1.1 x
    // 2^(d+1) e (1 + 1/d) = 35.88 (the conservative form of Karaman & Frazzoli's
    // bound k_rrt > e (1 + 1/d); the 248 neighbours at n = 1000). With it
    // the cap decides k from n = 6 on, as it does in OMPL's comparison.
    static constexpr double kRrt = 1.1 * 8.0 * 2.718281828459045 * 1.5;

    // Starts a query. kInvalidArgument: params out of range, the map not valid,
    // start or goal not free (no query is then running: iterate() does nothing
    // and there is no solution). The map must outlive the query and not change
    // during it.
    core::Status start(const LocalMap& map, geometry::Point2 start, geometry::Point2 goal, const RrtStarParams& params,
                       std::uint64_t seed);

    // Runs up to maxIterations samples. Returns the iterations done (fewer only
    // when the pool is full or no query is started).
    std::uint32_t iterate(std::uint32_t maxIterations);

    bool started() const { return started_; }
    bool solved() const { return bestNode_ != kNone; }
    double bestCost() const { return bestCost_; }
    // start .. goal into out; 0 if unsolved, out is null or the path needs more than maxPoints.
    std::size_t bestPath(geometry::Point2* out, std::size_t maxPoints) const;
    // Points bestPath() would write (0 if unsolved).
    std::size_t bestPathPointCount() const;

    // The tree, for tests and diagnostics: ids 0..nodeCount() - 1, 0 the start
    // (ids are renumbered when a full pool is pruned). Out-of-range ids give
    // kNoNode / NaN.
    static constexpr std::uint32_t kNoNode = 0xFFFFFFFFU;
    geometry::Point2 nodePoint(std::size_t id) const;
    double nodeCost(std::size_t id) const;
    std::uint32_t nodeParent(std::size_t id) const;  // kNoNode for the start

    std::uint32_t iterations() const { return iterations_; }
    std::size_t nodeCount() const { return grid_.size(); }
    bool poolFull() const { return grid_.size() == kMaxRrtNodes; }

    // Work counters of the current query (start() clears them).
    std::uint32_t firstSolutionIteration() const { return firstSolutionIteration_; }  // iterations() then; see solved()
    std::uint16_t largestK() const { return largestK_; }           // largest k computed (<= kCap)
    std::uint16_t largestNeighbourSet() const { return largestNeighbourSet_; }  // most candidates found (<= kCap + 1)
    std::uint32_t rewires() const { return rewires_; }
    std::uint32_t segmentChecks() const { return segmentChecks_; }
    std::uint32_t samplesRejected() const { return samplesRejected_; }  // informed rejections (step 2)
    std::uint32_t regrids() const { return regrids_; }
    std::uint32_t prunedNodes() const { return prunedNodes_; }

private:
    static constexpr std::uint32_t kNone = kNoNode;
    static constexpr std::size_t kMaxCandidates = kMaxRrtNeighbours + 1U;  // the k nearest + the nearest node

    struct Node {
        double cost;  // path length from the start through the tree
        std::uint32_t parent;
        std::uint32_t firstChild;
        std::uint32_t nextSibling;
        std::uint32_t prevSibling;
        bool goal;  // within the goal tolerance with a free segment to the goal
    };

    // xoshiro256** (Blackman & Vigna) seeded through splitmix64: small, fast,
    // and the same sequence on every target for a seed.
    struct Random {
        std::uint64_t s[4];
        void seed(std::uint64_t seed);
        std::uint64_t next();
        double uniform();  // [0, 1)
    };

    void step();
    bool drawSample(geometry::Point2* sample);
    bool drawInformed(geometry::Point2* sample);
    std::uint16_t kFor(std::size_t n);
    void link(std::uint32_t child, std::uint32_t parent);
    void unlink(std::uint32_t child);
    void rewire(std::uint32_t id, std::uint32_t newParent, double newCost);
    void considerGoal(std::uint32_t id);
    bool rebuild(std::size_t minFreed);
    std::size_t markPromising();
    void compact(std::size_t n);
    bool regridDue();
    void ellipseBox(geometry::Point2* lo, geometry::Point2* hi) const;
    bool segmentFree(geometry::Point2 a, geometry::Point2 b);

    const LocalMap* map_ = nullptr;
    RrtStarParams params_{1.0, 0.0, 0.0, 1};
    geometry::Point2 start_{0.0, 0.0};
    geometry::Point2 goal_{0.0, 0.0};
    bool started_ = false;
    bool goalNext_ = false;      // the next sample is the goal
    bool goalNodeExists_ = false;
    Random random_{};
    // Informed-sampling frame: ellipse centre, unit axis start -> goal, |goal - start|.
    geometry::Point2 centre_{0.0, 0.0};
    geometry::Point2 axis_{1.0, 0.0};
    double focalDistance_ = 0.0;
    double boundsArea_ = 0.0;
    geometry::Point2 boundsLo_{0.0, 0.0};  // the bounds' box in the grid's frame
    geometry::Point2 boundsHi_{0.0, 0.0};

    std::uint32_t bestNode_ = kNone;
    double bestCost_ = INFINITY;
    std::uint32_t iterations_ = 0;
    std::uint32_t firstSolutionIteration_ = 0;
    std::size_t kForN_ = 0;  // kFor() cache
    std::uint16_t kCached_ = 1;
    std::uint16_t largestK_ = 0;
    std::uint16_t largestNeighbourSet_ = 0;
    std::uint32_t rewires_ = 0;
    std::uint32_t segmentChecks_ = 0;
    std::uint32_t samplesRejected_ = 0;
    std::uint32_t regrids_ = 0;
    std::size_t gridCells_ = 0;  // cells last asked of the grid
    std::uint32_t prunedNodes_ = 0;
    double pruneRefusedAtCost_ = INFINITY;  // a prune freed too little at this best cost
    double regridCheckedCost_ = INFINITY;   // regridDue() last looked at this best cost
    double gridBoxArea_ = 0.0;              // of the grid's box when it was last shaped

    // Per-iteration scratch.
    Neighbour candidates_[kMaxCandidates] = {};
    double throughCost_[kMaxCandidates] = {};
    double edge_[kMaxCandidates] = {};
    std::int8_t free_[kMaxCandidates] = {};  // +1 free, -1 blocked, 0 unchecked

    Node nodes_[kMaxRrtNodes] = {};
    std::uint8_t keep_[kMaxRrtNodes] = {};  // prune() scratch
    PointGrid<kMaxRrtNodes> grid_{};
};

}  // namespace rse::habitual
