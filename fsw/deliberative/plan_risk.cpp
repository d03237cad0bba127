#include "fsw/deliberative/plan_risk.hpp"

#include <cmath>

#include "fsw/deliberative/gaussian.hpp"

namespace rse::deliberative {

namespace {

// One face end: its standardised slack z = (a . mu - b) / sqrt(v), P(E) and v.
struct EndEvent {
    double z;
    double risk;
    double variance;
};

EndEvent endEvent(const CcProblem& p, const PlanObstacle& o, std::size_t j, double x, double y, std::size_t tau,
                  RiskWork* work) {
    const double slack = o.normalX[j] * x + o.normalY[j] * y - o.offset[j];
    const double v = faceVariance(o.normalX[j], o.normalY[j], p.startCov, p.processSigmaM, static_cast<unsigned>(tau));
    ++work->tails;
    if (!(v > 0.0)) {
        return EndEvent{slack >= 0.0 ? INFINITY : -INFINITY, slack >= 0.0 ? 0.0 : 1.0, 0.0};
    }
    const double z = slack / std::sqrt(v);
    return EndEvent{z, PhiComplement(z), v};
}

// a' Sigma_m c for the random walk's Sigma_m = Sigma_0 + m sigma^2 I.
double crossCovariance(const CcProblem& p, double ax, double ay, double cx, double cy, std::size_t m) {
    const double* s = p.startCov;
    return ax * (s[0] * cx + s[1] * cy) + ay * (s[2] * cx + s[3] * cy) +
           static_cast<double>(m) * p.processSigmaM * p.processSigmaM * (ax * cx + ay * cy);
}

// P(E_a(tau) n E_c(tau')) as computed (within kBivariateAbsError), capped by
// the smaller of the two events.
double orthant(const CcProblem& p, const PlanObstacle& o, std::size_t a, const EndEvent& ea, std::size_t tauA,
               std::size_t c, const EndEvent& ec, std::size_t tauC, RiskWork* work) {
    const std::size_t m = tauA < tauC ? tauA : tauC;
    const double cov = crossCovariance(p, o.normalX[a], o.normalY[a], o.normalX[c], o.normalY[c], m);
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
    EndEvent e0[kMaxObstacleFaces];
    EndEvent e1[kMaxObstacleFaces];
    double best = 1.0;
    std::size_t anchor = 0;
    bool random = true;  // every end has variance (the orthants apply)
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        e0[j] = endEvent(p, o, j, mx[t], my[t], t, w);
        e1[j] = endEvent(p, o, j, mx[t + 1], my[t + 1], t + 1, w);
        double u = e0[j].risk + e1[j].risk;
        if (e0[j].variance > 0.0 && e1[j].variance > 0.0) {
            if (u > kNegligibleRisk) {
                // Same face at t and t + 1 (correlation sqrt(v_t / v_{t+1})):
                // the intersection taken low by its error, so the union is high.
                const double both = orthant(p, o, j, e0[j], t, j, e1[j], t + 1, w) - kBivariateAbsError;
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
    }
    if (!random || !(best > kNegligibleRisk)) {
        return best;
    }
    const EndEvent* anchorEnd[2] = {&e0[anchor], &e1[anchor]};
    for (std::size_t k = 0; k < o.faceCount; ++k) {
        if (k == anchor) {
            continue;
        }
        const EndEvent* otherEnd[2] = {&e0[k], &e1[k]};
        double sum = 0.0;
        for (std::size_t a = 0; a < 2 && sum < best; ++a) {
            for (std::size_t c = 0; c < 2 && sum < best; ++c) {
                sum += orthant(p, o, anchor, *anchorEnd[a], t + a, k, *otherEnd[c], t + c, w) + kBivariateAbsError;
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
