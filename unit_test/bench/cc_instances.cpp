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

// A convex polygon of `faces` vertices on the ellipse (r1, r2) turned by phi
// about (cx, cy): angle gaps proportional to weights in [0.6, 1.4], so every
// gap is below pi (the centre is inside) and none degenerate.
std::vector<Point> ellipsePolygon(Random& rng, std::size_t faces, double cx, double cy, double r1, double r2,
                                  double phi) {
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
    return v;
}

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
            const std::vector<Point> v = ellipsePolygon(rng, faces, cx, cy, r1, r2, phi);
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

// ---------------------------------------------------------------------------
// Hard instances (cc_instances.hpp).

namespace rse::test::cc {

namespace {

// The largest margin at step t over all directions for M obstacles (the even
// split's delta with M = kMaxPlanObstacles, so never smaller than the real one).
double worstMargin(const CcProblem& p, std::size_t t) {
    double cov[4];
    stepCovariance(p, t, cov);
    const double mean = 0.5 * (cov[0] + cov[3]);
    const double dev = std::sqrt(0.25 * (cov[0] - cov[3]) * (cov[0] - cov[3]) + cov[1] * cov[2]);
    const double delta = p.riskBound / (2.0 * static_cast<double>(p.steps) * static_cast<double>(kMaxPlanObstacles));
    return normalUpperQuantile(delta) * std::sqrt(mean + dev);
}

PlanObstacle randomPolygon(Random& rng, double cx, double cy, double rMin, double rMax, std::uint8_t id) {
    const std::size_t faces = 3 + rng.below(6);  // 3 .. 8
    const double r1 = rng.uniform(rMin, rMax);
    const double r2 = rng.uniform(rMin, rMax);
    const double phi = rng.uniform(0.0, 2.0 * kPi);
    return obstacleFromVertices(ellipsePolygon(rng, faces, cx, cy, r1, r2, phi), id);
}

void addObstacle(CcProblem* p, const PlanObstacle& o) {
    p->obstacles[p->obstacleCount] = o;
    p->obstacles[p->obstacleCount].id = static_cast<std::uint8_t>(p->obstacleCount + 1);
    ++p->obstacleCount;
}

// A U of three overlapping boxes around (x, y) opening towards -dir (dir = +1:
// the back wall is at +x): inner half-width h, depth d behind and arm length a.
void addU(CcProblem* p, double x, double y, double dir, double h, double back, double front) {
    const double t = 1.0;  // wall thickness
    const double xb0 = x + dir * back;           // inner face of the back wall
    const double xb1 = xb0 + dir * t;
    const double xf = x - dir * front;           // open end of the arms
    const double lo = std::min(xf, xb1), hi = std::max(xf, xb1);
    addObstacle(p, boxObstacle(std::min(xb0, xb1), y - h - t, std::max(xb0, xb1), y + h + t, 0));
    addObstacle(p, boxObstacle(lo, y + h, hi, y + h + t, 0));
    addObstacle(p, boxObstacle(lo, y - h - t, hi, y - h, 0));
}

bool tryHard(Random& rng, HardKind kind, std::uint8_t minSteps, std::uint8_t maxSteps, HardInstance* out) {
    HardInstance h;
    h.kind = kind;
    CcProblem& p = h.problem;
    p.steps = static_cast<std::uint8_t>(minSteps + rng.below(static_cast<std::uint32_t>(maxSteps - minSteps + 1)));
    p.riskBound = std::pow(10.0, -rng.uniform(1.0, 4.0));
    p.processSigmaM = rng.uniform(0.02, 0.2);
    const double vx = rng.uniform(0.005, 0.05), vy = rng.uniform(0.005, 0.05);
    const double rho = rng.uniform(-0.8, 0.8);
    p.startCov[0] = vx;
    p.startCov[3] = vy;
    p.startCov[1] = p.startCov[2] = rho * std::sqrt(vx * vy);
    const std::size_t n = p.steps;
    const double m0 = worstMargin(p, 0), mN = worstMargin(p, n);
    std::vector<Point> w;  // the witness's legs, from the start; the rest parks at the goal
    if (kind == HardKind::kGap) {
        p.xMin = 0.0, p.xMax = 30.0, p.yMin = 0.0, p.yMax = 20.0;
        // One or two walls (thickness 1 .. 4 m); wall k is passed at steps
        // 2k + 1 -> 2k + 2, its half gap a little above the margin there.
        const std::size_t walls = 1 + rng.below(2);
        const double thick[2] = {rng.uniform(0.5, 2.0), rng.uniform(0.5, 2.0)};
        const double wall[2] = {rng.uniform(8.0, 13.0), rng.uniform(17.0, 21.0)};
        p.startX = rng.uniform(1.0, 5.0), p.startY = rng.uniform(2.0, 18.0);
        p.goalX = rng.uniform(25.0, 29.0), p.goalY = rng.uniform(2.0, 18.0);
        w = {{p.startX, p.startY}};
        for (std::size_t k = 0; k < walls; ++k) {
            const double gapY = rng.uniform(4.0, 16.0);
            const double m = worstMargin(p, std::min<std::size_t>(2 * k + 2, n));
            const double half = m * rng.uniform(1.01, 1.15) + 0.01;
            addObstacle(&p, boxObstacle(wall[k] - thick[k], -2.0, wall[k] + thick[k], gapY - half, 0));
            addObstacle(&p, boxObstacle(wall[k] - thick[k], gapY + half, wall[k] + thick[k], 22.0, 0));
            // Buttresses overlap the boxes; the witness check keeps the gap open.
            addObstacle(&p, randomPolygon(rng, wall[k] + rng.uniform(-2.0, 2.0), rng.uniform(0.0, gapY - half - 2.0),
                                          1.5, 3.0, 0));
            addObstacle(&p, randomPolygon(rng, wall[k] + rng.uniform(-2.0, 2.0), rng.uniform(gapY + half + 2.0, 20.0),
                                          1.5, 3.0, 0));
            const double c = thick[k] + m + 0.05;
            w.push_back({wall[k] - c, gapY});
            w.push_back({wall[k] + c, gapY});
        }
        w.push_back({p.goalX, p.goalY});
    } else if (kind == HardKind::kConcave) {
        const double clear = mN * 1.1 + 0.3;
        const double hu = clear + rng.uniform(0.2, 1.5);      // inner half-width
        const double back = m0 * 1.1 + rng.uniform(0.2, 1.5);
        const double front = rng.uniform(1.0, 3.0);
        const double span = 2.0 * (back + front + 1.0 + clear) + rng.uniform(6.0, 16.0);
        p.xMin = 0.0, p.xMax = span + 2.0 * (front + clear + 1.0), p.yMin = 0.0, p.yMax = 4.0 * (hu + 1.0 + clear) + 4.0;
        p.startX = front + clear + 1.0, p.startY = rng.uniform(0.3, 0.7) * p.yMax;
        p.goalX = p.xMax - (front + clear + 1.0), p.goalY = rng.uniform(0.3, 0.7) * p.yMax;
        addU(&p, p.startX, p.startY, +1.0, hu, back, front);
        const bool goalU = rng.below(2) == 1;
        const double top = hu + 1.0 + clear;
        const double sOut = p.startX - front - clear, sBack = p.startX + back + 1.0 + clear;
        const double sideS = p.goalY >= p.startY ? 1.0 : -1.0;
        w = {{p.startX, p.startY}, {sOut, p.startY}, {sOut, p.startY + sideS * top}, {sBack, p.startY + sideS * top}};
        if (goalU) {
            addU(&p, p.goalX, p.goalY, -1.0, hu, back, front);
            const double gOut = p.goalX + front + clear, gBack = p.goalX - back - 1.0 - clear;
            const double sideG = p.startY >= p.goalY ? 1.0 : -1.0;
            w.push_back({gBack, p.goalY + sideG * top});
            w.push_back({gOut, p.goalY + sideG * top});
            w.push_back({gOut, p.goalY});
        }
        w.push_back({p.goalX, p.goalY});
    } else {
        p.xMin = 0.0, p.xMax = 30.0, p.yMin = 0.0, p.yMax = 20.0;
        p.startX = rng.uniform(1.0, 5.0), p.startY = rng.uniform(3.0, 17.0);
        p.goalX = rng.uniform(25.0, 29.0), p.goalY = rng.uniform(3.0, 17.0);
        const std::size_t m = 4 + rng.below(5);
        for (std::size_t i = 0; i < m; ++i) {
            const double s = rng.uniform(0.15, 0.85);
            const double cx = p.startX + s * (p.goalX - p.startX) + rng.uniform(-4.0, 4.0);
            const double cy = p.startY + s * (p.goalY - p.startY) + rng.uniform(-6.0, 6.0);
            const PlanObstacle o = randomPolygon(rng, cx, cy, 1.5, 5.0, 0);
            if (obstacleSlack(o, p.startX, p.startY) > m0 * 1.05 + 0.01 &&
                obstacleSlack(o, p.goalX, p.goalY) > mN * 1.05 + 0.01) {
                addObstacle(&p, o);
            }
        }
        if (p.obstacleCount < 4) {
            return false;
        }
    }
    if (kind != HardKind::kClutter) {
        if (w.size() - 1 > n) {
            return false;
        }
        // Clutter that leaves the witness intact.
        const std::size_t extra = rng.below(3);
        std::size_t tau = 0;
        for (; tau < w.size(); ++tau) {
            h.witnessX[tau] = w[tau].x, h.witnessY[tau] = w[tau].y;
        }
        for (; tau <= n; ++tau) {
            h.witnessX[tau] = p.goalX, h.witnessY[tau] = p.goalY;
        }
        for (std::size_t k = 0; k < extra && p.obstacleCount < kMaxPlanObstacles; ++k) {
            addObstacle(&p, randomPolygon(rng, rng.uniform(p.xMin, p.xMax), rng.uniform(p.yMin, p.yMax), 1.0, 3.0, 0));
            if (segmentConstraintSlack(p, h.witnessX, h.witnessY, evenSplit(p)) < 1e-6) {
                --p.obstacleCount;  // it would block the witness
            }
        }
        for (std::size_t k = 1; k < n; ++k) {
            if (h.witnessX[k] < p.xMin || h.witnessX[k] > p.xMax || h.witnessY[k] < p.yMin || h.witnessY[k] > p.yMax) {
                return false;
            }
        }
        if (segmentConstraintSlack(p, h.witnessX, h.witnessY, evenSplit(p)) < 1e-6) {
            return false;
        }
        h.hasWitness = true;
    }
    if (!validateProblem(p).empty()) {
        return false;
    }
    *out = h;
    return true;
}

}  // namespace

HardInstance hardInstance(std::uint64_t seed, std::uint8_t minSteps, std::uint8_t maxSteps) {
    const auto kind = static_cast<HardKind>(seed % 3);
    maxSteps = std::min<std::uint8_t>(maxSteps, static_cast<std::uint8_t>(kMaxPlanSteps));
    minSteps = std::min(minSteps, maxSteps);
    HardInstance h;
    for (std::uint64_t redraw = 0; redraw < 10000; ++redraw) {
        Random rng(redraw == 0 ? seed : splitmix64(seed ^ (redraw * 0xD1B54A32D192ED03ULL)));
        if (tryHard(rng, kind, minSteps, maxSteps, &h)) {
            return h;
        }
    }
    return h;
}

std::vector<HardInstance> hardSet(std::size_t count, std::uint64_t base, std::uint8_t minSteps, std::uint8_t maxSteps) {
    std::vector<HardInstance> set;
    for (std::size_t k = 0; k < count; ++k) {
        set.push_back(hardInstance(base + k, minSteps, maxSteps));
    }
    return set;
}

}  // namespace rse::test::cc
