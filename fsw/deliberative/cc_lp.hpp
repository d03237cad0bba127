// The linear program of a CcProblem (cc_problem.hpp) once faces and deltas are
// chosen: the planner's node relaxation (some pairs assigned), its leaf and
// its risk allocation (every pair assigned).
//
// Variables (n = 3 N - 2): the free means mu_1 .. mu_{N-1} (x and y) and one
// epigraph variable s_t per segment t = 0 .. N-1, in time order (sIndex,
// muIndex); mu_0 and mu_N = goal are constants. minimise sum_t s_t subject to
//   c_k . (mu_{t+1} - mu_t) - s_t <= 0        k = 0 .. 15, t = 0 .. N-1  (16 N rows)
//   site bounds on mu_1 .. mu_{N-1}, shrunk by kBoundSafetyM;  s_t >= 0
//   per assigned pair (t, i) on face j, for each end tau in {t, t + 1}:
//     a_j . mu_tau >= b_j + margin_tau + kSafetyM
// so at the optimum s_t is the 16-gon length of segment t. An end at a constant
// mean (tau = 0 or tau = N) adds no row: it is checked when the pair is added
// (exactly, without kSafetyM), and a pair whose constant end fails is refused.
//
// kSafetyM (1 um) keeps the LP's feasibility tolerance (1e-9) from ever
// showing as a violated chance constraint: a plan read off the LP meets every
// margin exactly, which CcPlanner verifies before it hands a plan out. It
// changes costs by micrometres.
//
// Margins are metres: margin = PhiInv(1 - delta) sqrt(a' Sigma_tau a)
// (gaussian.hpp), from faceMargin() below or the caller's own table.
//
// Pairs form a stack (push with addPair, pop with popPairs): branch and bound
// pushes a pair per level and pops back; LpSolver's basis snapshots take the
// LP back. sizeof(CcLp) = 216 320 B (the LpSolver inside is 211 680 B).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/lp_solver.hpp"

namespace rse::deliberative {

constexpr double kSafetyM = 1e-6;
constexpr double kBoundSafetyM = 1e-8;
constexpr std::size_t kMaxPairs = kMaxPlanSteps * kMaxPlanObstacles;

// Checks a problem: sizes (N 1..24, M 0..8, faces 3..8), finite numbers, unit
// normals (|a| within 1e-9 of 1), Sigma_0 symmetric positive semidefinite,
// sigma >= 0, xMin < xMax and yMin < yMax, start and goal inside the site,
// 0 < Delta < 0.5, a known allocation. kInvalidArgument otherwise.
core::Status checkProblem(const CcProblem& problem);

// The 16-gon length max_k c_k . (dx, dy).
double polygonLength(double dx, double dy);

// margin of face j of obstacle i at step tau for risk delta.
double faceMargin(const CcProblem& problem, std::size_t obstacle, std::size_t face, std::size_t tau, double delta);

// a_j . mu - b_j - margin: >= 0 when the end meets its tightened face.
inline double endSlack(const PlanObstacle& obstacle, std::size_t face, double x, double y, double margin) {
    return obstacle.normalX[face] * x + obstacle.normalY[face] * y - obstacle.offset[face] - margin;
}

class CcLp {
public:
    static constexpr std::uint8_t kEndStart = 1;  // the end at mu_t
    static constexpr std::uint8_t kEndFinish = 2; // the end at mu_{t+1}
    static constexpr std::uint8_t kBothEnds = 3;

    // Builds the base LP (no pairs) of a problem that passed checkProblem()
    // (kInvalidArgument otherwise).
    core::Status setup(const CcProblem& problem);

    // Pushes pair (t, i) on face j with the margins of its ends (metres).
    // kInvalidArgument: indices out of range; kFull: kMaxPairs pushed. Returns
    // kOk with *feasible = false (and nothing pushed) when a constant end
    // misses its margin. ends selects the ends constrained (kBothEnds is the
    // problem's formulation; one end alone is the waypoint-only formulation,
    // which lets segments cut corners, kept for comparison).
    core::Status addPair(std::size_t t, std::size_t obstacle, std::size_t face, double margin0, double margin1,
                         bool* feasible, std::uint8_t ends = kBothEnds);
    // Pops back to `count` pairs (their rows are dropped; restore an LpBasis
    // saved at that depth to warm-start, else the next solve starts cold).
    core::Status popPairs(std::size_t count);
    // New margins for pushed pair k (a right-hand side change: warm start).
    core::Status setPairMargins(std::size_t k, double margin0, double margin1);
    std::size_t pairCount() const { return pairCount_; }

    LpStatus solve(std::uint32_t maxIterations, double cutoff = HUGE_VAL) { return lp_.solve(maxIterations, cutoff); }
    LpSolver& solver() { return lp_; }
    const LpSolver& solver() const { return lp_; }

    // The solution of the last solve (after kOptimal).
    double cost() const;
    double meanX(std::size_t tau) const;  // tau = 0 .. N
    double meanY(std::size_t tau) const;

    // Pushed pair k: its end `e` (0: mu_t, 1: mu_{t+1}) at the solution.
    // slack = a . mu - b - margin (true margin, without kSafetyM); dual = the
    // LP multiplier of its row (0 for a constant end or an unconstrained end);
    // active = the row holds with equality (slack < kSafetyM + 1e-7) or has a
    // positive multiplier.
    double pairSlack(std::size_t k, std::size_t e) const;
    double pairDual(std::size_t k, std::size_t e) const;
    bool pairActive(std::size_t k, std::size_t e) const;

    std::size_t steps() const { return steps_; }
    std::size_t variables() const { return lp_.variableCount(); }
    // Variables in time order, s_0, mu_1 (x, y), s_1, mu_2, ..., s_{N-1}: each
    // row's nonzeros lie within 6 consecutive variables, which keeps the
    // LP's refactorisation banded (lp_solver.hpp).
    std::size_t muIndex(std::size_t tau, std::size_t axis) const { return 3 * tau - 2 + axis; }
    std::size_t sIndex(std::size_t t) const { return 3 * t; }

private:
    static constexpr std::uint16_t kNoRow = 0xFFFFU;
    struct Pair {
        std::uint8_t t;
        std::uint8_t obstacle;
        std::uint8_t face;
        std::uint8_t ends;
        std::uint16_t row[2];  // LP row of each end, kNoRow when constant or not constrained
        double margin[2];
    };

    const CcProblem* problem_ = nullptr;
    std::size_t steps_ = 0;
    std::size_t baseRows_ = 0;
    LpSolver lp_;
    Pair pair_[kMaxPairs];
    std::size_t pairCount_ = 0;
};

// The fixed-face LP in one call: every pair (t, i) on face[t][i] with both
// ends tightened by delta[t][i][0..1]. The result's slack/active tables say
// which chance constraints bind (what risk allocation needs).
struct CcLpSolution {
    LpStatus status = LpStatus::kNotSolved;
    double cost = 0.0;
    double meanX[kMaxPlanSteps + 1] = {};
    double meanY[kMaxPlanSteps + 1] = {};
    double slack[kMaxPlanSteps][kMaxPlanObstacles][2] = {};
    bool active[kMaxPlanSteps][kMaxPlanObstacles][2] = {};
    std::uint32_t iterations = 0;
};

// kInvalidArgument: the problem fails checkProblem() or a face is out of
// range. A constant end that misses its margin gives status kInfeasible.
core::Status solveFixedFaces(const CcProblem& problem, const std::uint8_t face[kMaxPlanSteps][kMaxPlanObstacles],
                             const double delta[kMaxPlanSteps][kMaxPlanObstacles][2], std::uint32_t maxIterations,
                             CcLp* workspace, CcLpSolution* out);

}  // namespace rse::deliberative
