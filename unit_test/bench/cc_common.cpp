#include "unit_test/bench/cc_common.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

namespace rse::test::cc {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();

// Acklam's rational approximation of Phi^-1 on (0, 1).
double acklam(double p) {
    static const double a[6] = {-3.969683028665376e+01, 2.209460984245205e+02,
                                -2.759285104469687e+02, 1.383577518672690e+02,
                                -3.066479806614716e+01, 2.506628277459239e+00};
    static const double b[5] = {-5.447609879822406e+01, 1.615858368580409e+02,
                                -1.556989798598866e+02, 6.680131188771972e+01,
                                -1.328068155288572e+01};
    static const double c[6] = {-7.784894002430293e-03, -3.223964580411365e-01,
                                -2.400758277161838e+00, -2.549732539343734e+00,
                                4.374664141464968e+00,  2.938163982698783e+00};
    static const double d[4] = {7.784695709041462e-03, 3.224671290700398e-01,
                                2.445134137142996e+00, 3.754408661907416e+00};
    constexpr double pLow = 0.02425;
    if (p < pLow) {
        const double q = std::sqrt(-2.0 * std::log(p));
        return (((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
               ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    }
    if (p > 1.0 - pLow) {
        const double q = std::sqrt(-2.0 * std::log1p(-p));
        return -(((((c[0] * q + c[1]) * q + c[2]) * q + c[3]) * q + c[4]) * q + c[5]) /
               ((((d[0] * q + d[1]) * q + d[2]) * q + d[3]) * q + 1.0);
    }
    const double q = p - 0.5;
    const double r = q * q;
    return (((((a[0] * r + a[1]) * r + a[2]) * r + a[3]) * r + a[4]) * r + a[5]) * q /
           (((((b[0] * r + b[1]) * r + b[2]) * r + b[3]) * r + b[4]) * r + 1.0);
}

double faceValue(const PlanObstacle& o, std::size_t j, double x, double y) {
    return o.normalX[j] * x + o.normalY[j] * y - o.offset[j];
}

bool finite(double v) { return std::isfinite(v); }

}  // namespace

double normalCdf(double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); }

double normalQuantile(double p) {
    if (!(p >= 0.0 && p <= 1.0)) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    if (p == 0.0) {
        return -kInf;
    }
    if (p == 1.0) {
        return kInf;
    }
    // Work in the lower half (where p keeps its relative precision), mirror.
    const bool upper = p > 0.5;
    const double pl = upper ? 1.0 - p : p;
    double x = acklam(pl);
    // One Halley step on Phi(x) - pl, with Phi from erfc (accurate in the tail).
    const double e = 0.5 * std::erfc(-x / std::sqrt(2.0)) - pl;
    const double u = e * std::sqrt(2.0 * kPi) * std::exp(0.5 * x * x);
    x = x - u / (1.0 + 0.5 * x * u);
    return upper ? -x : x;
}

double normalUpperQuantile(double delta) { return -normalQuantile(delta); }

void stepCovariance(const CcProblem& problem, std::size_t t, double cov[4]) {
    const double add = static_cast<double>(t) * problem.processSigmaM * problem.processSigmaM;
    cov[0] = problem.startCov[0] + add;
    cov[1] = problem.startCov[1];
    cov[2] = problem.startCov[2];
    cov[3] = problem.startCov[3] + add;
}

double faceMargin(const CcProblem& problem, std::size_t t, double ax, double ay, double delta) {
    double s[4];
    stepCovariance(problem, t, s);
    const double var = ax * ax * s[0] + ax * ay * (s[1] + s[2]) + ay * ay * s[3];
    return normalUpperQuantile(delta) * std::sqrt(std::max(0.0, var));
}

double RiskSplit::total(const CcProblem& problem) const {
    double sum = 0.0;
    for (std::size_t t = 0; t < problem.steps && t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount && i < kMaxPlanObstacles; ++i) {
            sum += delta[t][i][0] + delta[t][i][1];
        }
    }
    return sum;
}

RiskSplit evenSplit(const CcProblem& problem) {
    RiskSplit split;
    if (problem.steps == 0 || problem.obstacleCount == 0) {
        return split;
    }
    const double each =
        problem.riskBound / (2.0 * static_cast<double>(problem.steps) * problem.obstacleCount);
    for (std::size_t t = 0; t < problem.steps && t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount && i < kMaxPlanObstacles; ++i) {
            split.delta[t][i][0] = each;
            split.delta[t][i][1] = each;
        }
    }
    return split;
}

RiskSplit splitOf(const CcPlan& plan) {
    RiskSplit split;
    for (std::size_t t = 0; t < kMaxPlanSteps; ++t) {
        for (std::size_t i = 0; i < kMaxPlanObstacles; ++i) {
            split.delta[t][i][0] = plan.delta[t][i][0];
            split.delta[t][i][1] = plan.delta[t][i][1];
        }
    }
    return split;
}

double kgonLength(const double* meanX, const double* meanY, std::size_t steps) {
    double c[kPolygonNormSides];
    double s[kPolygonNormSides];
    for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
        const double angle = 2.0 * kPi * static_cast<double>(k) / kPolygonNormSides;
        c[k] = std::cos(angle);
        s[k] = std::sin(angle);
    }
    double sum = 0.0;
    for (std::size_t t = 0; t < steps; ++t) {
        const double dx = meanX[t + 1] - meanX[t];
        const double dy = meanY[t + 1] - meanY[t];
        double best = -kInf;
        for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
            best = std::max(best, c[k] * dx + s[k] * dy);
        }
        sum += best;
    }
    return sum;
}

double euclideanLength(const double* meanX, const double* meanY, std::size_t steps) {
    double sum = 0.0;
    for (std::size_t t = 0; t < steps; ++t) {
        sum += std::hypot(meanX[t + 1] - meanX[t], meanY[t + 1] - meanY[t]);
    }
    return sum;
}

double obstacleSlack(const PlanObstacle& obstacle, double x, double y) {
    double best = -kInf;
    for (std::size_t j = 0; j < obstacle.faceCount && j < kMaxObstacleFaces; ++j) {
        best = std::max(best, faceValue(obstacle, j, x, y));
    }
    return best;
}

bool pointInObstacle(const PlanObstacle& obstacle, double x, double y) {
    return obstacle.faceCount > 0 && obstacleSlack(obstacle, x, y) < 0.0;
}

bool segmentIntersectsObstacle(const PlanObstacle& obstacle, double x0, double y0, double x1,
                               double y1) {
    if (obstacle.faceCount == 0) {
        return false;
    }
    double lo = 0.0;
    double hi = 1.0;
    for (std::size_t j = 0; j < obstacle.faceCount && j < kMaxObstacleFaces; ++j) {
        const double f0 = faceValue(obstacle, j, x0, y0);
        const double f1 = faceValue(obstacle, j, x1, y1);
        // Inside this face's open half-plane where f(s) = f0 + s (f1 - f0) < 0.
        if (f0 >= 0.0 && f1 >= 0.0) {
            return false;
        }
        if (f0 < 0.0 && f1 < 0.0) {
            continue;
        }
        const double cross = f0 / (f0 - f1);
        if (f0 < 0.0) {
            hi = std::min(hi, cross);
        } else {
            lo = std::max(lo, cross);
        }
        if (lo >= hi) {
            return false;
        }
    }
    return lo < hi;
}

std::vector<Point> obstacleVertices(const PlanObstacle& obstacle) {
    const std::size_t n = obstacle.faceCount;
    std::vector<Point> v;
    if (n < 3 || n > kMaxObstacleFaces) {
        return v;
    }
    double turn = 0.0;
    for (std::size_t k = 0; k < n; ++k) {
        const std::size_t p = (k + n - 1) % n;
        const double ax = obstacle.normalX[p], ay = obstacle.normalY[p];
        const double bx = obstacle.normalX[k], by = obstacle.normalY[k];
        const double det = ax * by - ay * bx;
        if (!(det > 1e-12)) {
            return {};  // consecutive normals must turn counter-clockwise by (0, pi)
        }
        turn += std::atan2(det, ax * bx + ay * by);
        const double bp = obstacle.offset[p], bk = obstacle.offset[k];
        v.push_back({(bp * by - ay * bk) / det, (ax * bk - bp * bx) / det});
    }
    if (std::fabs(turn - 2.0 * kPi) > 1e-9) {
        return {};  // the normals wind more than once
    }
    for (std::size_t k = 0; k < n; ++k) {
        const Point& a = v[k];
        const Point& b = v[(k + 1) % n];
        // Face k runs from vertex k to vertex k + 1 along (-ny, nx).
        const double along = (b.x - a.x) * -obstacle.normalY[k] + (b.y - a.y) * obstacle.normalX[k];
        if (!(along > 1e-9)) {
            return {};
        }
        for (std::size_t j = 0; j < n; ++j) {
            if (faceValue(obstacle, j, a.x, a.y) > 1e-9 * (1.0 + std::fabs(obstacle.offset[j]))) {
                return {};
            }
        }
    }
    return v;
}

PlanObstacle obstacleFromVertices(const std::vector<Point>& v, std::uint8_t id) {
    PlanObstacle o;
    o.id = id;
    const std::size_t n = std::min(v.size(), kMaxObstacleFaces);
    o.faceCount = static_cast<std::uint8_t>(n);
    for (std::size_t k = 0; k < n; ++k) {
        const Point& a = v[k];
        const Point& b = v[(k + 1) % n];
        const double dx = b.x - a.x, dy = b.y - a.y;
        const double len = std::hypot(dx, dy);
        o.normalX[k] = dy / len;
        o.normalY[k] = -dx / len;
        o.offset[k] = o.normalX[k] * a.x + o.normalY[k] * a.y;
    }
    return o;
}

PlanObstacle boxObstacle(double x0, double y0, double x1, double y1, std::uint8_t id) {
    PlanObstacle o;
    o.id = id;
    o.faceCount = 4;
    const double nx[4] = {0.0, 1.0, 0.0, -1.0};
    const double ny[4] = {-1.0, 0.0, 1.0, 0.0};
    const double b[4] = {-y0, x1, y1, -x0};
    for (std::size_t k = 0; k < 4; ++k) {
        o.normalX[k] = nx[k];
        o.normalY[k] = ny[k];
        o.offset[k] = b[k];
    }
    return o;
}

std::string validateProblem(const CcProblem& p) {
    std::ostringstream why;
    if (p.steps < 1 || p.steps > kMaxPlanSteps) {
        why << "steps " << int{p.steps} << " not in 1.." << kMaxPlanSteps << "; ";
    }
    if (p.obstacleCount > kMaxPlanObstacles) {
        why << "obstacleCount " << int{p.obstacleCount} << " > " << kMaxPlanObstacles << "; ";
    }
    const double scalars[] = {p.startX, p.startY, p.goalX,  p.goalY, p.xMin,      p.xMax,
                              p.yMin,   p.yMax,   p.processSigmaM,   p.riskBound, p.startCov[0],
                              p.startCov[1],      p.startCov[2],     p.startCov[3]};
    for (double v : scalars) {
        if (!finite(v)) {
            why << "non-finite number; ";
            break;
        }
    }
    if (!(p.xMin < p.xMax && p.yMin < p.yMax)) {
        why << "empty site; ";
    }
    if (!(p.riskBound > 0.0 && p.riskBound < 0.5)) {
        why << "riskBound " << p.riskBound << " not in (0, 0.5); ";
    }
    if (!(p.processSigmaM >= 0.0)) {
        why << "processSigmaM < 0; ";
    }
    const double* s = p.startCov;
    if (!(s[0] >= 0.0 && s[3] >= 0.0 && std::fabs(s[1] - s[2]) <= 1e-12 * (1.0 + std::fabs(s[1])) &&
          s[0] * s[3] - s[1] * s[2] >= -1e-15)) {
        why << "startCov not symmetric PSD; ";
    }
    auto inside = [&](double x, double y) {
        return x >= p.xMin && x <= p.xMax && y >= p.yMin && y <= p.yMax;
    };
    if (!inside(p.startX, p.startY)) {
        why << "start outside the site; ";
    }
    if (!inside(p.goalX, p.goalY)) {
        why << "goal outside the site; ";
    }
    for (std::size_t i = 0; i < p.obstacleCount && i < kMaxPlanObstacles; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        if (o.faceCount < 3 || o.faceCount > kMaxObstacleFaces) {
            why << "obstacle " << i << " has " << int{o.faceCount} << " faces; ";
            continue;
        }
        bool unit = true;
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            const double norm = std::hypot(o.normalX[j], o.normalY[j]);
            if (!finite(o.offset[j]) || !(std::fabs(norm - 1.0) <= 1e-9)) {
                unit = false;
            }
        }
        if (!unit) {
            why << "obstacle " << i << " has a non-unit normal or a non-finite offset; ";
        } else if (obstacleVertices(o).empty()) {
            why << "obstacle " << i << " is not a closed convex CCW polygon; ";
        }
    }
    return why.str();
}

double segmentConstraintSlack(const CcProblem& problem, const double* meanX, const double* meanY,
                              const RiskSplit& split, std::size_t* worstT, std::size_t* worstI) {
    double worst = kInf;
    for (std::size_t t = 0; t < problem.steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            const PlanObstacle& o = problem.obstacles[i];
            double best = -kInf;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double ax = o.normalX[j], ay = o.normalY[j];
                const double s0 = faceValue(o, j, meanX[t], meanY[t]) -
                                  faceMargin(problem, t, ax, ay, split.delta[t][i][0]);
                const double s1 = faceValue(o, j, meanX[t + 1], meanY[t + 1]) -
                                  faceMargin(problem, t + 1, ax, ay, split.delta[t][i][1]);
                best = std::max(best, std::min(s0, s1));
            }
            if (best < worst) {
                worst = best;
                if (worstT != nullptr) {
                    *worstT = t;
                }
                if (worstI != nullptr) {
                    *worstI = i;
                }
            }
        }
    }
    return worst;
}

double planReportedSlack(const CcProblem& problem, const CcPlan& plan) {
    double worst = kInf;
    for (std::size_t t = 0; t < problem.steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            const PlanObstacle& o = problem.obstacles[i];
            const std::size_t j = plan.face[t][i];
            if (j >= o.faceCount) {
                return -kInf;
            }
            const double ax = o.normalX[j], ay = o.normalY[j];
            const double s0 = faceValue(o, j, plan.meanX[t], plan.meanY[t]) -
                              faceMargin(problem, t, ax, ay, plan.delta[t][i][0]);
            const double s1 = faceValue(o, j, plan.meanX[t + 1], plan.meanY[t + 1]) -
                              faceMargin(problem, t + 1, ax, ay, plan.delta[t][i][1]);
            worst = std::min(worst, std::min(s0, s1));
        }
    }
    return worst;
}

double waypointConstraintSlack(const CcProblem& problem, const double* meanX, const double* meanY,
                               const RiskSplit& split) {
    double worst = kInf;
    const std::size_t n = problem.steps;
    for (std::size_t w = 0; w <= n; ++w) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            double delta = kInf;
            if (w < n) {
                delta = std::min(delta, split.delta[w][i][0]);
            }
            if (w > 0) {
                delta = std::min(delta, split.delta[w - 1][i][1]);
            }
            const PlanObstacle& o = problem.obstacles[i];
            double best = -kInf;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                best = std::max(best, faceValue(o, j, meanX[w], meanY[w]) -
                                          faceMargin(problem, w, o.normalX[j], o.normalY[j], delta));
            }
            worst = std::min(worst, best);
        }
    }
    return worst;
}

double siteBoundViolation(const CcProblem& p, const double* meanX, const double* meanY) {
    double worst = -kInf;
    for (std::size_t t = 1; t < p.steps; ++t) {
        worst = std::max({worst, p.xMin - meanX[t], meanX[t] - p.xMax, p.yMin - meanY[t],
                          meanY[t] - p.yMax});
    }
    return worst;
}

bool meanPathHitsObstacle(const CcProblem& problem, const double* meanX, const double* meanY) {
    for (std::size_t t = 0; t < problem.steps; ++t) {
        for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
            if (segmentIntersectsObstacle(problem.obstacles[i], meanX[t], meanY[t], meanX[t + 1],
                                          meanY[t + 1])) {
                return true;
            }
        }
    }
    return false;
}

double quantile(std::vector<double> values, double q) {
    if (values.empty()) {
        return std::numeric_limits<double>::quiet_NaN();
    }
    std::sort(values.begin(), values.end());
    const double pos = std::clamp(q, 0.0, 1.0) * static_cast<double>(values.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(pos);
    const double frac = pos - static_cast<double>(lo);
    if (frac == 0.0) {
        return values[lo];  // exact, also when the values hold infinities
    }
    return values[lo] + frac * (values[lo + 1] - values[lo]);
}

GapVerdict combineProofs(double cost, const ProofPass& unaided, const ProofPass& aided) {
    GapVerdict v;
    auto gapTo = [&](double reference) {
        return std::isfinite(cost) ? (cost - reference) / reference : std::numeric_limits<double>::infinity();
    };
    auto usable = [](double x) { return std::isfinite(x) && x > 0.0; };
    if (unaided.ran && unaided.proven && usable(unaided.cost)) {
        v.source = GapSource::kProvenUnaided;
        v.reference = unaided.cost;
        v.gap = gapTo(v.reference);
        return v;
    }
    if (aided.ran && aided.proven && usable(aided.cost)) {
        v.source = GapSource::kProvenAided;
        v.reference = aided.cost;
        v.gap = gapTo(v.reference);
        return v;
    }
    if (aided.ran && aided.noneBelowCutoff && usable(aided.cutoff)) {
        v.source = GapSource::kProvenByCutoff;
        v.reference = aided.cutoff;
        v.gap = std::isfinite(cost) ? std::max(0.0, gapTo(v.reference)) : std::numeric_limits<double>::infinity();
        return v;
    }
    double bound = -std::numeric_limits<double>::infinity();
    for (const ProofPass* pass : {&unaided, &aided}) {
        if (pass->ran && usable(pass->bound)) {
            bound = std::max(bound, pass->bound);
        }
    }
    if (usable(bound)) {
        v.source = GapSource::kBound;
        v.reference = bound;
        v.gap = gapTo(bound);
        return v;
    }
    v.gap = std::numeric_limits<double>::quiet_NaN();
    return v;
}

bool proofsConsistent(const ProofPass& a, const ProofPass& b, double tolerance) {
    auto lower = [](const ProofPass& p) {
        double l = -std::numeric_limits<double>::infinity();
        if (!p.ran) {
            return l;
        }
        if (std::isfinite(p.bound)) {
            l = std::max(l, p.bound);
        }
        if (p.noneBelowCutoff && std::isfinite(p.cutoff)) {
            l = std::max(l, p.cutoff);
        }
        if (p.proven && std::isfinite(p.cost)) {
            l = std::max(l, p.cost);
        }
        return l;
    };
    auto check = [&](const ProofPass& p, const ProofPass& other) {
        if (!p.ran || !p.proven || !std::isfinite(p.cost)) {
            return true;
        }
        const double slack = tolerance * std::fabs(p.cost);
        if (p.cost < lower(other) - slack) {
            return false;  // the other pass proved more than this optimum
        }
        return !(other.ran && other.proven && std::isfinite(other.cost) && std::fabs(other.cost - p.cost) > slack);
    };
    return check(a, b) && check(b, a);
}

double cutoffFor(double cost, double tolerance) { return cost * (1.0 + tolerance); }

}  // namespace rse::test::cc
