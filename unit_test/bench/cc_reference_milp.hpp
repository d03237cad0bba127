// Exact reference for the chance-constrained planning problem of
// fsw/deliberative/cc_problem.hpp with a FIXED risk allocation (one delta per
// segment end, e.g. cc::evenSplit): a mixed-integer linear program solved to
// proven optimality with COIN-OR CBC (Debian coinor-libcbc-dev, through its C
// interface Cbc_C_Interface.h). Host only: CBC never links into flight code.
//
// Variables: mu_t = (x_t, y_t) for t = 0 .. N (mu_0 = start and mu_N = goal
// fixed, the others inside the site bounds); s_t >= 0 the 16-gon length of
// step t; binaries z[t][i][j], sum_j z[t][i][j] = 1.
// Segment mode (the problem as defined): for segment t, obstacle i, face j
//   a_j . mu_t     >= b_j + margin(t,     a_j, delta[t][i][0]) - M (1 - z[t][i][j])
//   a_j . mu_{t+1} >= b_j + margin(t + 1, a_j, delta[t][i][1]) - M (1 - z[t][i][j])
// with M per row the least that makes the row void over the site box, or
// over the search region below (a row already void is left out; a face that
// cannot hold at the fixed mu_0 / mu_N has its z fixed to 0).
// Waypoint-only mode (to reproduce the corner cut, not the problem): one face
// per (waypoint w, obstacle i), a_j . mu_w >= b_j + margin(w, a_j, delta_w)
// with delta_w the smallest delta of the segment ends at w; the segment between
// two waypoints is not tied to either face.
// Objective: min sum_t s_t, s_t >= c_k . (mu_{t+1} - mu_t) for k < 16.
//
// Search (all of it exact): first an incumbent: options.startPlan when it is a
// plan, else CBC on this model with the means from ceil(N/2) on pinned to the
// goal (a restriction with fewer free segments: good paths come far sooner;
// its bound is not used), or on the model itself when that finds none, for
// firstPhaseS; then, unless that
// proved it, CBC again with the incumbent as cutoff and every free mean
// confined to the region where a path no longer than the incumbent can pass
// (||mu - start|| + ||goal - mu|| <= cost, 16-gon norm): its bounding box
// bounds the means, big-M is taken over it (far smaller than over the site),
// faces whose half-plane misses it are fixed off, and an obstacle one of whose
// faces holds over all of it needs no binaries. Each better solution restarts
// that with the smaller region (at most 40 times). The best bound reported is
// a bound on the true optimum: every path better than the incumbent is inside
// the region.
// After CBC, the faces it chose are fixed and the LP without binaries is
// re-solved ("polish"), so the plan meets its constraints to LP tolerance and
// not merely to CBC's integrality tolerance times M.
//
// How hard: the LP relaxation of any such disjunctive model lets a segment
// through an obstacle at no cost (its two ends split over two faces), so the
// bound stays at the straight line until every segment's face near each
// blocking obstacle is fixed by branching: the tree grows like
// (faces)^(segments) per obstacle across the line. N = 10 with one obstacle
// across the line proves in seconds; two across the line often not in 10 s.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <string>
#include <utility>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"

namespace rse::test::cc {

enum class ConstraintMode : std::uint8_t {
    kSegment = 0,       // both ends of every segment in one face's half-plane (cc_problem.hpp)
    kWaypointOnly = 1,  // every waypoint outside every obstacle, segments free (corner cut)
};

struct MilpOptions {
    ConstraintMode mode = ConstraintMode::kSegment;
    // The limit counts CPU time (CBC's timeMode cpu, the phases' budget in this
    // thread's CPU time): a loaded machine stretches the wall time, not what
    // CBC gets to do. kWall: wall-clock time (timeMode elapsed), as before
    // issue 15's benchmarks had to hold under load.
    enum class TimeBase : std::uint8_t { kCpu = 0, kWall = 1 };
    TimeBase timeBase = TimeBase::kCpu;
    double timeLimitS = 60.0;        // CBC's limit, in timeBase
    double relativeGap = 1e-6;       // "proven optimal" = within this relative gap
    double absoluteGap = 1e-7;       // ... or this absolute gap (m)
    bool polish = true;              // re-solve the LP with the chosen faces fixed
    // The search described above (false: one plain CBC run on the model).
    bool regionTightening = true;
    // The first incumbent's budget; negative: 20 % of timeLimitS, within [0.5, 10] s.
    double firstPhaseS = -1.0;
    // A plan to start from (e.g. the flight planner's): used as the first
    // incumbent when it meets every constraint of this problem and split
    // exactly (slack >= 0, inside the site, ends at start and goal), else
    // ignored (also without regionTightening). Returned as the answer when
    // CBC finds nothing shorter.
    const CcPlan* startPlan = nullptr;
    // An objective cutoff (m; +inf: none): only plans costing less are
    // sought (CBC's cutoff), e.g. a known plan's cost x (1 + 1e-7) to prove
    // or refute that plan's optimality. With regionTightening the search
    // starts at once in the region where a path shorter than the cutoff can
    // pass (no first phase), and its first run is not stopped at its first
    // solution (each better solution restarts the search only once an
    // incumbent exists). Outcomes: kOptimal (the optimum is below the
    // cutoff and proven), kFeasible (limit reached with a plan below it;
    // bestBound), kNoPlan with noneBelowCutoff (proven: no plan costs less
    // than the cutoff; bestBound = cutoff) or without it (limit reached,
    // nothing found below the cutoff; bestBound = min(cutoff, CBC's bound)).
    // A cutoff is an objective bound, not a MIP start (CBC 2.10.8 crashed
    // after MIP starts); with startPlan too, the smaller of the two counts.
    double cutoff = std::numeric_limits<double>::infinity();
    int logLevel = 0;                // CBC's log level (0 silent)
    std::vector<std::pair<std::string, std::string>> cbcParameters;  // extra "-name value" for CBC
};

struct MilpResult {
    // status kOptimal (proven within the gap), kFeasible (time limit with a
    // plan; bestBound and gap say how far it may be), kNoPlan (proven
    // infeasible, or no plan found within the time limit: see provenInfeasible),
    // kBadProblem (validateProblem failed, or a delta outside (0, 0.5)).
    // plan.face[t][i]: the chosen face (waypoint mode: the face of waypoint t);
    // plan.delta: the split used; riskUsed its sum; cost and euclideanLengthM
    // recomputed from the means.
    CcPlan plan;
    bool provenInfeasible = false;  // the problem has no plan (never set with a finite options.cutoff)
    bool noneBelowCutoff = false;   // options.cutoff finite and proven: no plan costs less than it
    bool startPlanUsed = false;  // options.startPlan was valid and seeded the search
    bool timeLimitReached = false;
    double cost = 0.0;           // = plan.cost (K-gon length), +inf without a plan
    double bestBound = 0.0;      // lower bound on the true optimum (best of the CBC runs')
    double gap = 0.0;            // (cost - bestBound) / cost; +inf without a plan
    double seconds = 0.0;        // wall time: build + CBC + polish
    double cbcSeconds = 0.0;     // wall time in Cbc_solve
    int nodes = 0;               // branch-and-bound nodes, all runs
    int binaries = 0;            // size of the model (the unrestricted one; rows: the last run's)
    int rows = 0;
    int columns = 0;
    double constraintSlack = 0.0;  // segmentConstraintSlack / waypointConstraintSlack of the plan (>= -1e-7 expected)
};

// The MILP with the given deltas (entries for t < N, i < M are used).
MilpResult solveReferenceMilp(const CcProblem& problem, const RiskSplit& split,
                              const MilpOptions& options = MilpOptions{});
// The same with the even split Delta / (2 N M).
MilpResult solveReferenceMilp(const CcProblem& problem, const MilpOptions& options = MilpOptions{});

// The fixed-face LP: the faces are given (face[t][i] for segment t, or for
// waypoint t in waypoint mode, face[N][i] for the goal), no binaries. For
// checking a planner's LP: the optimum of this LP is the best path with those
// faces. status kOptimal or kNoPlan (infeasible faces).
MilpResult solveFixedFaceLp(const CcProblem& problem, const RiskSplit& split,
                            const std::uint8_t face[kMaxPlanSteps + 1][kMaxPlanObstacles],
                            ConstraintMode mode = ConstraintMode::kSegment);

}  // namespace rse::test::cc
