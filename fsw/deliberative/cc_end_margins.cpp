#include "fsw/deliberative/cc_end_margins.hpp"

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_work_units.hpp"
#include "fsw/deliberative/gaussian.hpp"

namespace rse::deliberative {

void CcEndMargins::build(const CcProblem& problem, double searchBudget, std::uint64_t* work) {
    steps_ = problem.steps;
    const std::size_t obstacles = problem.obstacleCount;
    evenDelta_ = obstacles > 0 ? searchBudget / static_cast<double>(2 * steps_ * obstacles) : 0.0;
    raised_ = 0;
    splitFixedEnds(problem, searchBudget, work);
    for (std::size_t i = 0; i < obstacles; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            for (std::size_t tau = 0; tau <= steps_; ++tau) {
                margin_[tau][i][j] = faceMargin(problem, i, j, tau, endDelta(tau, i));
            }
        }
    }
}

void CcEndMargins::keepEvenSplit() {
    for (std::size_t e = 0; e < 2; ++e) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            fixedDelta_[e][i] = evenDelta_;
        }
    }
}

void CcEndMargins::splitFixedEnds(const CcProblem& problem, double searchBudget, std::uint64_t* work) {
    // At the even split a goal 1 m clear of a rock needs more than
    // Delta / (2 N M) there (at N = 20, M = 4, Delta = 1e-3 the goal's margin
    // is 1.00 m), and the presolve "proved" no plan that the optimised
    // allocation would have found (the goal alone needs 6e-6 of the 1e-3).
    // kEvenSplit keeps Delta / (2 N M) everywhere: that is its definition.
    keepEvenSplit();
    const std::size_t obstacles = problem.obstacleCount;
    if (problem.allocation != RiskAllocation::kOptimised || obstacles == 0) {
        return;
    }
    const std::size_t ends = 2 * steps_ * obstacles;
    double fixedSum = 0.0;
    std::size_t raised = 0;
    for (std::size_t e = 0; e < 2; ++e) {
        const std::size_t tau = e == 0 ? 0 : steps_;
        const double x = e == 0 ? problem.startX : problem.goalX;
        const double y = e == 0 ? problem.startY : problem.goalY;
        for (std::size_t i = 0; i < obstacles; ++i) {
            const PlanObstacle& o = problem.obstacles[i];
            double need = 1.0;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double variance = faceVariance(o.normalX[j], o.normalY[j], problem.startCov,
                                                     problem.processSigmaM, static_cast<unsigned>(tau));
                const double r = endRisk(endSlack(o, j, x, y, 0.0) - kSafetyM, variance);
                need = r < need ? r : need;
            }
            *work += kMarginWork * o.faceCount;
            if (need > evenDelta_ && need < 0.5) {
                fixedDelta_[e][i] = need;
                fixedSum += need;
                ++raised;
            }
        }
    }
    if (raised == 0) {
        return;
    }
    // The rest shared by the other ends, shaved so that rounding in any order
    // keeps the sum within searchBudget. Nothing left: keep the even split, and
    // the presolve proves the fixed ends out.
    const double rest = (searchBudget - fixedSum) * (1.0 - kRiskSafety) / static_cast<double>(ends - raised);
    if (!(rest > 0.0) || raised >= ends) {
        keepEvenSplit();
        return;
    }
    for (std::size_t e = 0; e < 2; ++e) {
        for (std::size_t i = 0; i < obstacles; ++i) {
            fixedDelta_[e][i] = fixedDelta_[e][i] > evenDelta_ ? fixedDelta_[e][i] : rest;
        }
    }
    evenDelta_ = rest;
    raised_ = static_cast<std::uint8_t>(raised);
}

}  // namespace rse::deliberative
