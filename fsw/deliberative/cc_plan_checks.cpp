#include "fsw/deliberative/cc_plan_checks.hpp"

#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/plan_risk.hpp"

namespace rse::deliberative {

core::Status checkPlanShape(const CcProblem& p, const CcPlan& plan, double riskLimit, double* deltaSum) {
    const core::Status bad = core::Status::kInvalidArgument;
    if (checkProblem(p) != core::Status::kOk || plan.steps != p.steps) {
        return bad;
    }
    const std::size_t n = p.steps;
    if (plan.meanX[0] != p.startX || plan.meanY[0] != p.startY || plan.meanX[n] != p.goalX ||
        plan.meanY[n] != p.goalY) {
        return bad;
    }
    for (std::size_t tau = 1; tau < n; ++tau) {
        const double x = plan.meanX[tau];
        const double y = plan.meanY[tau];
        if (!std::isfinite(x) || !std::isfinite(y) || x < p.xMin || x > p.xMax || y < p.yMin || y > p.yMax) {
            return bad;
        }
    }
    double sum = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            const PlanObstacle& o = p.obstacles[i];
            const std::size_t j = plan.face[t][i];
            if (j >= o.faceCount) {
                return bad;
            }
            for (std::size_t e = 0; e < 2; ++e) {
                const double delta = plan.delta[t][i][e];
                if (!(delta > 0.0) || !(delta < 0.5)) {
                    return bad;
                }
                const double margin = faceMargin(p, i, j, t + e, delta);
                if (!std::isfinite(margin) || endSlack(o, j, plan.meanX[t + e], plan.meanY[t + e], margin) < 0.0) {
                    return bad;
                }
                sum += delta;
            }
        }
    }
    if (!std::isfinite(plan.cost) || !(plan.riskUsed <= riskLimit)) {
        return bad;
    }
    *deltaSum = sum;
    return core::Status::kOk;
}

void claimBooleRisk(const CcProblem& p, CcPlan* plan) {
    double total = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        double segment = 0.0;
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            segment += plan->delta[t][i][0] + plan->delta[t][i][1];
        }
        plan->segmentRisk[t] = segment;
        total += segment;
    }
    plan->riskUsed = total;
}

void measurePath(std::size_t steps, CcPlan* plan) {
    double cost = 0.0;
    double euclid = 0.0;
    for (std::size_t t = 0; t < steps; ++t) {
        const double dx = plan->meanX[t + 1] - plan->meanX[t];
        const double dy = plan->meanY[t + 1] - plan->meanY[t];
        cost += polygonLength(dx, dy);
        euclid += std::sqrt(dx * dx + dy * dy);
    }
    plan->cost = cost;
    plan->euclideanLengthM = euclid;
}

core::Status checkPlan(const CcProblem& p, const CcPlan& plan) {
    double deltaSum = 0.0;
    if (checkPlanShape(p, plan, p.riskBound, &deltaSum) != core::Status::kOk) {
        return core::Status::kInvalidArgument;
    }
    if (deltaSum <= p.riskBound && plan.riskUsed >= deltaSum * (1.0 - 1e-12)) {
        return core::Status::kOk;  // Boole's certificate, and the plan claims no less
    }
    RiskWork work;
    const double certified = certifiedPlanRisk(p, plan, nullptr, &work);
    // The plan must not claim less than can be certified.
    const bool claims = plan.riskUsed >= certified * (1.0 - 1e-9);
    return certified <= p.riskBound && claims ? core::Status::kOk : core::Status::kInvalidArgument;
}

}  // namespace rse::deliberative
