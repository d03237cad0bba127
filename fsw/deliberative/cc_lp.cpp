#include "fsw/deliberative/cc_lp.hpp"

#include <cmath>

#include "fsw/deliberative/gaussian.hpp"

namespace rse::deliberative {

namespace {

constexpr double kTwoPi = 6.283185307179586476925;

// c_k = (cos 2 pi k / K, sin 2 pi k / K), computed once per call site.
struct PolygonDirections {
    double cx[kPolygonNormSides];
    double cy[kPolygonNormSides];
    PolygonDirections() {
        for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
            const double a = kTwoPi * static_cast<double>(k) / static_cast<double>(kPolygonNormSides);
            cx[k] = std::cos(a);
            cy[k] = std::sin(a);
        }
    }
};

const PolygonDirections& directions() {
    static const PolygonDirections d;
    return d;
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

double polygonLength(double dx, double dy) {
    const PolygonDirections& d = directions();
    double best = -HUGE_VAL;
    for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
        const double v = d.cx[k] * dx + d.cy[k] * dy;
        best = v > best ? v : best;
    }
    return best;
}

core::Status checkProblem(const CcProblem& p) {
    const core::Status bad = core::Status::kInvalidArgument;
    if (p.steps < 1 || p.steps > kMaxPlanSteps || p.obstacleCount > kMaxPlanObstacles) {
        return bad;
    }
    if (!finite(p.startX) || !finite(p.startY) || !finite(p.goalX) || !finite(p.goalY) || !finite(p.xMin) ||
        !finite(p.xMax) || !finite(p.yMin) || !finite(p.yMax) || !finite(p.processSigmaM) || !finite(p.riskBound)) {
        return bad;
    }
    if (!(p.xMin < p.xMax) || !(p.yMin < p.yMax) || p.processSigmaM < 0.0) {
        return bad;
    }
    if (p.startX < p.xMin || p.startX > p.xMax || p.startY < p.yMin || p.startY > p.yMax || p.goalX < p.xMin ||
        p.goalX > p.xMax || p.goalY < p.yMin || p.goalY > p.yMax) {
        return bad;
    }
    if (!(p.riskBound > 0.0) || !(p.riskBound < 0.5)) {
        return bad;
    }
    if (p.allocation != RiskAllocation::kEvenSplit && p.allocation != RiskAllocation::kOptimised) {
        return bad;
    }
    const double* c = p.startCov;
    for (std::size_t k = 0; k < 4; ++k) {
        if (!finite(c[k])) {
            return bad;
        }
    }
    const double scale = std::fabs(c[0]) + std::fabs(c[3]) + 1e-300;
    if (std::fabs(c[1] - c[2]) > 1e-12 * scale || c[0] < 0.0 || c[3] < 0.0 ||
        c[0] * c[3] - c[1] * c[2] < -1e-12 * scale * scale) {
        return bad;
    }
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        if (o.faceCount < 3 || o.faceCount > kMaxObstacleFaces) {
            return bad;
        }
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            if (!finite(o.normalX[j]) || !finite(o.normalY[j]) || !finite(o.offset[j])) {
                return bad;
            }
            const double norm = std::sqrt(o.normalX[j] * o.normalX[j] + o.normalY[j] * o.normalY[j]);
            if (std::fabs(norm - 1.0) > 1e-9) {
                return bad;
            }
        }
    }
    return core::Status::kOk;
}

double faceMargin(const CcProblem& p, std::size_t obstacle, std::size_t face, std::size_t tau, double delta) {
    const PlanObstacle& o = p.obstacles[obstacle];
    const double variance =
        faceVariance(o.normalX[face], o.normalY[face], p.startCov, p.processSigmaM, static_cast<unsigned>(tau));
    return tighteningMargin(delta, variance);
}

core::Status CcLp::setup(const CcProblem& p) {
    if (checkProblem(p) != core::Status::kOk) {
        return core::Status::kInvalidArgument;
    }
    problem_ = &p;
    steps_ = p.steps;
    pairCount_ = 0;
    const std::size_t n = 3 * steps_ - 2;
    if (lp_.reset(n) != core::Status::kOk) {
        return core::Status::kNoCapacity;
    }
    const double span = (p.xMax - p.xMin) + (p.yMax - p.yMin);
    const double artificial = 4.0 * span > 1e6 ? 4.0 * span : 1e6;
    (void)lp_.setArtificialBound(artificial);
    // Site bounds, shrunk so the LP's tolerance never leaves the site.
    const double shrinkX = (p.xMax - p.xMin) > 4.0 * kBoundSafetyM ? kBoundSafetyM : 0.0;
    const double shrinkY = (p.yMax - p.yMin) > 4.0 * kBoundSafetyM ? kBoundSafetyM : 0.0;
    for (std::size_t tau = 1; tau < steps_; ++tau) {
        (void)lp_.setBounds(muIndex(tau, 0), p.xMin + shrinkX, p.xMax - shrinkX);
        (void)lp_.setBounds(muIndex(tau, 1), p.yMin + shrinkY, p.yMax - shrinkY);
    }
    for (std::size_t t = 0; t < steps_; ++t) {
        (void)lp_.setBounds(sIndex(t), 0.0, HUGE_VAL);
        (void)lp_.setObjective(sIndex(t), 1.0);
    }
    // Epigraph rows: c_k . (mu_{t+1} - mu_t) - s_t <= 0, constants to the right.
    const PolygonDirections& d = directions();
    for (std::size_t t = 0; t < steps_; ++t) {
        for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
            std::uint8_t idx[5];
            double val[5];
            std::size_t count = 0;
            double rhs = 0.0;
            if (t == 0) {
                rhs += d.cx[k] * p.startX + d.cy[k] * p.startY;
            } else {
                idx[count] = static_cast<std::uint8_t>(muIndex(t, 0));
                val[count++] = -d.cx[k];
                idx[count] = static_cast<std::uint8_t>(muIndex(t, 1));
                val[count++] = -d.cy[k];
            }
            if (t + 1 == steps_) {
                rhs -= d.cx[k] * p.goalX + d.cy[k] * p.goalY;
            } else {
                idx[count] = static_cast<std::uint8_t>(muIndex(t + 1, 0));
                val[count++] = d.cx[k];
                idx[count] = static_cast<std::uint8_t>(muIndex(t + 1, 1));
                val[count++] = d.cy[k];
            }
            idx[count] = static_cast<std::uint8_t>(sIndex(t));
            val[count++] = -1.0;
            // Drop exact zeros (cos and sin of multiples of pi / 2).
            std::uint8_t idx2[5];
            double val2[5];
            std::size_t count2 = 0;
            for (std::size_t e = 0; e < count; ++e) {
                if (std::fabs(val[e]) > 1e-15) {
                    idx2[count2] = idx[e];
                    val2[count2++] = val[e];
                }
            }
            if (lp_.addRow(idx2, val2, count2, rhs, nullptr) != core::Status::kOk) {
                return core::Status::kNoCapacity;
            }
        }
    }
    baseRows_ = lp_.rowCount();
    return core::Status::kOk;
}

core::Status CcLp::addPair(std::size_t t, std::size_t obstacle, std::size_t face, double margin0, double margin1,
                           bool* feasible, std::uint8_t ends) {
    if (problem_ == nullptr || feasible == nullptr) {
        return core::Status::kNotInitialized;
    }
    const CcProblem& p = *problem_;
    if (t >= steps_ || obstacle >= p.obstacleCount || face >= p.obstacles[obstacle].faceCount ||
        !std::isfinite(margin0) || !std::isfinite(margin1) || ends == 0 || ends > kBothEnds) {
        return core::Status::kInvalidArgument;
    }
    if (pairCount_ >= kMaxPairs) {
        return core::Status::kFull;
    }
    const PlanObstacle& o = p.obstacles[obstacle];
    const double margin[2] = {margin0, margin1};
    // Constant ends first: nothing is pushed if one fails.
    for (std::size_t e = 0; e < 2; ++e) {
        if ((ends & (1U << e)) == 0) {
            continue;
        }
        const std::size_t tau = t + e;
        if (tau == 0 && endSlack(o, face, p.startX, p.startY, margin[e]) < 0.0) {
            *feasible = false;
            return core::Status::kOk;
        }
        if (tau == steps_ && endSlack(o, face, p.goalX, p.goalY, margin[e]) < 0.0) {
            *feasible = false;
            return core::Status::kOk;
        }
    }
    Pair& pr = pair_[pairCount_];
    pr.t = static_cast<std::uint8_t>(t);
    pr.obstacle = static_cast<std::uint8_t>(obstacle);
    pr.face = static_cast<std::uint8_t>(face);
    pr.ends = ends;
    const std::size_t rowsBefore = lp_.rowCount();
    for (std::size_t e = 0; e < 2; ++e) {
        pr.margin[e] = margin[e];
        pr.row[e] = kNoRow;
        const std::size_t tau = t + e;
        if ((ends & (1U << e)) == 0 || tau == 0 || tau == steps_) {
            continue;
        }
        // -a . mu_tau <= -(b + margin + safety)
        const std::uint8_t idx[2] = {static_cast<std::uint8_t>(muIndex(tau, 0)),
                                     static_cast<std::uint8_t>(muIndex(tau, 1))};
        const double val[2] = {-o.normalX[face], -o.normalY[face]};
        std::size_t row = 0;
        const core::Status st = lp_.addRow(idx, val, 2, -(o.offset[face] + margin[e] + kSafetyM), &row);
        if (st != core::Status::kOk) {
            (void)lp_.truncateRows(rowsBefore);
            return st;
        }
        pr.row[e] = static_cast<std::uint16_t>(row);
    }
    ++pairCount_;
    *feasible = true;
    return core::Status::kOk;
}

core::Status CcLp::popPairs(std::size_t count) {
    if (count > pairCount_) {
        return core::Status::kInvalidArgument;
    }
    std::size_t rows = baseRows_;
    for (std::size_t k = 0; k < count; ++k) {
        for (std::size_t e = 0; e < 2; ++e) {
            rows += pair_[k].row[e] != kNoRow ? 1U : 0U;
        }
    }
    pairCount_ = count;
    return lp_.truncateRows(rows);
}

core::Status CcLp::setPairMargins(std::size_t k, double margin0, double margin1) {
    if (k >= pairCount_ || !std::isfinite(margin0) || !std::isfinite(margin1)) {
        return core::Status::kInvalidArgument;
    }
    Pair& pr = pair_[k];
    const PlanObstacle& o = problem_->obstacles[pr.obstacle];
    const double margin[2] = {margin0, margin1};
    for (std::size_t e = 0; e < 2; ++e) {
        pr.margin[e] = margin[e];
        if (pr.row[e] != kNoRow) {
            (void)lp_.setRhs(pr.row[e], -(o.offset[pr.face] + margin[e] + kSafetyM));
        }
    }
    return core::Status::kOk;
}

double CcLp::cost() const {
    double s = 0.0;
    for (std::size_t t = 0; t < steps_; ++t) {
        s += lp_.value(sIndex(t));
    }
    return s;
}

double CcLp::meanX(std::size_t tau) const {
    if (problem_ == nullptr) {
        return 0.0;
    }
    if (tau == 0) {
        return problem_->startX;
    }
    if (tau >= steps_) {
        return problem_->goalX;
    }
    return lp_.value(muIndex(tau, 0));
}

double CcLp::meanY(std::size_t tau) const {
    if (problem_ == nullptr) {
        return 0.0;
    }
    if (tau == 0) {
        return problem_->startY;
    }
    if (tau >= steps_) {
        return problem_->goalY;
    }
    return lp_.value(muIndex(tau, 1));
}

double CcLp::pairSlack(std::size_t k, std::size_t e) const {
    if (k >= pairCount_ || e > 1) {
        return 0.0;
    }
    const Pair& pr = pair_[k];
    const std::size_t tau = pr.t + e;
    return endSlack(problem_->obstacles[pr.obstacle], pr.face, meanX(tau), meanY(tau), pr.margin[e]);
}

double CcLp::pairDual(std::size_t k, std::size_t e) const {
    if (k >= pairCount_ || e > 1 || pair_[k].row[e] == kNoRow) {
        return 0.0;
    }
    return lp_.rowDual(pair_[k].row[e]);
}

bool CcLp::pairActive(std::size_t k, std::size_t e) const {
    if (k >= pairCount_ || e > 1 || pair_[k].row[e] == kNoRow) {
        return false;
    }
    return pairDual(k, e) > 0.0 || pairSlack(k, e) < kSafetyM + 1e-7;
}

core::Status solveFixedFaces(const CcProblem& problem, const std::uint8_t face[kMaxPlanSteps][kMaxPlanObstacles],
                             const double delta[kMaxPlanSteps][kMaxPlanObstacles][2], std::uint32_t maxIterations,
                             CcLp* workspace, CcLpSolution* out) {
    if (workspace == nullptr || out == nullptr) {
        return core::Status::kInvalidArgument;
    }
    if (workspace->setup(problem) != core::Status::kOk) {
        return core::Status::kInvalidArgument;
    }
    *out = CcLpSolution{};
    const std::size_t steps = problem.steps;
    for (std::size_t t = 0; t < steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            const std::size_t j = face[t][i];
            if (j >= problem.obstacles[i].faceCount) {
                return core::Status::kInvalidArgument;
            }
            const double m0 = faceMargin(problem, i, j, t, delta[t][i][0]);
            const double m1 = faceMargin(problem, i, j, t + 1, delta[t][i][1]);
            if (!std::isfinite(m0) || !std::isfinite(m1)) {
                return core::Status::kInvalidArgument;
            }
            bool feasible = false;
            const core::Status st = workspace->addPair(t, i, j, m0, m1, &feasible);
            if (st != core::Status::kOk) {
                return st;
            }
            if (!feasible) {
                out->status = LpStatus::kInfeasible;
                return core::Status::kOk;
            }
        }
    }
    out->status = workspace->solve(maxIterations);
    out->iterations = workspace->solver().lastIterations();
    if (out->status != LpStatus::kOptimal) {
        return core::Status::kOk;
    }
    out->cost = workspace->cost();
    for (std::size_t tau = 0; tau <= steps; ++tau) {
        out->meanX[tau] = workspace->meanX(tau);
        out->meanY[tau] = workspace->meanY(tau);
    }
    std::size_t k = 0;
    for (std::size_t t = 0; t < steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i, ++k) {
            for (std::size_t e = 0; e < 2; ++e) {
                out->slack[t][i][e] = workspace->pairSlack(k, e);
                out->active[t][i][e] = workspace->pairActive(k, e);
            }
        }
    }
    return core::Status::kOk;
}

}  // namespace rse::deliberative
