// Test helpers for the chance-constrained planner: obstacles, problems, exact
// geometric checks and a seeded instance generator (boxes and rotated convex
// polygons between a start and a goal), header-only.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <random>

#include "fsw/deliberative/cc_problem.hpp"

namespace rse::test {

using deliberative::CcProblem;
using deliberative::PlanObstacle;

// Faces in the order right, top, left, bottom.
inline PlanObstacle makeBox(std::uint8_t id, double xmin, double xmax, double ymin, double ymax) {
    PlanObstacle o;
    o.id = id;
    o.faceCount = 4;
    o.normalX[0] = 1.0;
    o.normalY[0] = 0.0;
    o.offset[0] = xmax;
    o.normalX[1] = 0.0;
    o.normalY[1] = 1.0;
    o.offset[1] = ymax;
    o.normalX[2] = -1.0;
    o.normalY[2] = 0.0;
    o.offset[2] = -xmin;
    o.normalX[3] = 0.0;
    o.normalY[3] = -1.0;
    o.offset[3] = -ymin;
    return o;
}

// Regular polygon of `faces` faces around (cx, cy), inradius r, first normal at
// angle `rotation`.
inline PlanObstacle makePolygon(std::uint8_t id, double cx, double cy, double r, std::uint8_t faces, double rotation) {
    PlanObstacle o;
    o.id = id;
    o.faceCount = faces;
    for (std::size_t j = 0; j < faces; ++j) {
        const double a = rotation + 2.0 * M_PI * static_cast<double>(j) / faces;
        o.normalX[j] = std::cos(a);
        o.normalY[j] = std::sin(a);
        o.offset[j] = o.normalX[j] * cx + o.normalY[j] * cy + r;
    }
    return o;
}

inline CcProblem makeProblem(std::uint8_t steps, double sx, double sy, double gx, double gy, double xmin, double xmax,
                             double ymin, double ymax) {
    CcProblem p;
    p.steps = steps;
    p.startX = sx;
    p.startY = sy;
    p.goalX = gx;
    p.goalY = gy;
    p.xMin = xmin;
    p.xMax = xmax;
    p.yMin = ymin;
    p.yMax = ymax;
    p.riskBound = 0.01;
    p.processSigmaM = 0.0;
    return p;
}

// How deep the closed segment [p, q] enters obstacle o: the largest, over the
// segment's points, of min_j (b_j - a_j . x) (> 0 inside). Exact: the function
// is concave along the segment, maximised by a short ternary-free search over
// the breakpoints (each pair of faces) and the ends.
inline double segmentPenetration(const PlanObstacle& o, double px, double py, double qx, double qy) {
    auto depthAt = [&](double s) {
        const double x = px + s * (qx - px);
        const double y = py + s * (qy - py);
        double d = INFINITY;
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            const double v = o.offset[j] - (o.normalX[j] * x + o.normalY[j] * y);
            d = v < d ? v : d;
        }
        return d;
    };
    double best = depthAt(0.0);
    const double e = depthAt(1.0);
    best = e > best ? e : best;
    // Breakpoints where two faces' values cross.
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        for (std::size_t k = j + 1; k < o.faceCount; ++k) {
            const double fj0 = o.offset[j] - (o.normalX[j] * px + o.normalY[j] * py);
            const double fk0 = o.offset[k] - (o.normalX[k] * px + o.normalY[k] * py);
            const double fj1 = o.offset[j] - (o.normalX[j] * qx + o.normalY[j] * qy);
            const double fk1 = o.offset[k] - (o.normalX[k] * qx + o.normalY[k] * qy);
            const double den = (fj1 - fj0) - (fk1 - fk0);
            if (std::fabs(den) < 1e-15) {
                continue;
            }
            const double s = (fk0 - fj0) / den;
            if (s > 0.0 && s < 1.0) {
                const double v = depthAt(s);
                best = v > best ? v : best;
            }
        }
    }
    return best;
}

// Random instance: `m` obstacles (boxes and 3..8-gons, inradius 0.75..2 m) in
// a 30 x 20 m site, start on the left, goal on the right, the obstacles'
// centres within 3 m of the line between them (so that most are in the way),
// placed so that neither start nor goal lies within 1.5 m of an obstacle.
// sigma = 0.05 m per step and Sigma_0 = 0.01 m^2 I give margins of a few
// decimetres.
inline CcProblem randomInstance(std::uint64_t seed, std::uint8_t steps, std::uint8_t m, double riskBound) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(0.0, 1.0);
    CcProblem p = makeProblem(steps, 1.0 + 2.0 * u(rng), 3.0 + 14.0 * u(rng), 27.0 + 2.0 * u(rng),
                              3.0 + 14.0 * u(rng), 0.0, 30.0, 0.0, 20.0);
    p.riskBound = riskBound;
    p.processSigmaM = 0.05;
    p.startCov[0] = 0.01;
    p.startCov[3] = 0.01;
    std::size_t placed = 0;
    for (int attempt = 0; attempt < 1000 && placed < m; ++attempt) {
        const double along = 0.15 + 0.7 * u(rng);
        const double across = 6.0 * u(rng) - 3.0;
        const double lx = p.goalX - p.startX;
        const double ly = p.goalY - p.startY;
        const double len = std::sqrt(lx * lx + ly * ly);
        const double cx = p.startX + along * lx - across * ly / len;
        const double cy = p.startY + along * ly + across * lx / len;
        const double r = 0.75 + 1.25 * u(rng);
        PlanObstacle o;
        if (u(rng) < 0.5) {
            const double w = r * (0.6 + 0.8 * u(rng));
            const double h = r * (0.6 + 0.8 * u(rng));
            o = makeBox(static_cast<std::uint8_t>(placed), cx - w, cx + w, cy - h, cy + h);
        } else {
            const std::uint8_t faces = static_cast<std::uint8_t>(3 + rng() % 6);
            o = makePolygon(static_cast<std::uint8_t>(placed), cx, cy, r, faces, 2.0 * M_PI * u(rng));
        }
        auto clearOf = [&](double x, double y) {
            double d = -INFINITY;  // signed distance to the obstacle's faces
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double v = o.normalX[j] * x + o.normalY[j] * y - o.offset[j];
                d = v > d ? v : d;
            }
            return d > 1.5;
        };
        if (!clearOf(p.startX, p.startY) || !clearOf(p.goalX, p.goalY)) {
            continue;
        }
        p.obstacles[placed++] = o;
    }
    p.obstacleCount = static_cast<std::uint8_t>(placed);
    return p;
}

}  // namespace rse::test
