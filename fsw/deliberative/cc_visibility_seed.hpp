// The visibility seed of the planner (cc_planner.hpp, "Seed"): the shortest
// path from start to goal round the obstacles inflated by their margins at
// one step, cut into the plan's N segments.
//
// build(): every face moved out by its margin at step tauInflate plus
// kSeedInflateM (the LP then puts the path at the exact margins); the graph's
// vertices are the start, the goal and the free space's corners: the
// crossings of two lines among the inflated faces and the site's four sides
// that lie on the boundary of each obstacle they come from, inside the site
// and inside no obstacle (two faces of one obstacle: its vertices; faces of
// two obstacles: where overlapping obstacles meet; a face and a side: where an
// obstacle leaves the site). settleOne(): one vertex of Dijkstra from the
// start (16-gon lengths), the costly visibility test (a segment against every
// inflated obstacle, touching allowed up to kSeedTouchM) only for edges that
// would improve a distance. cutPath(): the path's legs get one segment each
// and the rest either one at a time to the leg with the longest segments or,
// "front-loaded", parked at the goal (the path passes the obstacles while the
// margins are small).
//
// Work: build() charges 2 M kMaxObstacleFaces a line pair, a visibility test
// 10 M kMaxObstacleFaces (one unit of the planner each: build, or a vertex).
// Memory: 6.5 KiB. No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_end_margins.hpp"
#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

class CcVisibilitySeed {
public:
    static constexpr std::size_t kMaxVertices = 192;  // start, goal and free-space corners
    // Inflation beyond the margin, and how far a visibility edge may touch an
    // inflated obstacle.
    static constexpr double kSeedInflateM = 1e-4;
    static constexpr double kSeedTouchM = 1e-6;

    // The graph for the obstacles inflated by their margin at step
    // tauInflate; false (no path) when the start or the goal is inside one.
    bool build(const CcProblem& problem, const CcEndMargins& margins, std::size_t tauInflate, std::uint64_t* work);
    // Settles one vertex; true when the goal is settled or none is left.
    bool settleOne(const CcProblem& problem, std::uint64_t* work);
    // After settleOne() returned true: the path cut into the problem's N
    // segments, x[0..N], y[0..N]; false without a path (or with more legs
    // than segments).
    bool cutPath(const CcProblem& problem, bool frontLoaded, double* x, double* y);
    // The path's 16-gon length (INFINITY: none).
    double distance() const { return dist_[1]; }
    std::size_t vertexCount() const { return vertexCount_; }

private:
    // The lines of the inflated faces and the site's sides (obstacle
    // kSiteSide), each {x : nx x + ny y = b}.
    static constexpr std::uint8_t kSiteSide = 0xFF;
    static constexpr std::size_t kMaxLines = kMaxPlanObstacles * kMaxObstacleFaces + 4;
    struct Lines {
        std::size_t count = 0;
        std::uint8_t obstacle[kMaxLines];
        double nx[kMaxLines];
        double ny[kMaxLines];
        double b[kMaxLines];
    };

    bool insideInflated(const CcProblem& problem, std::size_t i, double x, double y, double tol) const;
    bool onBoundaryOf(const CcProblem& problem, std::size_t i, double x, double y) const;
    void collectLines(const CcProblem& problem, Lines* lines) const;
    void addCorners(const CcProblem& problem, const Lines& lines, std::uint64_t* work);
    bool segmentBlocked(const CcProblem& problem, double px, double py, double qx, double qy, std::uint64_t* work);
    bool legs(std::size_t steps, std::size_t* count);

    double inflated_[kMaxPlanObstacles][kMaxObstacleFaces] = {};  // b_j + the margin at tauInflate
    double vx_[kMaxVertices] = {};
    double vy_[kMaxVertices] = {};
    double dist_[kMaxVertices] = {};
    std::uint8_t prev_[kMaxVertices] = {};
    bool settled_[kMaxVertices] = {};
    std::size_t vertexCount_ = 0;
    std::uint8_t legPoint_[kMaxVertices + 1] = {};  // the path's vertices, start first
};

}  // namespace rse::deliberative
