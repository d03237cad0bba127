// The risk each end gets in the planner's search, and the margin that risk
// asks of each face (cc_planner.hpp; issue 15 item 4, "fixed ends").
//
// The search works at one Boole budget B (Delta' = Delta (1 - kRiskSafety),
// times CcPlannerParams::searchRiskScale for a wide search) shared by the
// 2 N M face ends. kEvenSplit: every end gets B / (2 N M). kOptimised: the
// start (tau 0) and the goal (tau N) are constants, so the risk each of their
// ends needs on its best face is known before any search; an end that needs
// more than the even split gets its need (1 um inside its slack, as the LP's
// rows), and the other ends share the rest evenly (shaved so that rounding in
// any order keeps the sum within B). When the fixed ends' needs alone pass B
// there is no plan within it (Boole): the even split is kept and the search's
// presolve proves it.
//
// margin(tau, i, j): face j of obstacle i tightened for the end at step tau,
// PhiInv(1 - delta) sqrt(a_j' Sigma_tau a_j) (cc_lp.hpp faceMargin), for
// every end of the problem: the table every part of the planner reads.
//
// Memory: 9.6 KiB (the table). No heap.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::deliberative {

// Delta' = Delta (1 - kRiskSafety): the sum of 2 N M deltas added in any
// order in double precision stays within Delta.
constexpr double kRiskSafety = 1e-12;

class CcEndMargins {
public:
    // Splits searchBudget over the ends of a problem that passed
    // checkProblem() and fills the margin table; the work of the fixed ends'
    // risks is added to *work.
    void build(const CcProblem& problem, double searchBudget, std::uint64_t* work);

    // The delta of every end of obstacle `obstacle` at step tau.
    double endDelta(std::size_t tau, std::size_t obstacle) const {
        if (tau == 0) {
            return fixedDelta_[0][obstacle];
        }
        return tau == steps_ ? fixedDelta_[1][obstacle] : evenDelta_;
    }
    double margin(std::size_t tau, std::size_t obstacle, std::size_t face) const {
        return margin_[tau][obstacle][face];
    }
    // Every end's delta but the fixed start's and goal's.
    double evenDelta() const { return evenDelta_; }
    // Start or goal ends given more than the even split (0: the split is even).
    std::uint8_t raised() const { return raised_; }

private:
    void splitFixedEnds(const CcProblem& problem, double searchBudget, std::uint64_t* work);
    void keepEvenSplit();

    std::size_t steps_ = 0;
    double evenDelta_ = 0.0;
    double fixedDelta_[2][kMaxPlanObstacles] = {};  // the start's (0) and the goal's (1) ends, per obstacle
    std::uint8_t raised_ = 0;
    double margin_[kMaxPlanSteps + 1][kMaxPlanObstacles][kMaxObstacleFaces] = {};
};

}  // namespace rse::deliberative
