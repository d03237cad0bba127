#include "fsw/deliberative/cc_planner.hpp"

#include <cmath>

#include "fsw/deliberative/gaussian.hpp"
#include "fsw/deliberative/plan_risk.hpp"
#include "fsw/deliberative/plan_tauten.hpp"

namespace rse::deliberative {

namespace {

constexpr std::uint8_t kUnassigned = 0xFF;
// The seed inflates the obstacles by this much beyond their margin at the
// variant's step (the LP then puts the path at the exact margins), and lets a
// visibility edge touch an inflated obstacle up to kSeedTouchM.
constexpr double kSeedInflateM = 1e-4;
constexpr double kSeedTouchM = 1e-6;
// Risk allocation: a slack end keeps this share of its old delta (the rest
// moves towards its need), and no delta goes below evenDelta * kIraFloor.
constexpr double kIraKeep = 0.3;
constexpr double kIraFloor = 1e-6;
constexpr double kRiskSafety = 1e-12;  // Delta' = Delta (1 - kRiskSafety)
// Work units (LpSolver::work() scale) charged for the planner's own
// arithmetic: one face score, one margin or risk (a quantile or erfc).
constexpr std::uint64_t kScoreWork = 20;
constexpr std::uint64_t kMarginWork = 200;
// The certified risk (plan_risk.hpp): one normal tail (an erfc, ~8 ns on the
// development host) and one bivariate orthant (~145 ns; bench_cc_risk_bounds
// prints both), at ~0.45 ns a unit. A 2x2 solve building a segment's own
// line is charged as a face score.
constexpr std::uint64_t kTailWork = 20;
constexpr std::uint64_t kOrthantWork = 320;
// Stretching the allocation: a round that certifies r <= Delta raises the
// allocation's budget by (Delta / r) x kStretchAim, at most x kMaxStretch a round.
constexpr double kStretchAim = 0.97;
constexpr double kMaxStretch = 8.0;
// The stretch has converged when the certified risk is this close below Delta.
constexpr double kStretchClose = 0.9;
// With optimised allocation the search stops at this share of the work
// budget, leaving the rest to the allocation rounds.
constexpr std::uint64_t kSearchSharePercent = 80;
// The allocation rounds stop at this share; the rest is the finish's (the
// taut path's certified risk: at N = 24, M = 8 about 0.4 M units).
constexpr std::uint64_t kAllocateSharePercent = 97;
// Seed variants: obstacles inflated by the margin at step N * k / 2; the
// segments shared among the legs by length, or one per leg and the rest
// parked at the goal ("front-loaded": the path passes the obstacles early,
// while the margins are small).
constexpr std::size_t kSeedStepsNumerator[] = {2, 1, 0, 0};
constexpr bool kSeedFrontLoaded[] = {false, false, false, true};

double euclidean(double dx, double dy) { return std::sqrt(dx * dx + dy * dy); }

}  // namespace

namespace {

// Everything checkPlan checks but the risk bound; *deltaSum gets the sum of
// the deltas (Boole's certificate).
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

// The plan claims its deltas' sum (Boole's certificate): riskUsed and each
// segment's share.
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

}  // namespace

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

core::Status CcPlanner::start(const CcProblem& problem, const CcPlannerParams& params) {
    best_ = CcPlan{};
    best_.status = CcStatus::kNoPlan;
    phase_ = Phase::kDone;
    nodes_ = 0;
    seedSolves_ = 0;
    incumbents_ = 0;
    tautenRefused_ = 0;
    lastIncumbentNode_ = 0;
    maxDepth_ = 0;
    depth_ = 0;
    exhausted_ = false;
    incomplete_ = false;
    unresolvedBound_ = INFINITY;
    evenCost_ = INFINITY;
    seedCost_ = INFINITY;
    seedFound_ = false;
    hintPending_ = false;
    hintSeedCost_ = INFINITY;
    iraDone_ = 0;
    iraLastRound_ = false;
    iraReady_ = false;
    evalRunning_ = false;
    tautenDone_ = false;
    const bool paramsOk = params.nodeBudget > 0 && params.iterationBudget > 0 && params.perLpIterations > 0 &&
                          params.relativeGap >= 0.0 && params.relativeGap < 0.5 && params.iraRounds <= 50 &&
                          params.searchRiskScale >= 1.0 && params.searchRiskScale <= kMaxSearchRiskScale;
    if (!paramsOk || checkProblem(problem) != core::Status::kOk) {
        best_.status = CcStatus::kBadProblem;
        return core::Status::kInvalidArgument;
    }
    problem_ = problem;
    params_ = params;
    steps_ = problem_.steps;
    obstacles_ = problem_.obstacleCount;
    best_.steps = problem_.steps;
    riskBudget_ = problem_.riskBound * (1.0 - kRiskSafety);
    searchBudget_ = riskBudget_ * searchScale();
    bestCertified_ = false;
    noPlan_ = CcPlan{};
    noPlan_.steps = problem_.steps;
    evenDelta_ = obstacles_ > 0 ? searchBudget_ / static_cast<double>(2 * steps_ * obstacles_) : 0.0;
    geometryWork_ = 0;
    fixedEndsRaised_ = 0;
    splitFixedEnds();
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = problem_.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            for (std::size_t tau = 0; tau <= steps_; ++tau) {
                margin_[tau][i][j] = faceMargin(problem_, i, j, tau, endDelta(tau, i));
            }
        }
    }
    for (std::size_t t = 0; t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            assigned_[t][i] = kUnassigned;
        }
    }
    if (lp_.setup(problem_) != core::Status::kOk) {
        best_.status = CcStatus::kBadProblem;
        return core::Status::kInvalidArgument;
    }
    factorSize_ = LpSolver::factorDoubles(lp_.variables());
    factorSlots_ = kFactorPoolDoubles / factorSize_;
    factorSlots_ = factorSlots_ < kMaxFactorSlots ? factorSlots_ : kMaxFactorSlots;
    for (std::size_t k = 0; k < kMaxFactorSlots; ++k) {
        slotOwner_[k] = kMaxPairs;
    }
    factorRestores_ = 0;
    seedVariant_ = 0;
    seedStage_ = SeedStage::kIdle;
    lpRunning_ = false;
    layerTau_ = 0;
    layerFull_ = 0;
    guideValid_ = false;
    guideDistance_ = HUGE_VAL;
    phase_ = (params_.seed && obstacles_ > 0) ? Phase::kSeed : Phase::kRoot;
    return core::Status::kOk;
}

// ---------------------------------------------------------------------------
// Fixed ends (issue 15 item 4).

void CcPlanner::splitFixedEnds() {
    // The start (tau 0) and the goal (tau N) are constants: the risk each of
    // their ends needs on its best face is known before any search. At the even
    // split a goal 1 m clear of a rock needs more than Delta / (2 N M) there
    // (at N = 20, M = 4, Delta = 1e-3 the goal's margin is 1.00 m), and the
    // presolve "proved" no plan that the optimised allocation would have found
    // (the goal alone needs 6e-6 of the 1e-3). With kOptimised such an end is
    // given what it needs (1 um inside its slack, as the LP's rows) and the
    // other ends share the rest evenly; when the fixed ends' needs alone pass
    // Delta there is no plan within Delta (Boole), and the presolve finds it.
    // kEvenSplit keeps Delta / (2 N M) everywhere: that is its definition.
    for (std::size_t e = 0; e < 2; ++e) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            fixedDelta_[e][i] = evenDelta_;
        }
    }
    if (problem_.allocation != RiskAllocation::kOptimised || obstacles_ == 0) {
        return;
    }
    const std::size_t ends = 2 * steps_ * obstacles_;
    double fixedSum = 0.0;
    std::size_t raised = 0;
    for (std::size_t e = 0; e < 2; ++e) {
        const std::size_t tau = e == 0 ? 0 : steps_;
        const double x = e == 0 ? problem_.startX : problem_.goalX;
        const double y = e == 0 ? problem_.startY : problem_.goalY;
        for (std::size_t i = 0; i < obstacles_; ++i) {
            const PlanObstacle& o = problem_.obstacles[i];
            double need = 1.0;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double variance = faceVariance(o.normalX[j], o.normalY[j], problem_.startCov,
                                                     problem_.processSigmaM, static_cast<unsigned>(tau));
                const double r = endRisk(endSlack(o, j, x, y, 0.0) - kSafetyM, variance);
                need = r < need ? r : need;
            }
            geometryWork_ += kMarginWork * o.faceCount;
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
    // keeps the sum within searchBudget_. Nothing left: keep the even split, and
    // the presolve proves the fixed ends out.
    const double rest = (searchBudget_ - fixedSum) * (1.0 - kRiskSafety) / static_cast<double>(ends - raised);
    if (!(rest > 0.0) || raised >= ends) {
        for (std::size_t e = 0; e < 2; ++e) {
            for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
                fixedDelta_[e][i] = evenDelta_;
            }
        }
        return;
    }
    for (std::size_t e = 0; e < 2; ++e) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            fixedDelta_[e][i] = fixedDelta_[e][i] > evenDelta_ ? fixedDelta_[e][i] : rest;
        }
    }
    evenDelta_ = rest;
    fixedEndsRaised_ = static_cast<std::uint8_t>(raised);
}

double CcPlanner::endDelta(std::size_t tau, std::size_t i) const {
    if (tau == 0) {
        return fixedDelta_[0][i];
    }
    return tau == steps_ ? fixedDelta_[1][i] : evenDelta_;
}

core::Status CcPlanner::setSeedHint(const CcPlan& hint) {
    // Only before the first step, and only faces that exist in this problem.
    bool fits = phase_ == Phase::kSeed && seedVariant_ == 0 && seedSolves_ == 0 && hint.steps == steps_;
    for (std::size_t t = 0; t < steps_ && fits; ++t) {
        for (std::size_t i = 0; i < obstacles_ && fits; ++i) {
            fits = hint.face[t][i] < problem_.obstacles[i].faceCount;
        }
    }
    if (!fits) {
        return core::Status::kInvalidArgument;
    }
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            hintFace_[t][i] = hint.face[t][i];
        }
    }
    hintPending_ = true;
    return core::Status::kOk;
}

CcStatus CcPlanner::solve(const CcProblem& problem, const CcPlannerParams& params, CcPlan* out) {
    (void)start(problem, params);
    // Each call does at least one unit until the phases run out: bounded by
    // the node budget, the seed's and the allocation's solves.
    const std::uint64_t guard = static_cast<std::uint64_t>(params.nodeBudget) + 4U * kMaxPairs + 64U;
    for (std::uint64_t k = 0; k < guard && !finished(); ++k) {
        (void)step(1000);
    }
    if (!finished()) {
        finish();
    }
    if (out != nullptr) {
        *out = best_;
    }
    return best_.status;
}

bool CcPlanner::step(std::uint32_t maxNodes) {
    std::uint32_t units = 0;
    // Each pass does one unit or moves to a later phase (at most 5 moves).
    const std::uint64_t guard = static_cast<std::uint64_t>(maxNodes) + 8U;
    for (std::uint64_t pass = 0; pass < guard && units < maxNodes && phase_ != Phase::kDone; ++pass) {
        switch (phase_) {
            case Phase::kSeed:
                // Out of budget: whatever seed is under way is dropped.
                if (hintPending_ && budgetLeft()) {
                    runHintSeed();
                } else if (budgetLeft()) {
                    runSeed();
                } else {
                    lpRunning_ = false;
                    phase_ = Phase::kRoot;
                }
                ++units;
                break;
            case Phase::kRoot:
                // The presolve always runs (it can prove there is no plan at
                // no LP cost); the root's LP only within the budget.
                if (!lpRunning_ || budgetLeft()) {
                    rootStep();
                } else {
                    abandonNode();
                    phase_ = Phase::kAllocate;
                }
                ++units;
                break;
            case Phase::kSearch:
                if (nodes_ >= params_.nodeBudget || !budgetLeft()) {
                    if (lpRunning_) {
                        abandonNode();
                    }
                    incomplete_ = true;
                    phase_ = Phase::kAllocate;
                } else if (searchStep()) {
                    ++units;
                } else {
                    exhausted_ = !incomplete_;
                    phase_ = Phase::kAllocate;
                }
                break;
            case Phase::kAllocate:
                allocateStep();
                ++units;
                break;
            case Phase::kFinish:
                finishStep();
                ++units;
                break;
            case Phase::kIdle:
            case Phase::kDone:
                phase_ = Phase::kDone;
                break;
        }
    }
    if (phase_ != Phase::kDone && best_.status == CcStatus::kOptimal) {
        best_.status = CcStatus::kFeasible;
    }
    return finished();
}

bool CcPlanner::budgetLeft() const {
    if (lpIterations() >= params_.iterationBudget) {
        return false;
    }
    const std::uint64_t share = problem_.allocation == RiskAllocation::kOptimised ? kSearchSharePercent : 100U;
    return params_.workBudget == 0 || work() < 10ULL * share * params_.workBudget;
}

std::uint32_t CcPlanner::lpCap() const {
    const std::uint32_t used = lpIterations();
    const std::uint32_t left = used < params_.iterationBudget ? params_.iterationBudget - used : 0U;
    return left < params_.perLpIterations ? left : params_.perLpIterations;
}

double CcPlanner::pruneThreshold() const {
    if (!std::isfinite(evenCost_)) {
        return INFINITY;
    }
    return evenCost_ * (1.0 - params_.relativeGap) - 1e-9;
}

double CcPlanner::lowerBound() const {
    double lb = std::isfinite(evenCost_) ? evenCost_ * (1.0 - params_.relativeGap) : HUGE_VAL;
    if (exhausted_) {
        return lb;
    }
    for (std::size_t d = 0; d < depth_; ++d) {
        if (level_[d].next < level_[d].count && level_[d].bound < lb) {
            lb = level_[d].bound;
        }
    }
    return unresolvedBound_ < lb ? unresolvedBound_ : lb;
}

// min over the pair's two ends of its slack on face j; an end the LP holds
// (not the fixed start or goal) is scored against the LP's row, i.e. less
// kSafetyM and with the LP's tolerance, so that a score >= 0 means the end
// meets its margin exactly.
double CcPlanner::pairScore(std::size_t t, std::size_t i, std::size_t j, const double* mx, const double* my) const {
    const PlanObstacle& o = problem_.obstacles[i];
    double worst = INFINITY;
    for (std::size_t e = 0; e < 2; ++e) {
        const std::size_t tau = t + e;
        double s = endSlack(o, j, mx[tau], my[tau], margin_[tau][i][j]);
        if (tau != 0 && tau != steps_) {
            s -= kSafetyM - 2.0 * LpSolver::kPrimalTol;
        }
        worst = s < worst ? s : worst;
    }
    return worst;
}

void CcPlanner::chooseFacesAt(const double* mx, const double* my,
                              std::uint8_t (&face)[kMaxPlanSteps][kMaxPlanObstacles]) const {
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            double best = -INFINITY;
            std::uint8_t bestFace = 0;
            for (std::size_t j = 0; j < problem_.obstacles[i].faceCount; ++j) {
                const double s = pairScore(t, i, j, mx, my);
                if (s > best) {
                    best = s;
                    bestFace = static_cast<std::uint8_t>(j);
                }
            }
            face[t][i] = bestFace;
        }
    }
}

// The plan at the LP's optimum with these faces, even split; kept when it
// verifies and beats the best.
void CcPlanner::offerIncumbentFromLp(const std::uint8_t (&face)[kMaxPlanSteps][kMaxPlanObstacles]) {
    CcPlan& c = candidate_;
    c = CcPlan{};
    c.status = CcStatus::kFeasible;
    c.steps = problem_.steps;
    for (std::size_t tau = 0; tau <= steps_; ++tau) {
        c.meanX[tau] = lp_.meanX(tau);
        c.meanY[tau] = lp_.meanY(tau);
    }
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            c.face[t][i] = face[t][i];
            c.delta[t][i][0] = endDelta(t, i);
            c.delta[t][i][1] = endDelta(t + 1, i);
        }
    }
    claimBooleRisk(problem_, &c);
    double cost = 0.0;
    double euclid = 0.0;
    for (std::size_t t = 0; t < steps_; ++t) {
        const double dx = c.meanX[t + 1] - c.meanX[t];
        const double dy = c.meanY[t + 1] - c.meanY[t];
        cost += polygonLength(dx, dy);
        euclid += euclidean(dx, dy);
    }
    c.cost = cost;
    c.euclideanLengthM = euclid;
    geometryWork_ += kMarginWork * 2U * steps_ * obstacles_;
    double deltaSum = 0.0;
    const double searchBound = problem_.riskBound * searchScale();
    if (checkPlanShape(problem_, c, searchBound, &deltaSum) != core::Status::kOk || !(deltaSum <= searchBound)) {
        return;
    }
    if (cost < evenCost_) {
        best_ = c;
        bestCertified_ = deltaSum <= problem_.riskBound;  // Boole's certificate
        evenCost_ = cost;
        ++incumbents_;
        lastIncumbentNode_ = nodes_;
    }
}

// ---------------------------------------------------------------------------
// Seed.

bool CcPlanner::segmentBlocked(double px, double py, double qx, double qy) {
    geometryWork_ += 10U * kMaxObstacleFaces * obstacles_;
    const double dx = qx - px;
    const double dy = qy - py;
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = problem_.obstacles[i];
        double lo = 0.0;
        double hi = 1.0;
        bool outside = false;
        for (std::size_t j = 0; j < o.faceCount && !outside; ++j) {
            // Inside the (touch-shrunk) inflated obstacle: f0 + s fd < 0.
            const double f0 = o.normalX[j] * px + o.normalY[j] * py - (inflated_[i][j] - kSeedTouchM);
            const double fd = o.normalX[j] * dx + o.normalY[j] * dy;
            if (std::fabs(fd) < 1e-15) {
                outside = f0 >= 0.0;
            } else if (fd > 0.0) {
                const double s = -f0 / fd;
                hi = s < hi ? s : hi;
            } else {
                const double s = -f0 / fd;
                lo = s > lo ? s : lo;
            }
            outside = outside || !(lo < hi);
        }
        if (!outside && lo < hi) {
            return true;
        }
    }
    return false;
}

bool CcPlanner::seedVertices() {
    const CcProblem& p = problem_;
    auto insideInflated = [&](std::size_t i, double x, double y, double tol) {
        const PlanObstacle& o = p.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            if (o.normalX[j] * x + o.normalY[j] * y >= inflated_[i][j] - tol) {
                return false;
            }
        }
        return true;
    };
    for (std::size_t i = 0; i < obstacles_; ++i) {
        if (insideInflated(i, p.startX, p.startY, kSeedTouchM) || insideInflated(i, p.goalX, p.goalY, kSeedTouchM)) {
            return false;
        }
    }
    vx_[0] = p.startX;
    vy_[0] = p.startY;
    vx_[1] = p.goalX;
    vy_[1] = p.goalY;
    vertexCount_ = 2;
    // The free space's corners, where a shortest path can bend: the
    // intersections of two lines among the inflated faces and the site's four
    // sides that lie on the boundary of each obstacle they come from, inside
    // the site and inside no obstacle. Two faces of one obstacle: its
    // vertices; faces of two obstacles: where overlapping obstacles meet; a
    // face and a side: where an obstacle leaves the site.
    const std::size_t sides = 4;
    std::size_t lineCount = 0;
    std::uint8_t lineObstacle[kMaxPlanObstacles * kMaxObstacleFaces + 4];
    double lineX[kMaxPlanObstacles * kMaxObstacleFaces + 4];
    double lineY[kMaxPlanObstacles * kMaxObstacleFaces + 4];
    double lineB[kMaxPlanObstacles * kMaxObstacleFaces + 4];
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            lineObstacle[lineCount] = static_cast<std::uint8_t>(i);
            lineX[lineCount] = o.normalX[j];
            lineY[lineCount] = o.normalY[j];
            lineB[lineCount] = inflated_[i][j];
            ++lineCount;
        }
    }
    const double sideX[sides] = {1.0, 1.0, 0.0, 0.0};
    const double sideY[sides] = {0.0, 0.0, 1.0, 1.0};
    const double sideB[sides] = {p.xMin, p.xMax, p.yMin, p.yMax};
    for (std::size_t k = 0; k < sides; ++k) {
        lineObstacle[lineCount] = kUnassigned;
        lineX[lineCount] = sideX[k];
        lineY[lineCount] = sideY[k];
        lineB[lineCount] = sideB[k];
        ++lineCount;
    }
    auto onBoundaryOf = [&](std::size_t i, double x, double y) {
        const PlanObstacle& o = p.obstacles[i];
        for (std::size_t l = 0; l < o.faceCount; ++l) {
            if (o.normalX[l] * x + o.normalY[l] * y > inflated_[i][l] + 1e-7) {
                return false;
            }
        }
        return true;
    };
    for (std::size_t a = 0; a < lineCount; ++a) {
        for (std::size_t b = a + 1; b < lineCount; ++b) {
            if (lineObstacle[a] == kUnassigned && lineObstacle[b] == kUnassigned) {
                continue;  // a corner of the site: never a bend of a shortest path
            }
            geometryWork_ += 2U * kMaxObstacleFaces * obstacles_;
            const double det = lineX[a] * lineY[b] - lineY[a] * lineX[b];
            if (std::fabs(det) < 1e-9) {
                continue;
            }
            const double x = (lineB[a] * lineY[b] - lineY[a] * lineB[b]) / det;
            const double y = (lineX[a] * lineB[b] - lineB[a] * lineX[b]) / det;
            if (!(x >= p.xMin && x <= p.xMax && y >= p.yMin && y <= p.yMax)) {
                continue;
            }
            bool valid = (lineObstacle[a] == kUnassigned || onBoundaryOf(lineObstacle[a], x, y)) &&
                         (lineObstacle[b] == kUnassigned || onBoundaryOf(lineObstacle[b], x, y));
            for (std::size_t i = 0; i < obstacles_ && valid; ++i) {
                valid = !insideInflated(i, x, y, kSeedTouchM);
            }
            for (std::size_t v = 2; v < vertexCount_ && valid; ++v) {
                valid = std::fabs(vx_[v] - x) + std::fabs(vy_[v] - y) > 1e-9;
            }
            if (valid && vertexCount_ < kMaxSeedVertices) {
                vx_[vertexCount_] = x;
                vy_[vertexCount_] = y;
                ++vertexCount_;
            }
        }
    }
    // Dijkstra from the start (dijkstraStep, one vertex per unit); the
    // (costly) visibility test only for edges that would improve a distance.
    for (std::size_t v = 0; v < vertexCount_; ++v) {
        dist_[v] = INFINITY;
        settled_[v] = false;
        prev_[v] = 0;
    }
    dist_[0] = 0.0;
    return true;
}

// Settles one vertex; true when the goal is settled or none is left.
bool CcPlanner::dijkstraStep() {
    std::size_t u = vertexCount_;
    double du = INFINITY;
    for (std::size_t v = 0; v < vertexCount_; ++v) {
        if (!settled_[v] && dist_[v] < du) {
            du = dist_[v];
            u = v;
        }
    }
    if (u == vertexCount_ || u == 1) {
        return true;
    }
    settled_[u] = true;
    for (std::size_t v = 0; v < vertexCount_; ++v) {
        if (settled_[v]) {
            continue;
        }
        const double d = du + polygonLength(vx_[v] - vx_[u], vy_[v] - vy_[u]);
        if (d < dist_[v] && !segmentBlocked(vx_[u], vy_[u], vx_[v], vy_[v])) {
            dist_[v] = d;
            prev_[v] = static_cast<std::uint8_t>(u);
        }
    }
    return false;
}

// The shortest path's legs into legPoint_ (start first); false without one.
bool CcPlanner::seedLegs(std::size_t* legs) {
    if (!std::isfinite(dist_[1])) {
        return false;
    }
    // The path, goal back to start, then reversed into legPoint_.
    std::size_t count = 0;
    std::size_t v = 1;
    for (std::size_t guard = 0; guard <= vertexCount_; ++guard) {
        legPoint_[count++] = static_cast<std::uint8_t>(v);
        if (v == 0) {
            break;
        }
        v = prev_[v];
    }
    if (legPoint_[count - 1] != 0) {
        return false;
    }
    for (std::size_t a = 0, b = count - 1; a < b; ++a, --b) {
        const std::uint8_t tmp = legPoint_[a];
        legPoint_[a] = legPoint_[b];
        legPoint_[b] = tmp;
    }
    *legs = count - 1;
    return *legs >= 1 && *legs <= steps_;
}

void CcPlanner::runSeed() {
    // One unit: a slice of the current seed (its LP, a Dijkstra round, a
    // slice of a layer), else the start of the next one.
    if (lpRunning_) {
        seedLpUnit();
        return;
    }
    hintRunning_ = false;  // the hint's LP and polish, if any, are over
    if (seedStage_ == SeedStage::kDijkstra) {
        if (dijkstraStep()) {
            seedStage_ = SeedStage::kIdle;
            cutSeedPath();
        }
        return;
    }
    if (seedStage_ == SeedStage::kLayered) {
        if (layeredSeedStep()) {
            seedStage_ = SeedStage::kIdle;
        }
        return;
    }
    if (seedVariant_ > kSeedVariants) {
        phase_ = Phase::kRoot;
        return;
    }
    // Order: the visibility variants from the most conservative inflation;
    // the layered search (complete, dearer) once they have failed; then the
    // remaining variants, which may shorten its plan.
    const std::size_t slot = seedVariant_++;
    if (slot == kLayeredSeedSlot) {
        if (!seedFound_ && params_.layeredSeed) {
            layerTau_ = 0;
            seedStage_ = SeedStage::kLayered;
        }
        return;
    }
    seedCurrent_ = slot < kLayeredSeedSlot ? slot : slot - 1;
    // Variant v inflates every face by its margin at step kSeedSteps[v] of N
    // (margins grow with the step: N is the conservative inflation, 0 the
    // optimistic one that keeps gaps open for the early steps).
    const std::size_t tauInflate = steps_ * kSeedStepsNumerator[seedCurrent_] / 2U;
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = problem_.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            inflated_[i][j] = o.offset[j] + margin_[tauInflate][i][j] + kSeedInflateM;
        }
    }
    if (seedVertices()) {
        seedStage_ = SeedStage::kDijkstra;
    }
}

// The visibility path cut into N segments (variant seedCurrent_), then seeded.
void CcPlanner::cutSeedPath() {
    std::size_t legs = 0;
    if (!seedLegs(&legs)) {
        return;
    }
    // Segments per leg: one each, the rest one at a time to the leg with the
    // longest segments.
    std::size_t share[kMaxPlanSteps];  // legs <= steps (seedPath)
    double length[kMaxPlanSteps];
    for (std::size_t l = 0; l < legs; ++l) {
        share[l] = 1;
        length[l] = euclidean(vx_[legPoint_[l + 1]] - vx_[legPoint_[l]], vy_[legPoint_[l + 1]] - vy_[legPoint_[l]]);
    }
    for (std::size_t extra = legs; extra < steps_ && !kSeedFrontLoaded[seedCurrent_]; ++extra) {
        std::size_t best = 0;
        for (std::size_t l = 1; l < legs; ++l) {
            if (length[l] / static_cast<double>(share[l]) > length[best] / static_cast<double>(share[best])) {
                best = l;
            }
        }
        ++share[best];
    }
    std::size_t tau = 0;
    for (std::size_t l = 0; l < legs; ++l) {
        const double ax = vx_[legPoint_[l]];
        const double ay = vy_[legPoint_[l]];
        const double bx = vx_[legPoint_[l + 1]];
        const double by = vy_[legPoint_[l + 1]];
        for (std::size_t k = 0; k < share[l]; ++k, ++tau) {
            const double f = static_cast<double>(k) / static_cast<double>(share[l]);
            scratchX_[tau] = ax + f * (bx - ax);
            scratchY_[tau] = ay + f * (by - ay);
        }
    }
    for (; tau <= steps_; ++tau) {
        scratchX_[tau] = problem_.goalX;
        scratchY_[tau] = problem_.goalY;
    }
    seedFromPath(dist_[1]);
}

// The faces the path in scratchX_ / scratchY_ clears best, the fixed-face LP
// and the polish rounds; `distance` is the path's length for the guide.
void CcPlanner::seedFromPath(double distance) {
    chooseFacesAt(scratchX_, scratchY_, faceScratch_);
    if (distance < guideDistance_) {
        // The search tries these faces first (see evaluateNode): the shortest
        // visibility path's, even when its own LP turns out infeasible (the
        // margins grow along the path; the search's dives then find the
        // waypoints that fit, near that path).
        for (std::size_t t = 0; t < steps_; ++t) {
            for (std::size_t i = 0; i < obstacles_; ++i) {
                guideFace_[t][i] = faceScratch_[t][i];
            }
        }
        guideDistance_ = distance;
        guideValid_ = true;
    }
    // The fixed-face LP, then polish rounds (each one LP), in units.
    seedRound_ = 0;
    seedStartLp();
}

void CcPlanner::runHintSeed() {
    // An earlier plan's faces (setSeedHint), e.g. the plan at a looser bound:
    // re-solved at this problem's margins they give at once a plan close to
    // that one's route when it still fits, where the visibility seeds and a
    // search cut short by the budget may only find a longer one (issue 15
    // item 5: a 1e-9 plan 1 m longer than the 1e-8 one). Its LP and polish
    // run in units like any seed's (runSeed); seedLpUnit records its cost.
    hintPending_ = false;
    hintRunning_ = true;
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            faceScratch_[t][i] = hintFace_[t][i];
        }
    }
    seedRound_ = 0;
    seedStartLp();
    if (!lpRunning_) {
        hintRunning_ = false;  // the hint's faces do not fit this problem's margins
    }
}

// The fixed-face LP of faceScratch_, started (its pivots run in units).
void CcPlanner::seedStartLp() {
    (void)lp_.popPairs(0);
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            const std::size_t j = faceScratch_[t][i];
            bool feasible = false;
            if (lp_.addPair(t, i, j, margin_[t][i][j], margin_[t + 1][i][j], &feasible) != core::Status::kOk ||
                !feasible) {
                return;
            }
        }
    }
    ++seedSolves_;
    beginLp(HUGE_VAL, lpCap());
}

// One unit of the seed's LP; at its optimum the plan is offered, then
// "polish": each pair moves to the face its ends clear best (the path stays
// feasible, so the cost cannot rise) and, if any moved, the LP again.
void CcPlanner::seedLpUnit() {
    LpStatus st = LpStatus::kNotSolved;
    if (!continueLp(&st) || st != LpStatus::kOptimal) {
        return;
    }
    offerIncumbentFromLp(faceScratch_);
    if (std::isfinite(evenCost_)) {
        seedFound_ = true;
        seedCost_ = evenCost_;
        if (hintRunning_) {
            hintSeedCost_ = evenCost_;
        }
    }
    if (seedRound_ >= kPolishRounds) {
        return;
    }
    ++seedRound_;
    for (std::size_t k = 0; k <= steps_; ++k) {
        scratchX_[k] = lp_.meanX(k);
        scratchY_[k] = lp_.meanY(k);
    }
    bool changed = false;
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            const std::uint8_t old = faceScratch_[t][i];
            double best = pairScore(t, i, old, scratchX_, scratchY_);
            for (std::size_t j = 0; j < problem_.obstacles[i].faceCount; ++j) {
                const double sc = pairScore(t, i, j, scratchX_, scratchY_);
                if (sc > best + 1e-9) {
                    best = sc;
                    faceScratch_[t][i] = static_cast<std::uint8_t>(j);
                }
            }
            changed = changed || faceScratch_[t][i] != old;
        }
    }
    geometryWork_ += kScoreWork * steps_ * obstacles_ * kMaxObstacleFaces;
    if (changed) {
        seedStartLp();
    }
}

// The pending LP (lpRunning_): started here, run by continueLp.
void CcPlanner::beginLp(double cutoff, std::uint32_t limit) {
    lpRunning_ = true;
    lpPivots_ = 0;
    lpLimit_ = limit;
    lpCutoff_ = cutoff;
}

// At most kPivotsPerUnit pivots of the pending LP; false while it runs on
// (its basis is kept: the next call continues it), true when it has ended
// (*status: its outcome; kIterationLimit when its pivot cap ran out).
bool CcPlanner::continueLp(LpStatus* status) {
    const std::uint32_t left = lpLimit_ > lpPivots_ ? lpLimit_ - lpPivots_ : 0U;
    *status = lp_.solve(left < kPivotsPerUnit ? left : kPivotsPerUnit, lpCutoff_);
    lpPivots_ += lp_.solver().lastIterations();
    if (*status == LpStatus::kIterationLimit && lpPivots_ < lpLimit_) {
        return false;
    }
    lpRunning_ = false;
    return true;
}

// ---------------------------------------------------------------------------
// Layered seed: a search over waypoints, layer by layer (see the header).

namespace {
// The layered seed's lines are the faces moved out by their margin plus this
// (the LP's kSafetyM with room for rounding), the site's sides moved in by
// kLayerSideM (more than the LP's kBoundSafetyM).
constexpr double kLayerSafetyM = 2.0 * kSafetyM;
constexpr double kLayerSideM = 1e-7;
constexpr std::uint8_t kStartPoint = 0xFE;
constexpr std::uint8_t kGoalPoint = 0xFF;
constexpr std::uint64_t kLayerPointWork = 4;  // one candidate's intersection, per face of the mask
constexpr std::uint64_t kLayerEdgeWork = 3;   // one transition test (a mask AND)
constexpr std::uint64_t kByteLow = 0x0101010101010101ULL;

// Every obstacle's byte of the mask nonzero: for each obstacle some face
// holds the point(s).
bool everyObstacle(std::uint64_t mask, std::uint64_t wanted) {
    std::uint64_t y = mask | (mask >> 4);
    y |= y >> 2;
    y |= y >> 1;
    return (y & wanted) == wanted;
}
}  // namespace

std::size_t CcPlanner::layerLineCount() const {
    std::size_t n = 4;  // the site's sides
    for (std::size_t i = 0; i < obstacles_; ++i) {
        n += problem_.obstacles[i].faceCount;
    }
    return n;
}

// Line k at layer tau as {x : nx x + ny y = c}, the free side nx x + ny y >= c.
void CcPlanner::layerLine(std::size_t tau, std::size_t k, double* nx, double* ny, double* c) const {
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = problem_.obstacles[i];
        if (k < o.faceCount) {
            *nx = o.normalX[k];
            *ny = o.normalY[k];
            *c = o.offset[k] + margin_[tau][i][k] + kLayerSafetyM;
            return;
        }
        k -= o.faceCount;
    }
    const double sx[4] = {1.0, -1.0, 0.0, 0.0};
    const double sy[4] = {0.0, 0.0, 1.0, -1.0};
    const double sc[4] = {problem_.xMin + kLayerSideM, -(problem_.xMax - kLayerSideM), problem_.yMin + kLayerSideM,
                          -(problem_.yMax - kLayerSideM)};
    *nx = sx[k & 3U];
    *ny = sy[k & 3U];
    *c = sc[k & 3U];
}

// The point named by two line indices at layer tau (or the start or goal).
bool CcPlanner::layerPoint(std::size_t tau, std::uint8_t a, std::uint8_t b, double* x, double* y) const {
    if (a == kStartPoint || a == kGoalPoint) {
        *x = a == kStartPoint ? problem_.startX : problem_.goalX;
        *y = a == kStartPoint ? problem_.startY : problem_.goalY;
        return true;
    }
    double ax = 0.0, ay = 0.0, ac = 0.0, bx = 0.0, by = 0.0, bc = 0.0;
    layerLine(tau, a, &ax, &ay, &ac);
    layerLine(tau, b, &bx, &by, &bc);
    const double det = ax * by - ay * bx;
    if (std::fabs(det) < 1e-9) {
        return false;
    }
    *x = (ac * by - ay * bc) / det;
    *y = (ax * bc - ac * bx) / det;
    return *x >= problem_.xMin + kBoundSafetyM && *x <= problem_.xMax - kBoundSafetyM &&
           *y >= problem_.yMin + kBoundSafetyM && *y <= problem_.yMax - kBoundSafetyM;
}

// Byte i, bit j: the point clears face j of obstacle i by its margin at tau
// (by kSafetyM more, as the LP wants, unless it is the fixed start or goal).
std::uint64_t CcPlanner::layerMask(std::size_t tau, double x, double y, bool fixedEnd) {
    geometryWork_ += kLayerPointWork * kMaxObstacleFaces * obstacles_;
    std::uint64_t mask = 0;
    for (std::size_t i = 0; i < obstacles_; ++i) {
        const PlanObstacle& o = problem_.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            double s = endSlack(o, j, x, y, margin_[tau][i][j]);
            s -= fixedEnd ? 0.0 : kSafetyM;
            if (s >= 0.0) {
                mask |= 1ULL << (8U * i + j);
            }
        }
    }
    return mask;
}

// Builds layer layerTau_ from the one before: every candidate point (two of
// the layer's lines crossing inside the site, the start, the goal) that
// clears every obstacle and is one feasible segment from a point of the
// layer before. True when the search is over (a path is in scratchX_ /
// scratchY_ and seeded, or there is none).
bool CcPlanner::layeredSeedStep() {
    const std::uint64_t wanted = kByteLow & (obstacles_ >= 8 ? ~0ULL : ((1ULL << (8U * obstacles_)) - 1U));
    if (layerTau_ == 0) {
        layerLines_[0][0][0] = kStartPoint;
        layerLines_[0][0][1] = kStartPoint;
        reachX_[0][0] = problem_.startX;
        reachY_[0][0] = problem_.startY;
        reachMask_[0][0] = layerMask(0, problem_.startX, problem_.startY, true);
        layerCount_[0] = 1;
        layerTau_ = 1;
        layerLineA_ = 0;
        layerBuilt_ = 0;
        return false;
    }
    const std::size_t tau = layerTau_;
    const std::size_t from = (tau - 1) & 1U;
    const std::size_t to = tau & 1U;
    auto consider = [&](std::uint8_t a, std::uint8_t b) {
        double x = 0.0;
        double y = 0.0;
        if (layerBuilt_ >= kMaxLayerPoints || !layerPoint(tau, a, b, &x, &y)) {
            return;
        }
        const bool fixedEnd = a == kStartPoint || a == kGoalPoint;
        const std::uint64_t mask = layerMask(tau, x, y, fixedEnd);
        if (!everyObstacle(mask, wanted)) {
            return;
        }
        // A point's future moves depend on its mask alone: one whose faces
        // include this one's already does all it could (exact, and it keeps
        // the layers far below kMaxLayerPoints).
        geometryWork_ += kLayerEdgeWork * layerBuilt_;
        for (std::size_t v = 0; v < layerBuilt_; ++v) {
            if ((reachMask_[to][v] & mask) == mask) {
                return;
            }
        }
        const std::size_t prevCount = layerCount_[tau - 1];
        for (std::size_t u = 0; u < prevCount; ++u) {
            if (everyObstacle(mask & reachMask_[from][u], wanted)) {
                geometryWork_ += kLayerEdgeWork * (u + 1U);
                layerLines_[tau][layerBuilt_][0] = a;
                layerLines_[tau][layerBuilt_][1] = b;
                layerPrev_[tau][layerBuilt_] = static_cast<std::uint16_t>(u);
                reachX_[to][layerBuilt_] = x;
                reachY_[to][layerBuilt_] = y;
                reachMask_[to][layerBuilt_] = mask;
                ++layerBuilt_;
                return;
            }
        }
        geometryWork_ += kLayerEdgeWork * prevCount;
    };
    const std::size_t lines = layerLineCount();
    bool goalReached = false;
    if (layerLineA_ == 0 && layerBuilt_ == 0) {
        // The goal first: once it is reached the rest of the steps park there.
        consider(kGoalPoint, kGoalPoint);
        goalReached = layerBuilt_ == 1;
        if (tau == steps_ || goalReached) {
            layerLineA_ = lines;
        }
    }
    // A slice of the line pairs (at least kLayerPairsPerUnit, whole rows).
    std::size_t pairs = 0;
    for (; layerLineA_ < lines && pairs < kLayerPairsPerUnit; ++layerLineA_) {
        const std::size_t a = layerLineA_;
        for (std::size_t b = a + 1; b < lines; ++b, ++pairs) {
            // Every pair, the site's corners too: a waypoint's polygon may
            // have its only vertices there.
            consider(static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b));
        }
    }
    if (layerLineA_ < lines) {
        return false;  // this layer goes on in the next unit
    }
    const std::size_t count = layerBuilt_;
    layerCount_[tau] = static_cast<std::uint16_t>(count);
    layerFull_ += count >= kMaxLayerPoints ? 1U : 0U;
    layerLineA_ = 0;
    layerBuilt_ = 0;
    if (count == 0 || (tau == steps_ && !goalReached)) {
        return true;  // no path through these points
    }
    if (!goalReached) {
        ++layerTau_;
        return false;
    }
    // The goal at layer tau: the rest of the steps park there (the goal
    // clears some face of every obstacle by its margin at N, the largest).
    std::size_t k = 0;  // the goal's index in layer tau
    for (std::size_t t = steps_; t > tau; --t) {
        scratchX_[t] = problem_.goalX;
        scratchY_[t] = problem_.goalY;
    }
    double length = 0.0;
    for (std::size_t t = tau + 1; t-- > 0;) {
        double x = 0.0;
        double y = 0.0;
        (void)layerPoint(t, layerLines_[t][k][0], layerLines_[t][k][1], &x, &y);
        scratchX_[t] = x;
        scratchY_[t] = y;
        if (t < tau) {
            length += polygonLength(scratchX_[t + 1] - x, scratchY_[t + 1] - y);
        }
        k = t > 0 ? layerPrev_[t][k] : 0U;
    }
    seedFromPath(length);
    return true;
}

// ---------------------------------------------------------------------------
// Search.

void CcPlanner::rootStep() {
    if (lpRunning_) {
        rootLpUnit();
        return;
    }
    (void)lp_.popPairs(0);
    depth_ = 0;
    rootPairs_ = 0;
    // Presolve: a pair of the first or last segment has an end at the fixed
    // start or goal, which rules out the faces it misses. A pair with no face
    // left proves there is no plan; a pair with one is fixed at the root.
    for (std::size_t t = 0; t < steps_; t += (steps_ > 1 ? steps_ - 1 : 1)) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            const PlanObstacle& o = problem_.obstacles[i];
            std::size_t count = 0;
            std::size_t only = 0;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const bool startOk =
                    t != 0 || endSlack(o, j, problem_.startX, problem_.startY, margin_[0][i][j]) >= 0.0;
                const bool goalOk =
                    t + 1 != steps_ || endSlack(o, j, problem_.goalX, problem_.goalY, margin_[steps_][i][j]) >= 0.0;
                if (startOk && goalOk) {
                    ++count;
                    only = j;
                }
            }
            if (count == 0) {
                phase_ = Phase::kSearch;
                return;  // depth 0: the search ends at once, exhausted, with no plan
            }
            if (count == 1) {
                bool feasible = false;
                if (lp_.addPair(t, i, only, margin_[t][i][only], margin_[t + 1][i][only], &feasible) ==
                        core::Status::kOk &&
                    feasible) {
                    assigned_[t][i] = static_cast<std::uint8_t>(only);
                    ++rootPairs_;
                }
            }
        }
    }
    beginLp(HUGE_VAL, lpCap());
}

// One unit of the root's LP; at its end the search starts from it.
void CcPlanner::rootLpUnit() {
    LpStatus st = LpStatus::kNotSolved;
    if (!continueLp(&st)) {
        return;
    }
    phase_ = Phase::kSearch;
    ++nodes_;
    if (st == LpStatus::kOptimal) {
        evaluateNode();
    } else if (st != LpStatus::kInfeasible) {
        incomplete_ = true;
        unresolvedBound_ = 0.0;
    }
}

void CcPlanner::evaluateNode() {
    const double cost = lp_.cost();
    if (cost >= pruneThreshold()) {
        return;
    }
    for (std::size_t tau = 0; tau <= steps_; ++tau) {
        scratchX_[tau] = lp_.meanX(tau);
        scratchY_[tau] = lp_.meanY(tau);
    }
    geometryWork_ += kScoreWork * steps_ * obstacles_ * kMaxObstacleFaces;
    double worst = 0.0;
    std::size_t wt = kMaxPlanSteps;
    std::size_t wi = 0;
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i) {
            if (assigned_[t][i] != kUnassigned) {
                faceScratch_[t][i] = assigned_[t][i];
                continue;
            }
            double best = -INFINITY;
            std::uint8_t bestFace = 0;
            for (std::size_t j = 0; j < problem_.obstacles[i].faceCount; ++j) {
                const double s = pairScore(t, i, j, scratchX_, scratchY_);
                if (s > best) {
                    best = s;
                    bestFace = static_cast<std::uint8_t>(j);
                }
            }
            faceScratch_[t][i] = bestFace;
            if (best < worst) {
                worst = best;
                wt = t;
                wi = i;
            }
        }
    }
    if (wt == kMaxPlanSteps) {
        offerIncumbentFromLp(faceScratch_);
        return;
    }
    if (rootPairs_ + depth_ >= kMaxPairs) {
        incomplete_ = true;  // cannot happen: every level assigns a new pair
        return;
    }
    Level& l = level_[depth_];
    l.t = static_cast<std::uint8_t>(wt);
    l.obstacle = static_cast<std::uint8_t>(wi);
    l.next = 0;
    l.bound = cost;
    const PlanObstacle& o = problem_.obstacles[wi];
    double score[kMaxObstacleFaces];
    l.count = 0;
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        score[j] = pairScore(wt, wi, j, scratchX_, scratchY_);
        if (guideValid_ && guideFace_[wt][wi] == j) {
            score[j] = HUGE_VAL;  // the guide's face first
        }
        // Insertion by descending score: least violated face first.
        std::size_t pos = l.count;
        while (pos > 0 && score[l.order[pos - 1]] < score[j]) {
            l.order[pos] = l.order[pos - 1];
            --pos;
        }
        l.order[pos] = static_cast<std::uint8_t>(j);
        ++l.count;
    }
    saveLevelFactor(depth_);
    ++depth_;
    maxDepth_ = depth_ > maxDepth_ ? depth_ : maxDepth_;
}

void CcPlanner::saveLevelFactor(std::size_t d) {
    Level& l = level_[d];
    if (factorSlots_ == 0) {
        lp_.solver().saveBasis(&l.basis);
        return;
    }
    const std::size_t slot = d % factorSlots_;
    if (lp_.solver().saveFactor(&l.basis, &factorPool_[slot * factorSize_], factorSize_) == core::Status::kOk) {
        slotOwner_[slot] = d;
    } else {
        lp_.solver().saveBasis(&l.basis);
    }
}

void CcPlanner::restoreLevel(std::size_t d) {
    Level& l = level_[d];
    if (factorSlots_ > 0) {
        const std::size_t slot = d % factorSlots_;
        if (slotOwner_[slot] == d &&
            lp_.solver().restoreFactor(l.basis, &factorPool_[slot * factorSize_], factorSize_) == core::Status::kOk) {
            ++factorRestores_;
            return;
        }
    }
    (void)lp_.solver().restoreBasis(l.basis);
    // The slot is free again once the levels above d are gone.
    if (lp_.solver().basisValid()) {
        saveLevelFactor(d);
    }
}

bool CcPlanner::searchStep() {
    if (lpRunning_) {
        nodeLpUnit();
        return true;
    }
    // Each pass consumes one child (or pops a level), so kMaxPairs levels of
    // at most kMaxObstacleFaces children bound it.
    const std::size_t guard = kMaxPairs * (kMaxObstacleFaces + 1) + 1;
    for (std::size_t pass = 0; pass < guard && depth_ > 0; ++pass) {
        Level& l = level_[depth_ - 1];
        if (l.next >= l.count || l.bound >= pruneThreshold()) {
            assigned_[l.t][l.obstacle] = kUnassigned;
            --depth_;
            continue;
        }
        const std::uint8_t face = l.order[l.next++];
        (void)lp_.popPairs(rootPairs_ + depth_ - 1);
        if (!lp_.solver().basisValid()) {
            restoreLevel(depth_ - 1);
        }
        assigned_[l.t][l.obstacle] = face;
        bool feasible = false;
        if (lp_.addPair(l.t, l.obstacle, face, margin_[l.t][l.obstacle][face], margin_[l.t + 1][l.obstacle][face],
                        &feasible) != core::Status::kOk ||
            !feasible) {
            continue;
        }
        beginLp(pruneThreshold(), lpCap());
        nodeLpUnit();
        return true;
    }
    return false;
}

// One unit of a node's LP; at its end the node is evaluated.
void CcPlanner::nodeLpUnit() {
    LpStatus st = LpStatus::kNotSolved;
    if (!continueLp(&st)) {
        return;
    }
    ++nodes_;
    if (st == LpStatus::kOptimal) {
        evaluateNode();
    } else if (st != LpStatus::kInfeasible && st != LpStatus::kCutoff) {
        abandonNode();
    }
}

// The node whose LP is running (or was cut short) stays unresolved: the
// search is incomplete and its parent's bound bounds what it hides.
void CcPlanner::abandonNode() {
    lpRunning_ = false;
    incomplete_ = true;
    const double bound = depth_ > 0 ? level_[depth_ - 1].bound : 0.0;
    unresolvedBound_ = bound < unresolvedBound_ ? bound : unresolvedBound_;
}

// ---------------------------------------------------------------------------
// Risk allocation.

void CcPlanner::allocateStep() {
    const bool workLeft = params_.workBudget == 0 || work() < 10ULL * kAllocateSharePercent * params_.workBudget;
    if (evalRunning_) {
        if (!workLeft) {
            evalRunning_ = false;
            endAllocation();
        } else if (evaluateUnit(&candidate_)) {
            judgeCandidate();
        }
        return;
    }
    if (lpRunning_) {
        LpStatus st = LpStatus::kNotSolved;
        if (!workLeft) {
            lpRunning_ = false;
            endAllocation();
        } else if (!continueLp(&st)) {
            // runs on in the next unit
        } else if (st != LpStatus::kOptimal) {
            endAllocation();
        } else if (!iraReady_) {
            iraReady_ = true;
        } else {
            allocationCandidate();
        }
        return;
    }
    if (best_.status == CcStatus::kNoPlan || obstacles_ == 0 ||
        problem_.allocation != RiskAllocation::kOptimised || iraDone_ >= params_.iraRounds || iraLastRound_ || !workLeft) {
        endAllocation();
        return;
    }
    if (!iraReady_) {
        // The best plan's faces, all pairs, its (even) deltas.
        // From the search's budget; a budget certified so far: Delta when
        // the search's plan is certified by Boole, none when it is not.
        iraBudget_ = bestCertified_ ? riskBudget_ : searchBudget_;
        budgetLo_ = bestCertified_ ? riskBudget_ : 0.0;
        budgetHi_ = INFINITY;
        (void)lp_.popPairs(0);
        for (std::size_t t = 0; t < steps_; ++t) {
            for (std::size_t i = 0; i < obstacles_; ++i) {
                const std::size_t j = best_.face[t][i];
                delta_[t][i][0] = best_.delta[t][i][0];
                delta_[t][i][1] = best_.delta[t][i][1];
                bool feasible = false;
                if (lp_.addPair(t, i, j, margin_[t][i][j], margin_[t + 1][i][j], &feasible) != core::Status::kOk ||
                    !feasible) {
                    endAllocation();
                    return;
                }
            }
        }
        beginLp(HUGE_VAL, params_.perLpIterations);
        return;
    }
    ++iraDone_;
    geometryWork_ += 3U * kMarginWork * 2U * steps_ * obstacles_;  // risks, margins, the check
    // New deltas at the current solution.
    const double floor = evenDelta_ * kIraFloor;
    double fixedSum = 0.0;
    double activeSum = 0.0;
    std::size_t activeCount = 0;
    bool active[kMaxPlanSteps][kMaxPlanObstacles][2];
    std::size_t k = 0;
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i, ++k) {
            const PlanObstacle& o = problem_.obstacles[i];
            const std::size_t j = best_.face[t][i];
            for (std::size_t e = 0; e < 2; ++e) {
                const std::size_t tau = t + e;
                active[t][i][e] = lp_.pairActive(k, e);
                if (active[t][i][e]) {
                    activeSum += delta_[t][i][e];
                    ++activeCount;
                    continue;
                }
                const double raw = endSlack(o, j, lp_.meanX(tau), lp_.meanY(tau), 0.0) - 2.0 * kSafetyM;
                const double variance =
                    faceVariance(o.normalX[j], o.normalY[j], problem_.startCov, problem_.processSigmaM,
                                 static_cast<unsigned>(tau));
                double need = endRisk(raw, variance);
                need = need > floor ? need : floor;
                double next = kIraKeep * delta_[t][i][e] + (1.0 - kIraKeep) * need;
                next = next < delta_[t][i][e] ? next : delta_[t][i][e];
                delta_[t][i][e] = next;
                fixedSum += next;
            }
        }
    }
    const double residual = iraBudget_ - fixedSum - activeSum;
    if (activeCount == 0 || !(residual > 0.0)) {
        // Nothing to stretch: the LP's path already meets the slack ends' new
        // deltas (each is at least its need there), so it is this round's
        // candidate as it stands, the last one (an uncertified search plan
        // still gets its evaluation).
        iraLastRound_ = true;
        allocationCandidate();
        return;
    }
    double add = residual / static_cast<double>(activeCount);
    // Sum in plan order; shave the share until it fits (rounding only).
    for (int attempt = 0; attempt < 8; ++attempt) {
        double sum = 0.0;
        for (std::size_t t = 0; t < steps_; ++t) {
            for (std::size_t i = 0; i < obstacles_; ++i) {
                for (std::size_t e = 0; e < 2; ++e) {
                    sum += active[t][i][e] ? delta_[t][i][e] + add : delta_[t][i][e];
                }
            }
        }
        if (sum <= iraBudget_) {
            break;
        }
        add *= 1.0 - 1e-9 * static_cast<double>(attempt + 1);
        if (attempt == 7) {
            add = 0.0;
        }
    }
    k = 0;
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t i = 0; i < obstacles_; ++i, ++k) {
            const std::size_t j = best_.face[t][i];
            for (std::size_t e = 0; e < 2; ++e) {
                if (active[t][i][e]) {
                    double d = delta_[t][i][e] + add;
                    d = d < 0.49 ? d : 0.49;
                    delta_[t][i][e] = d;
                }
            }
            (void)lp_.setPairMargins(k, faceMargin(problem_, i, j, t, delta_[t][i][0]),
                                     faceMargin(problem_, i, j, t + 1, delta_[t][i][1]));
        }
    }
    beginLp(HUGE_VAL, params_.perLpIterations);
}

// The candidate of an allocation round: its LP's path with its deltas; its
// certified risk is evaluated next (one segment a unit), then judged.
void CcPlanner::allocationCandidate() {
    CcPlan& c = candidate_;
    c = best_;
    c.status = CcStatus::kFeasible;
    double cost = 0.0;
    double euclid = 0.0;
    for (std::size_t tau = 0; tau <= steps_; ++tau) {
        c.meanX[tau] = lp_.meanX(tau);
        c.meanY[tau] = lp_.meanY(tau);
    }
    for (std::size_t t = 0; t < steps_; ++t) {
        const double dx = c.meanX[t + 1] - c.meanX[t];
        const double dy = c.meanY[t + 1] - c.meanY[t];
        cost += polygonLength(dx, dy);
        euclid += euclidean(dx, dy);
        for (std::size_t i = 0; i < obstacles_; ++i) {
            for (std::size_t e = 0; e < 2; ++e) {
                c.delta[t][i][e] = delta_[t][i][e];
            }
        }
    }
    c.cost = cost;
    c.euclideanLengthM = euclid;
    startEvaluation();
}

void CcPlanner::startEvaluation() {
    evalT_ = 0;
    evalTotal_ = 0.0;
    evalRunning_ = true;
}

bool CcPlanner::evaluateUnit(CcPlan* plan) {
    RiskWork w;
    const double r = certifiedSegmentRisk(problem_, *plan, evalT_, &w);
    geometryWork_ += kTailWork * w.tails + kOrthantWork * w.orthants + kScoreWork * w.lineSolves;
    plan->segmentRisk[evalT_] = r;
    evalTotal_ += r;
    if (++evalT_ < steps_) {
        return false;
    }
    evalRunning_ = false;
    plan->riskUsed = evalTotal_;
    return true;
}

// Keeps the candidate when it is certified within Delta and shorter, and sets
// the next round's budget: raised towards Delta / (certified risk) when it
// certified, halfway back to the last certified budget when it did not.
void CcPlanner::judgeCandidate() {
    const double certified = candidate_.riskUsed;
    double deltaSum = 0.0;
    const bool ok = checkPlanShape(problem_, candidate_, problem_.riskBound, &deltaSum) == core::Status::kOk &&
                    certified <= riskBudget_;
    const double previous = best_.cost;
    const bool gain = ok && (!bestCertified_ || candidate_.cost < previous);
    if (gain) {
        best_ = candidate_;
        bestCertified_ = true;
    }
    if (ok) {
        budgetLo_ = iraBudget_ > budgetLo_ ? iraBudget_ : budgetLo_;
        const double aim = certified > 0.0 ? kStretchAim * riskBudget_ / certified : kMaxStretch;
        double next = iraBudget_ * (aim < kMaxStretch ? aim : kMaxStretch);
        if (std::isfinite(budgetHi_)) {
            const double half = 0.5 * (iraBudget_ + budgetHi_);
            next = next < half ? next : half;
        }
        iraBudget_ = next > iraBudget_ ? next : iraBudget_;
    } else {
        budgetHi_ = iraBudget_ < budgetHi_ ? iraBudget_ : budgetHi_;
        iraBudget_ = 0.5 * (budgetLo_ + budgetHi_);
        // Back to the best plan's deltas, scaled down to the new budget when
        // they pass it (an uncertified search plan's do).
        double sum = 0.0;
        for (std::size_t t = 0; t < steps_; ++t) {
            for (std::size_t i = 0; i < obstacles_; ++i) {
                sum += best_.delta[t][i][0] + best_.delta[t][i][1];
            }
        }
        const double scale = sum > iraBudget_ ? iraBudget_ / sum * (1.0 - kRiskSafety) : 1.0;
        for (std::size_t t = 0; t < steps_; ++t) {
            for (std::size_t i = 0; i < obstacles_; ++i) {
                delta_[t][i][0] = best_.delta[t][i][0] * scale;
                delta_[t][i][1] = best_.delta[t][i][1] * scale;
            }
        }
    }
    const bool close = ok && certified >= kStretchClose * riskBudget_;
    const bool narrow = std::isfinite(budgetHi_) && budgetHi_ <= budgetLo_ * 1.02;
    const bool gained = gain && candidate_.cost < previous - 1e-9 * (1.0 + previous);
    if (!gained && iraDone_ > 2 && (close || narrow)) {
        endAllocation();
    }
}

// ---------------------------------------------------------------------------
// Finish: pull the plan taut (plan_tauten.hpp) and certify its risk.

void CcPlanner::endAllocation() {
    lpRunning_ = false;
    evalRunning_ = false;
    if (best_.status == CcStatus::kNoPlan || best_.status == CcStatus::kBadProblem) {
        phase_ = Phase::kDone;
        return;
    }
    if (!bestCertified_) {
        // The relaxed search's plan never certified within Delta: no plan.
        best_ = noPlan_;
        phase_ = Phase::kDone;
        return;
    }
    tautenDone_ = false;
    phase_ = Phase::kFinish;
}

void CcPlanner::finishStep() {
    const bool workLeft = params_.workBudget == 0 || work() < 1000ULL * params_.workBudget;
    if (!tautenDone_) {
        // The taut path keeps every face and delta: its deltas' sum is the
        // plan's, and its risk bound is evaluated next.
        tautenDone_ = true;
        candidate_ = best_;
        geometryWork_ += kTautWorkPerTry * tautenPlan(problem_, &candidate_);
        claimBooleRisk(problem_, &candidate_);
        startEvaluation();
        return;
    }
    bool evaluated = false;
    if (evalRunning_ && workLeft) {
        evaluated = evaluateUnit(&candidate_);
        if (!evaluated) {
            return;
        }
    }
    // Evaluated, or cut short by the budget (then the deltas' sum stands).
    evalRunning_ = false;
    if (!evaluated) {
        claimBooleRisk(problem_, &candidate_);
    }
    double deltaSum = 0.0;
    const bool shape = checkPlanShape(problem_, candidate_, problem_.riskBound, &deltaSum) == core::Status::kOk;
    if (shape && candidate_.riskUsed <= riskBudget_ && candidate_.cost <= best_.cost) {
        best_ = candidate_;
    } else {
        ++tautenRefused_;
    }
    phase_ = Phase::kDone;
    // A relaxed search's proof is about its own budget, not Delta's.
    const bool proven = exhausted_ && !incomplete_ && searchScale() == 1.0;
    best_.status = proven ? CcStatus::kOptimal : CcStatus::kFeasible;
}

double CcPlanner::searchScale() const {
    return problem_.allocation == RiskAllocation::kOptimised ? params_.searchRiskScale : 1.0;
}

void CcPlanner::finish() {
    if (phase_ != Phase::kFinish && phase_ != Phase::kDone) {
        endAllocation();
    }
    // Tautening, then at most N evaluation units.
    for (std::size_t k = 0; k < kMaxPlanSteps + 2 && phase_ == Phase::kFinish; ++k) {
        finishStep();
    }
    phase_ = Phase::kDone;
}

}  // namespace rse::deliberative
