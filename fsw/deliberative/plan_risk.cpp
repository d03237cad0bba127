#include "fsw/deliberative/plan_risk.hpp"

#include <cmath>
#include <initializer_list>

#include "fsw/deliberative/gaussian.hpp"

namespace rse::deliberative {

namespace {

// A line with the obstacle on its low side: every interior x has
// nx x + ny y < b. An obstacle face, or the segment's own separating line.
struct SupportLine {
    double nx;
    double ny;
    double b;
};

// One line end: its standardised slack z = (n . mu - b) / sqrt(v), P(E) and v.
struct EndEvent {
    double z;
    double risk;
    double variance;
};

EndEvent endEvent(const CcProblem& p, const SupportLine& l, double x, double y, std::size_t tau, RiskWork* work) {
    const double slack = l.nx * x + l.ny * y - l.b;
    const double v = faceVariance(l.nx, l.ny, p.startCov, p.processSigmaM, static_cast<unsigned>(tau));
    ++work->tails;
    if (!(v > 0.0)) {
        return EndEvent{slack >= 0.0 ? INFINITY : -INFINITY, slack >= 0.0 ? 0.0 : 1.0, 0.0};
    }
    const double z = slack / std::sqrt(v);
    return EndEvent{z, PhiComplement(z), v};
}

// The supporting line of the obstacle parallel to the mean segment, on the
// segment's side: the separating axis that the faces lack when a segment
// passes a corner (both ends beyond the corner's diagonal, each end inside
// one of the two faces' lines). Its normal is the segment's normal n written
// as lambda a_j + mu a_k with lambda, mu >= 0 for two faces j, k, and its
// offset lambda b_j + mu b_k: every interior x then has n . x < that offset,
// exactly, whatever the rounding of lambda and mu (weak duality), so the line
// is valid without the obstacle's vertices. The least offset over face pairs
// is the support (the corner's two faces). False when the segment has no
// length or neither side of it has a pair (rounding at a face normal).
bool segmentLine(const PlanObstacle& o, double x0, double y0, double x1, double y1, SupportLine* out,
                 RiskWork* work) {
    const double dx = x1 - x0;
    const double dy = y1 - y0;
    const double length = std::sqrt(dx * dx + dy * dy);
    if (!(length > 0.0)) {
        return false;
    }
    bool found = false;
    double bestSlack = 0.0;
    for (double side : {1.0, -1.0}) {
        const double nx = -side * dy / length;
        const double ny = side * dx / length;
        bool have = false;
        SupportLine line{0.0, 0.0, 0.0};
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            for (std::size_t k = j + 1; k < o.faceCount; ++k) {
                // n = lambda a_j + mu a_k (Cramer's rule on the 2 x 2 system).
                ++work->lineSolves;
                const double det = o.normalX[j] * o.normalY[k] - o.normalY[j] * o.normalX[k];
                if (!(std::fabs(det) > 1e-12)) {
                    continue;
                }
                const double lambda = (nx * o.normalY[k] - ny * o.normalX[k]) / det;
                const double mu = (o.normalX[j] * ny - o.normalY[j] * nx) / det;
                if (!(lambda >= 0.0 && mu >= 0.0)) {
                    continue;
                }
                const double cx = lambda * o.normalX[j] + mu * o.normalX[k];
                const double cy = lambda * o.normalY[j] + mu * o.normalY[k];
                const double norm = std::sqrt(cx * cx + cy * cy);
                if (!(norm > 0.0)) {
                    continue;
                }
                const SupportLine candidate{cx / norm, cy / norm, (lambda * o.offset[j] + mu * o.offset[k]) / norm};
                if (!have || candidate.b < line.b) {
                    line = candidate;
                    have = true;
                }
            }
        }
        if (!have) {
            continue;
        }
        // Of the two sides, the one the segment lies beyond by more.
        const double slack = line.nx * x0 + line.ny * y0 - line.b;
        if (!found || slack > bestSlack) {
            *out = line;
            bestSlack = slack;
            found = true;
        }
    }
    return found;
}

// a' Sigma_m c for the random walk's Sigma_m = Sigma_0 + m sigma^2 I.
double crossCovariance(const CcProblem& p, double ax, double ay, double cx, double cy, std::size_t m) {
    const double* s = p.startCov;
    return ax * (s[0] * cx + s[1] * cy) + ay * (s[2] * cx + s[3] * cy) +
           static_cast<double>(m) * p.processSigmaM * p.processSigmaM * (ax * cx + ay * cy);
}

// P(E_a(tau) n E_c(tau')) as computed (within kBivariateAbsError), capped by
// the smaller of the two events.
double orthant(const CcProblem& p, const SupportLine& a, const EndEvent& ea, std::size_t tauA, const SupportLine& c,
               const EndEvent& ec, std::size_t tauC, RiskWork* work) {
    const std::size_t m = tauA < tauC ? tauA : tauC;
    const double cov = crossCovariance(p, a.nx, a.ny, c.nx, c.ny, m);
    const double rho = cov / std::sqrt(ea.variance * ec.variance);
    ++work->orthants;
    const double q = bivariateUpperTail(ea.z, ec.z, rho);
    const double cap = ea.risk < ec.risk ? ea.risk : ec.risk;
    return q < cap ? q : cap;
}

}  // namespace

double pairRiskBound(const CcProblem& p, const double* mx, const double* my, std::size_t t, std::size_t i,
                     RiskWork* work) {
    RiskWork local;
    RiskWork* w = work != nullptr ? work : &local;
    const PlanObstacle& o = p.obstacles[i];
    // The obstacle's faces first; the segment's own line only where they
    // leave a risk worth refining (most pairs are far from their obstacle:
    // their first face is many sigma clear and the line's 2x2 solves would
    // be wasted in the planner's every evaluation).
    SupportLine lines[kMaxObstacleFaces + 1];
    EndEvent e0[kMaxObstacleFaces + 1];
    EndEvent e1[kMaxObstacleFaces + 1];
    double best = 1.0;
    std::size_t anchor = 0;
    bool random = true;  // every end has variance (the orthants apply)
    // P(E_j(t) u E_j(t+1)) of line j, kept as the anchor when it is the least.
    auto consider = [&](std::size_t j) {
        e0[j] = endEvent(p, lines[j], mx[t], my[t], t, w);
        e1[j] = endEvent(p, lines[j], mx[t + 1], my[t + 1], t + 1, w);
        double u = e0[j].risk + e1[j].risk;
        if (e0[j].variance > 0.0 && e1[j].variance > 0.0) {
            if (u > kNegligibleRisk) {
                // Same line at t and t + 1 (correlation sqrt(v_t / v_{t+1})):
                // the intersection taken low by its error, so the union is high.
                const double both = orthant(p, lines[j], e0[j], t, lines[j], e1[j], t + 1, w) - kBivariateAbsError;
                u = both > 0.0 ? u - both : u;
            }
        } else {
            random = false;
        }
        u = u < 1.0 ? u : 1.0;
        if (u < best) {
            best = u;
            anchor = j;
        }
    };
    std::size_t lineCount = 0;
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        lines[lineCount] = SupportLine{o.normalX[j], o.normalY[j], o.offset[j]};
        consider(lineCount++);
    }
    if (!(best > kNegligibleRisk)) {
        return best;
    }
    if (segmentLine(o, mx[t], my[t], mx[t + 1], my[t + 1], &lines[lineCount], w)) {
        consider(lineCount++);
    }
    if (!random || !(best > kNegligibleRisk)) {
        return best;
    }
    const EndEvent* anchorEnd[2] = {&e0[anchor], &e1[anchor]};
    for (std::size_t k = 0; k < lineCount; ++k) {
        if (k == anchor) {
            continue;
        }
        const EndEvent* otherEnd[2] = {&e0[k], &e1[k]};
        double sum = 0.0;
        for (std::size_t a = 0; a < 2 && sum < best; ++a) {
            for (std::size_t c = 0; c < 2 && sum < best; ++c) {
                sum += orthant(p, lines[anchor], *anchorEnd[a], t + a, lines[k], *otherEnd[c], t + c, w) +
                       kBivariateAbsError;
            }
        }
        best = sum < best ? sum : best;
    }
    return best;
}

double segmentRiskBound(const CcProblem& p, const double* mx, const double* my, std::size_t t,
                        const double* capPerPair, RiskWork* work) {
    double sum = 0.0;
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        double r = pairRiskBound(p, mx, my, t, i, work);
        if (capPerPair != nullptr && capPerPair[i] < r) {
            r = capPerPair[i];
        }
        sum += r;
    }
    return sum;
}

double planRiskBound(const CcProblem& p, const double* mx, const double* my, double* segmentRisk, RiskWork* work) {
    double total = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        const double r = segmentRiskBound(p, mx, my, t, nullptr, work);
        if (segmentRisk != nullptr) {
            segmentRisk[t] = r;
        }
        total += r;
    }
    return total;
}

double certifiedSegmentRisk(const CcProblem& p, const CcPlan& plan, std::size_t t, RiskWork* work) {
    double cap[kMaxPlanObstacles];
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        cap[i] = plan.delta[t][i][0] + plan.delta[t][i][1];
    }
    return segmentRiskBound(p, plan.meanX, plan.meanY, t, cap, work);
}

double certifiedPlanRisk(const CcProblem& p, const CcPlan& plan, double* segmentRisk, RiskWork* work) {
    double total = 0.0;
    for (std::size_t t = 0; t < p.steps; ++t) {
        const double r = certifiedSegmentRisk(p, plan, t, work);
        if (segmentRisk != nullptr) {
            segmentRisk[t] = r;
        }
        total += r;
    }
    return total;
}

}  // namespace rse::deliberative
