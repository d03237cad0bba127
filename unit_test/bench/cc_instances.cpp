#include "unit_test/bench/cc_instances.hpp"

#include <algorithm>
#include <cmath>
#include <random>

namespace rse::test::cc {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Seeds that differ in one bit give unrelated streams.
std::uint64_t splitmix64(std::uint64_t x) {
    x += 0x9E3779B97F4A7C15ULL;
    x = (x ^ (x >> 30)) * 0xBF58476D1CE4E5B9ULL;
    x = (x ^ (x >> 27)) * 0x94D049BB133111EBULL;
    return x ^ (x >> 31);
}

class Random {
public:
    explicit Random(std::uint64_t seed) : engine_(splitmix64(seed)) {}
    // [0, 1) from the top 53 bits: the same doubles on every platform.
    double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
    double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }
    std::uint32_t below(std::uint32_t n) { return static_cast<std::uint32_t>(engine_() % n); }

private:
    std::mt19937_64 engine_;
};

struct Placed {
    double cx, cy, radius;
};

bool tryInstance(Random& rng, const InstanceParams& p, CcProblem* out) {
    CcProblem prob;
    prob.steps = p.steps;
    prob.riskBound = p.riskBound;
    prob.xMin = 0.0;
    prob.xMax = p.siteLengthM;
    prob.yMin = 0.0;
    prob.yMax = p.siteWidthM;
    prob.startCov[0] = p.startVarM2;
    prob.startCov[3] = p.startVarM2;
    prob.processSigmaM = p.processSigmaM;
    const double yBand = std::min(3.0, 0.25 * p.siteWidthM);
    prob.startX = rng.uniform(1.0, 1.0 + p.endBandM);
    prob.startY = rng.uniform(yBand, p.siteWidthM - yBand);
    prob.goalX = rng.uniform(p.siteLengthM - 1.0 - p.endBandM, p.siteLengthM - 1.0);
    prob.goalY = rng.uniform(yBand, p.siteWidthM - yBand);

    const double lx = prob.goalX - prob.startX;
    const double ly = prob.goalY - prob.startY;
    const double len = std::hypot(lx, ly);
    const double ux = lx / len, uy = ly / len;

    const std::size_t m = std::min<std::size_t>(p.obstacles, kMaxPlanObstacles);
    const auto onLine = static_cast<std::size_t>(std::ceil(p.onLineFraction * static_cast<double>(m)));
    std::vector<Placed> placed;
    for (std::size_t i = 0; i < m; ++i) {
        bool ok = false;
        for (int attempt = 0; attempt < 400 && !ok; ++attempt) {
            const std::uint32_t span = static_cast<std::uint32_t>(p.maxFaces - p.minFaces + 1);
            const std::size_t faces = p.minFaces + rng.below(span);
            const double r1 = rng.uniform(p.minRadiusM, p.maxRadiusM);
            const double r2 = rng.uniform(p.minRadiusM, p.maxRadiusM);
            const double phi = rng.uniform(0.0, 2.0 * kPi);
            double cx, cy;
            if (i < onLine) {
                const double s = rng.uniform(0.2, 0.8);
                const double off = rng.uniform(-p.onLineOffsetM, p.onLineOffsetM);
                cx = prob.startX + s * lx - off * uy;
                cy = prob.startY + s * ly + off * ux;
            } else {
                cx = rng.uniform(0.0, p.siteLengthM);
                cy = rng.uniform(0.0, p.siteWidthM);
            }
            // Angles: gaps proportional to weights in [0.6, 1.4], so every gap
            // is below pi (the centre is inside) and none degenerate.
            double w[kMaxObstacleFaces];
            double total = 0.0;
            for (std::size_t k = 0; k < faces; ++k) {
                w[k] = rng.uniform(0.6, 1.4);
                total += w[k];
            }
            double angle = rng.uniform(0.0, 2.0 * kPi);
            std::vector<Point> v;
            const double cphi = std::cos(phi), sphi = std::sin(phi);
            for (std::size_t k = 0; k < faces; ++k) {
                const double ex = r1 * std::cos(angle), ey = r2 * std::sin(angle);
                v.push_back({cx + cphi * ex - sphi * ey, cy + sphi * ex + cphi * ey});
                angle += 2.0 * kPi * w[k] / total;
            }
            bool fits = true;
            for (const Point& q : v) {
                if (q.x < p.edgeClearanceM || q.x > p.siteLengthM - p.edgeClearanceM ||
                    q.y < p.edgeClearanceM || q.y > p.siteWidthM - p.edgeClearanceM) {
                    fits = false;
                }
            }
            const double radius = std::max(r1, r2);
            if (i >= onLine) {
                // Distance from the centre to the segment start -> goal.
                const double along = std::clamp((cx - prob.startX) * ux + (cy - prob.startY) * uy, 0.0, len);
                const double dist = std::hypot(cx - (prob.startX + along * ux), cy - (prob.startY + along * uy));
                if (dist < radius + p.offLineClearanceM) {
                    fits = false;
                }
            }
            for (const Placed& o : placed) {
                if (std::hypot(o.cx - cx, o.cy - cy) < o.radius + radius + p.gapM) {
                    fits = false;
                }
            }
            if (!fits) {
                continue;
            }
            PlanObstacle obstacle = obstacleFromVertices(v, static_cast<std::uint8_t>(i + 1));
            if (obstacleVertices(obstacle).empty() ||
                obstacleSlack(obstacle, prob.startX, prob.startY) < p.clearanceM ||
                obstacleSlack(obstacle, prob.goalX, prob.goalY) < p.clearanceM) {
                continue;
            }
            if (i < onLine &&
                !segmentIntersectsObstacle(obstacle, prob.startX, prob.startY, prob.goalX, prob.goalY)) {
                continue;  // an obstacle "on the line" blocks the straight path
            }
            prob.obstacles[i] = obstacle;
            placed.push_back({cx, cy, radius});
            ok = true;
        }
        if (!ok) {
            return false;
        }
    }
    prob.obstacleCount = static_cast<std::uint8_t>(m);
    *out = prob;
    return true;
}

}  // namespace

CcProblem generateInstance(std::uint64_t seed, const InstanceParams& params) {
    CcProblem problem;
    for (std::uint64_t redraw = 0; redraw < 1000; ++redraw) {
        Random rng(redraw == 0 ? seed : splitmix64(seed ^ (redraw * 0xD1B54A32D192ED03ULL)));
        if (tryInstance(rng, params, &problem)) {
            return problem;
        }
    }
    // Parameters that cannot be met: the obstacle-free instance (visible in M = 0).
    Random rng(seed);
    InstanceParams none = params;
    none.obstacles = 0;
    tryInstance(rng, none, &problem);
    return problem;
}

std::vector<CcProblem> provableSet(double riskBound, std::size_t count, std::uint8_t obstacles, std::uint8_t steps) {
    InstanceParams p;
    p.steps = steps;
    p.obstacles = obstacles;
    p.riskBound = riskBound;
    p.onLineFraction = 1.0 / static_cast<double>(std::max<std::uint8_t>(obstacles, 1));
    const std::uint64_t base = obstacles == 4 ? kProvableSeedBase : kProvable8SeedBase;
    std::vector<CcProblem> set;
    for (std::size_t k = 0; k < count; ++k) {
        set.push_back(generateInstance(base + k, p));
    }
    return set;
}

std::vector<CcProblem> largeSet(double riskBound, std::size_t count) {
    InstanceParams p;
    p.steps = 20;
    p.obstacles = 8;
    p.riskBound = riskBound;
    p.onLineFraction = 0.5;
    p.offLineClearanceM = -1e9;
    std::vector<CcProblem> set;
    for (std::size_t k = 0; k < count; ++k) {
        set.push_back(generateInstance(kLargeSeedBase + k, p));
    }
    return set;
}

CcProblem diagonalBoxInstance(double riskBound) {
    CcProblem p;
    p.steps = 4;
    p.startX = 0.0;
    p.startY = 0.0;
    p.goalX = 10.0;
    p.goalY = 10.0;
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    p.processSigmaM = 0.05;
    p.xMin = -2.0;
    p.xMax = 12.0;
    p.yMin = -2.0;
    p.yMax = 12.0;
    p.riskBound = riskBound;
    p.obstacleCount = 1;
    p.obstacles[0] = boxObstacle(2.0, -2.0, 6.0, 4.0, 1);
    return p;
}

}  // namespace rse::test::cc
