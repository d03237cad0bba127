#include "fsw/deliberative/whole_map_check.hpp"

#include <cmath>
#include <initializer_list>

#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/plan_risk.hpp"

namespace rse::deliberative {

static_assert(WholeMapCheck::kMaxUnitWork <= CcPlanner::kMaxUnitWork,
              "a left-out obstacle's check is one unit of the planner's slice");

FarRockBound farRockBound(const CcProblem& problem, std::size_t steps, double radiusM, double share) {
    // Sigma_0's largest eigenvalue, then lambda_t = lambda_0 + t sigma^2.
    const double a = problem.startCov[0];
    const double d = problem.startCov[3];
    const double b = 0.5 * (problem.startCov[1] + problem.startCov[2]);
    const double half = 0.5 * (a - d);
    const double lambda0 = std::fmax(0.0, 0.5 * (a + d) + std::sqrt(half * half + b * b));
    const double q = problem.processSigmaM * problem.processSigmaM;
    const double lambdaN = lambda0 + static_cast<double>(steps) * q;
    FarRockBound out;
    out.reachM = radiusM;
    if (!(lambdaN > 0.0)) {
        return out;   // no uncertainty: a rock beyond the disc is never met
    }
    if (!(share > 0.0) || !std::isfinite(lambdaN)) {
        // No share to give the far rocks: none is far enough, the whole
        // share is claimed (a caller bug, made safe: nothing is certified).
        out.reachM = INFINITY;
        out.risk = 1.0;
        return out;
    }
    // (N + 1) exp(-r^2 / (2 lambda_N)) = share, then the sum itself (<= share).
    const double r = std::sqrt(2.0 * lambdaN * std::log(static_cast<double>(steps + 1) / share));
    double sum = 0.0;
    for (std::size_t t = 0; t <= steps; ++t) {
        const double lambda = lambda0 + static_cast<double>(t) * q;
        sum += lambda > 0.0 ? std::exp(-r * r / (2.0 * lambda)) : 0.0;
    }
    out.reachM = radiusM + r;
    out.risk = sum;
    return out;
}

void WholeMapCheck::start(const CcProblem& problem, const CcPlan& plan, const MapObstacles& obstacles) {
    single_ = problem;
    single_.obstacleCount = 1;
    plan_ = &plan;
    obstacles_ = &obstacles;
    count_ = obstacles.count;
    next_ = 0;
    leftOut_ = 0;
    total_ = 0.0;
    for (double& r : risk_) {
        r = 0.0;
    }
}

bool WholeMapCheck::unit(std::uint64_t* work) {
    if (next_ >= count_) {
        return true;
    }
    single_.obstacles[0] = obstacles_->grown[next_];
    RiskWork w;
    double sum = 0.0;
    const std::size_t steps = plan_->steps <= kMaxPlanSteps ? plan_->steps : kMaxPlanSteps;
    for (std::size_t t = 0; t < steps; ++t) {
        sum += pairRiskBound(single_, plan_->meanX, plan_->meanY, t, 0, &w);
    }
    *work += kTailWork * w.tails + kOrthantWork * w.orthants + kScoreWork * w.lineSolves;
    risk_[next_] = sum;
    if (!obstacles_->inProblem[next_]) {
        total_ += sum;
        ++leftOut_;
    }
    ++next_;
    return done();
}

std::size_t WholeMapCheck::force(MapObstacles* obstacles, double floor) const {
    std::size_t forced = 0;
    for (std::size_t i = 0; i < obstacles->count; ++i) {
        forced += obstacles->forced[i] ? 1U : 0U;
    }
    // The left-out ones first (only they change the problem), then the held
    // ones the plan came near, so they keep their places while room is left.
    std::size_t leftOutAdded = 0;
    for (const bool held : {false, true}) {
        while (forced < kMaxPlanObstacles) {
            std::size_t worst = count_;
            for (std::size_t i = 0; i < count_; ++i) {
                const bool candidate =
                    !obstacles->forced[i] && obstacles->inProblem[i] == held && risk_[i] > floor;
                if (candidate && (worst == count_ || risk_[i] > risk_[worst])) {
                    worst = i;
                }
            }
            if (worst == count_) {
                break;
            }
            obstacles->forced[worst] = true;
            ++forced;
            leftOutAdded += held ? 0U : 1U;
        }
    }
    return leftOutAdded;
}

}  // namespace rse::deliberative
