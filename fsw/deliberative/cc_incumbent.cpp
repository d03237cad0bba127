#include "fsw/deliberative/cc_incumbent.hpp"

#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_work_units.hpp"

namespace rse::deliberative {

void CcIncumbent::reset() {
    best_ = CcPlan{};
    best_.status = CcStatus::kNoPlan;
    certified_ = false;
    evenCost_ = INFINITY;
    improvements_ = 0;
    lastNode_ = 0;
}

void CcIncumbent::offerFromLp(const CcProblem& problem, const CcEndMargins& margins, const CcLp& lp,
                              const CcFaceTable& face, double searchScale, std::uint32_t node, CcPlan* scratch,
                              std::uint64_t* work) {
    const std::size_t steps = problem.steps;
    const std::size_t obstacles = problem.obstacleCount;
    CcPlan& c = *scratch;
    c = CcPlan{};
    c.status = CcStatus::kFeasible;
    c.steps = problem.steps;
    for (std::size_t tau = 0; tau <= steps; ++tau) {
        c.meanX[tau] = lp.meanX(tau);
        c.meanY[tau] = lp.meanY(tau);
    }
    for (std::size_t t = 0; t < steps; ++t) {
        for (std::size_t i = 0; i < obstacles; ++i) {
            c.face[t][i] = face[t][i];
            c.delta[t][i][0] = margins.endDelta(t, i);
            c.delta[t][i][1] = margins.endDelta(t + 1, i);
        }
    }
    claimBooleRisk(problem, &c);
    measurePath(steps, &c);
    *work += kMarginWork * 2U * steps * obstacles;
    double deltaSum = 0.0;
    const double searchBound = problem.riskBound * searchScale;
    if (checkPlanShape(problem, c, searchBound, &deltaSum) != core::Status::kOk || !(deltaSum <= searchBound)) {
        return;
    }
    if (c.cost < evenCost_) {
        best_ = c;
        certified_ = deltaSum <= problem.riskBound;  // Boole's certificate
        evenCost_ = c.cost;
        ++improvements_;
        lastNode_ = node;
    }
}

}  // namespace rse::deliberative
