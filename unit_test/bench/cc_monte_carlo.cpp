#include "unit_test/bench/cc_monte_carlo.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

namespace rse::test::cc {

namespace {

// Continued fraction of the incomplete beta (modified Lentz).
double betaContinuedFraction(double a, double b, double x) {
    constexpr double kTiny = 1e-300;
    const double qab = a + b, qap = a + 1.0, qam = a - 1.0;
    double c = 1.0;
    double d = 1.0 - qab * x / qap;
    if (std::fabs(d) < kTiny) {
        d = kTiny;
    }
    d = 1.0 / d;
    double h = d;
    for (int m = 1; m <= 10000; ++m) {
        const double m2 = 2.0 * m;
        double aa = m * (b - m) * x / ((qam + m2) * (a + m2));
        d = 1.0 + aa * d;
        d = std::fabs(d) < kTiny ? kTiny : d;
        c = 1.0 + aa / c;
        c = std::fabs(c) < kTiny ? kTiny : c;
        d = 1.0 / d;
        h *= d * c;
        aa = -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2));
        d = 1.0 + aa * d;
        d = std::fabs(d) < kTiny ? kTiny : d;
        c = 1.0 + aa / c;
        c = std::fabs(c) < kTiny ? kTiny : c;
        d = 1.0 / d;
        const double del = d * c;
        h *= del;
        if (std::fabs(del - 1.0) < 1e-15) {
            break;
        }
    }
    return h;
}

// Regularised incomplete beta I_x(a, b).
double incompleteBeta(double a, double b, double x) {
    if (x <= 0.0) {
        return 0.0;
    }
    if (x >= 1.0) {
        return 1.0;
    }
    const double lnFront = std::lgamma(a + b) - std::lgamma(a) - std::lgamma(b) + a * std::log(x) +
                           b * std::log1p(-x);
    const double front = std::exp(lnFront);
    if (x < (a + 1.0) / (a + b + 2.0)) {
        return front * betaContinuedFraction(a, b, x) / a;
    }
    return 1.0 - front * betaContinuedFraction(b, a, 1.0 - x) / b;
}

struct Box {
    double x0, y0, x1, y1;
};

}  // namespace

double binomialCdf(std::size_t k, std::size_t n, double p) {
    if (k >= n) {
        return 1.0;
    }
    // P(X <= k) = I_{1-p}(n - k, k + 1).
    return incompleteBeta(static_cast<double>(n - k), static_cast<double>(k) + 1.0, 1.0 - p);
}

double clopperPearsonUpper(std::size_t k, std::size_t n, double confidence) {
    if (n == 0 || k >= n) {
        return 1.0;
    }
    const double alpha = 1.0 - confidence;
    double lo = static_cast<double>(k) / static_cast<double>(n), hi = 1.0;
    for (int it = 0; it < 200 && hi - lo > 1e-15 * hi; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (binomialCdf(k, n, mid) > alpha) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    return hi;
}

double wilsonUpper(std::size_t k, std::size_t n, double confidence) {
    if (n == 0) {
        return 1.0;
    }
    const double z = normalQuantile(confidence);
    const double nn = static_cast<double>(n);
    const double phat = static_cast<double>(k) / nn;
    const double z2 = z * z;
    const double centre = phat + z2 / (2.0 * nn);
    const double spread = z * std::sqrt(phat * (1.0 - phat) / nn + z2 / (4.0 * nn * nn));
    return std::min(1.0, (centre + spread) / (1.0 + z2 / nn));
}

McResult monteCarloCollision(const CcProblem& problem, const double* meanX, const double* meanY,
                             const McOptions& options) {
    const auto begin = std::chrono::steady_clock::now();
    McResult r;
    r.samples = options.samples;
    const std::size_t n = std::min<std::size_t>(problem.steps, kMaxPlanSteps);
    const std::size_t m = std::min<std::size_t>(problem.obstacleCount, kMaxPlanObstacles);

    // Cholesky of Sigma_0 (PSD, possibly singular).
    const double* s = problem.startCov;
    const double l11 = std::sqrt(std::max(0.0, s[0]));
    const double l21 = l11 > 0.0 ? s[2] / l11 : 0.0;
    const double l22 = std::sqrt(std::max(0.0, s[3] - l21 * l21));
    const double sigma = problem.processSigmaM;

    Box boxes[kMaxPlanObstacles];
    for (std::size_t i = 0; i < m; ++i) {
        const std::vector<Point> v = obstacleVertices(problem.obstacles[i]);
        Box b{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity(),
              -std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity()};
        for (const Point& q : v) {
            b.x0 = std::min(b.x0, q.x);
            b.y0 = std::min(b.y0, q.y);
            b.x1 = std::max(b.x1, q.x);
            b.y1 = std::max(b.y1, q.y);
        }
        if (v.empty()) {  // not a closed polygon: no box, test every segment
            b = {-std::numeric_limits<double>::infinity(), -std::numeric_limits<double>::infinity(),
                 std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
        }
        boxes[i] = b;
    }

    std::mt19937_64 engine(options.seed);
    std::normal_distribution<double> normal(0.0, 1.0);
    double x[kMaxPlanSteps + 1];
    double y[kMaxPlanSteps + 1];
    for (std::size_t k = 0; k < options.samples; ++k) {
        const double z1 = normal(engine), z2 = normal(engine);
        x[0] = meanX[0] + l11 * z1;
        y[0] = meanY[0] + l21 * z1 + l22 * z2;
        for (std::size_t t = 0; t < n; ++t) {
            const double w1 = normal(engine), w2 = normal(engine);
            x[t + 1] = x[t] + (meanX[t + 1] - meanX[t]) + sigma * w1;
            y[t + 1] = y[t] + (meanY[t + 1] - meanY[t]) + sigma * w2;
        }
        bool hit = false;
        for (std::size_t i = 0; i < m; ++i) {
            const Box& b = boxes[i];
            bool hitThis = false;
            for (std::size_t t = 0; t < n && !hitThis; ++t) {
                if (std::max(x[t], x[t + 1]) <= b.x0 || std::min(x[t], x[t + 1]) >= b.x1 ||
                    std::max(y[t], y[t + 1]) <= b.y0 || std::min(y[t], y[t + 1]) >= b.y1) {
                    continue;
                }
                hitThis = segmentIntersectsObstacle(problem.obstacles[i], x[t], y[t], x[t + 1], y[t + 1]);
            }
            if (hitThis) {
                ++r.collisionsPerObstacle[i];
                hit = true;
            }
        }
        if (hit) {
            ++r.collisions;
            bool pointHit = false;
            for (std::size_t t = 0; t <= n && !pointHit; ++t) {
                for (std::size_t i = 0; i < m && !pointHit; ++i) {
                    pointHit = pointInObstacle(problem.obstacles[i], x[t], y[t]);
                }
            }
            // A waypoint inside means its segments meet the obstacle too, so
            // waypoint collisions are a subset of segment collisions.
            if (pointHit) {
                ++r.waypointCollisions;
            }
        }
    }
    r.rate = options.samples > 0 ? static_cast<double>(r.collisions) / static_cast<double>(options.samples) : 0.0;
    r.upperClopperPearson = clopperPearsonUpper(r.collisions, options.samples, options.confidence);
    r.upperWilson = wilsonUpper(r.collisions, options.samples, options.confidence);
    r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    return r;
}

McResult monteCarloCollision(const CcProblem& problem, const CcPlan& plan, const McOptions& options) {
    return monteCarloCollision(problem, plan.meanX, plan.meanY, options);
}

std::size_t allowedCollisions(double riskBound, std::size_t samples) {
    const double n = static_cast<double>(samples);
    return static_cast<std::size_t>(std::floor(n * riskBound + 4.0 * std::sqrt(n * riskBound * (1.0 - riskBound))));
}

std::size_t monteCarloSamples(double riskBound, std::size_t minimum) {
    if (!(riskBound > 0.0)) {
        return minimum;
    }
    return std::max(minimum, static_cast<std::size_t>(std::ceil(500.0 / riskBound)));
}

Conservatism conservatism(double riskBound, const McResult& result) {
    Conservatism c;
    if (result.collisions > 0) {
        c.ratio = riskBound / result.rate;
    } else {
        c.ratio = riskBound / result.upperClopperPearson;
        c.lowerBound = true;
    }
    return c;
}

}  // namespace rse::test::cc
