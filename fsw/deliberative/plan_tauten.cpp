#include "fsw/deliberative/plan_tauten.hpp"

#include <cmath>
#include <cstddef>

#include "fsw/deliberative/cc_lp.hpp"

namespace rse::deliberative {

namespace {

// The margins of point tau's constraints: as the end of segment tau - 1 and the
// start of segment tau, for every obstacle.
struct PointMargins {
    double end[kMaxPlanObstacles];
    double start[kMaxPlanObstacles];
};

bool feasible(const CcProblem& p, const CcPlan& plan, std::size_t tau, const PointMargins& m, double x, double y) {
    if (!(x >= p.xMin && x <= p.xMax && y >= p.yMin && y <= p.yMax)) {
        return false;
    }
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        if (endSlack(o, plan.face[tau - 1][i], x, y, m.end[i]) < kSafetyM ||
            endSlack(o, plan.face[tau][i], x, y, m.start[i]) < kSafetyM) {
            return false;
        }
    }
    return true;
}

}  // namespace

std::uint32_t tautenPlan(const CcProblem& p, CcPlan* plan) {
    const bool hasPath = plan->status == CcStatus::kOptimal || plan->status == CcStatus::kFeasible;
    const std::size_t n = plan->steps;
    if (!hasPath || n < 2 || n > kMaxPlanSteps || p.obstacleCount > kMaxPlanObstacles) {
        return 0;
    }
    PointMargins margins[kMaxPlanSteps];
    for (std::size_t tau = 1; tau < n; ++tau) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            margins[tau].end[i] = faceMargin(p, i, plan->face[tau - 1][i], tau, plan->delta[tau - 1][i][1]);
            margins[tau].start[i] = faceMargin(p, i, plan->face[tau][i], tau, plan->delta[tau][i][0]);
        }
    }
    std::uint32_t tried = 0;
    // Moves point tau towards (tx, ty) by the largest feasible fraction.
    const auto pull = [&](std::size_t tau, double gx, double gy) {
        const double x = plan->meanX[tau], y = plan->meanY[tau];
        const double dx = gx - x, dy = gy - y;
        if (dx * dx + dy * dy < 1e-18) {
            return false;
        }
        double f = 1.0;
        for (std::uint32_t h = 0; h <= kTautHalvings; ++h, f *= 0.5) {
            ++tried;
            if (feasible(p, *plan, tau, margins[tau], x + f * dx, y + f * dy)) {
                plan->meanX[tau] = x + f * dx;
                plan->meanY[tau] = y + f * dy;
                return dx * dx + dy * dy > 1e-12;
            }
        }
        return false;
    };
    // 1. Every mean together towards the straight line start-goal, each at its
    //    share of the path's length, by the largest common fraction all allow:
    //    each new segment blends an old one and a piece of the line, so by the
    //    triangle inequality the path gets no longer in any norm.
    double along[kMaxPlanSteps + 1] = {};
    double lineX[kMaxPlanSteps + 1] = {};
    double lineY[kMaxPlanSteps + 1] = {};
    for (std::size_t t = 1; t <= n; ++t) {
        along[t] = along[t - 1] + std::hypot(plan->meanX[t] - plan->meanX[t - 1], plan->meanY[t] - plan->meanY[t - 1]);
    }
    if (along[n] > 0.0) {
        for (std::size_t tau = 1; tau < n; ++tau) {
            const double s = along[tau] / along[n];
            lineX[tau] = plan->meanX[0] + s * (plan->meanX[n] - plan->meanX[0]);
            lineY[tau] = plan->meanY[0] + s * (plan->meanY[n] - plan->meanY[0]);
        }
        double f = 1.0;
        for (std::uint32_t h = 0; h <= kTautHalvings; ++h, f *= 0.5) {
            bool all = true;
            for (std::size_t tau = 1; tau < n && all; ++tau) {
                ++tried;
                all = feasible(p, *plan, tau, margins[tau], plan->meanX[tau] + f * (lineX[tau] - plan->meanX[tau]),
                               plan->meanY[tau] + f * (lineY[tau] - plan->meanY[tau]));
            }
            if (all) {
                for (std::size_t tau = 1; tau < n; ++tau) {
                    plan->meanX[tau] += f * (lineX[tau] - plan->meanX[tau]);
                    plan->meanY[tau] += f * (lineY[tau] - plan->meanY[tau]);
                }
                break;
            }
        }
    }
    // 2. Sweeps: each mean towards the closest point of its neighbours' segment.
    for (std::uint32_t sweep = 0; sweep < kTautSweeps; ++sweep) {
        bool moved = false;
        for (std::size_t tau = 1; tau < n; ++tau) {
            const double ax = plan->meanX[tau - 1], ay = plan->meanY[tau - 1];
            const double dx = plan->meanX[tau + 1] - ax, dy = plan->meanY[tau + 1] - ay;
            const double ll = dx * dx + dy * dy;
            double s = ll > 0.0 ? ((plan->meanX[tau] - ax) * dx + (plan->meanY[tau] - ay) * dy) / ll : 0.0;
            s = s < 0.0 ? 0.0 : (s > 1.0 ? 1.0 : s);
            moved = pull(tau, ax + s * dx, ay + s * dy) || moved;
        }
        if (!moved) {
            break;
        }
    }
    double cost = 0.0;
    double length = 0.0;
    for (std::size_t t = 0; t < n; ++t) {
        const double dx = plan->meanX[t + 1] - plan->meanX[t];
        const double dy = plan->meanY[t + 1] - plan->meanY[t];
        cost += polygonLength(dx, dy);
        length += std::sqrt(dx * dx + dy * dy);
    }
    plan->cost = cost;
    plan->euclideanLengthM = length;
    return tried;
}

}  // namespace rse::deliberative
