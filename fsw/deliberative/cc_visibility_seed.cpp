#include "fsw/deliberative/cc_visibility_seed.hpp"

#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"

namespace rse::deliberative {

namespace {
double euclidean(double dx, double dy) { return std::sqrt(dx * dx + dy * dy); }
}  // namespace

bool CcVisibilitySeed::insideInflated(const CcProblem& problem, std::size_t i, double x, double y,
                                      double tol) const {
    const PlanObstacle& o = problem.obstacles[i];
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        if (o.normalX[j] * x + o.normalY[j] * y >= inflated_[i][j] - tol) {
            return false;
        }
    }
    return true;
}

bool CcVisibilitySeed::onBoundaryOf(const CcProblem& problem, std::size_t i, double x, double y) const {
    const PlanObstacle& o = problem.obstacles[i];
    for (std::size_t l = 0; l < o.faceCount; ++l) {
        if (o.normalX[l] * x + o.normalY[l] * y > inflated_[i][l] + 1e-7) {
            return false;
        }
    }
    return true;
}

bool CcVisibilitySeed::build(const CcProblem& problem, const CcEndMargins& margins, std::size_t tauInflate,
                             std::uint64_t* work) {
    const std::size_t obstacles = problem.obstacleCount;
    for (std::size_t i = 0; i < obstacles; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            inflated_[i][j] = o.offset[j] + margins.margin(tauInflate, i, j) + kSeedInflateM;
        }
    }
    for (std::size_t i = 0; i < obstacles; ++i) {
        if (insideInflated(problem, i, problem.startX, problem.startY, kSeedTouchM) ||
            insideInflated(problem, i, problem.goalX, problem.goalY, kSeedTouchM)) {
            return false;
        }
    }
    vx_[0] = problem.startX;
    vy_[0] = problem.startY;
    vx_[1] = problem.goalX;
    vy_[1] = problem.goalY;
    vertexCount_ = 2;
    Lines lines;
    collectLines(problem, &lines);
    addCorners(problem, lines, work);
    // Dijkstra from the start (settleOne, one vertex per unit).
    for (std::size_t v = 0; v < vertexCount_; ++v) {
        dist_[v] = INFINITY;
        settled_[v] = false;
        prev_[v] = 0;
    }
    dist_[0] = 0.0;
    return true;
}

void CcVisibilitySeed::collectLines(const CcProblem& problem, Lines* lines) const {
    std::size_t count = 0;
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            lines->obstacle[count] = static_cast<std::uint8_t>(i);
            lines->nx[count] = o.normalX[j];
            lines->ny[count] = o.normalY[j];
            lines->b[count] = inflated_[i][j];
            ++count;
        }
    }
    const std::size_t sides = 4;
    const double sideX[sides] = {1.0, 1.0, 0.0, 0.0};
    const double sideY[sides] = {0.0, 0.0, 1.0, 1.0};
    const double sideB[sides] = {problem.xMin, problem.xMax, problem.yMin, problem.yMax};
    for (std::size_t k = 0; k < sides; ++k) {
        lines->obstacle[count] = kSiteSide;
        lines->nx[count] = sideX[k];
        lines->ny[count] = sideY[k];
        lines->b[count] = sideB[k];
        ++count;
    }
    lines->count = count;
}

// The free space's corners, where a shortest path can bend (see the header).
void CcVisibilitySeed::addCorners(const CcProblem& p, const Lines& lines, std::uint64_t* work) {
    const std::size_t obstacles = p.obstacleCount;
    for (std::size_t a = 0; a < lines.count; ++a) {
        for (std::size_t b = a + 1; b < lines.count; ++b) {
            if (lines.obstacle[a] == kSiteSide && lines.obstacle[b] == kSiteSide) {
                continue;  // a corner of the site: never a bend of a shortest path
            }
            *work += 2U * kMaxObstacleFaces * obstacles;
            const double det = lines.nx[a] * lines.ny[b] - lines.ny[a] * lines.nx[b];
            if (std::fabs(det) < 1e-9) {
                continue;
            }
            const double x = (lines.b[a] * lines.ny[b] - lines.ny[a] * lines.b[b]) / det;
            const double y = (lines.nx[a] * lines.b[b] - lines.b[a] * lines.nx[b]) / det;
            if (!(x >= p.xMin && x <= p.xMax && y >= p.yMin && y <= p.yMax)) {
                continue;
            }
            bool valid = (lines.obstacle[a] == kSiteSide || onBoundaryOf(p, lines.obstacle[a], x, y)) &&
                         (lines.obstacle[b] == kSiteSide || onBoundaryOf(p, lines.obstacle[b], x, y));
            for (std::size_t i = 0; i < obstacles && valid; ++i) {
                valid = !insideInflated(p, i, x, y, kSeedTouchM);
            }
            for (std::size_t v = 2; v < vertexCount_ && valid; ++v) {
                valid = std::fabs(vx_[v] - x) + std::fabs(vy_[v] - y) > 1e-9;
            }
            if (valid && vertexCount_ < kMaxVertices) {
                vx_[vertexCount_] = x;
                vy_[vertexCount_] = y;
                ++vertexCount_;
            }
        }
    }
}

bool CcVisibilitySeed::segmentBlocked(const CcProblem& problem, double px, double py, double qx, double qy,
                                      std::uint64_t* work) {
    const std::size_t obstacles = problem.obstacleCount;
    *work += 10U * kMaxObstacleFaces * obstacles;
    const double dx = qx - px;
    const double dy = qy - py;
    for (std::size_t i = 0; i < obstacles; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
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

bool CcVisibilitySeed::settleOne(const CcProblem& problem, std::uint64_t* work) {
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
        if (d < dist_[v] && !segmentBlocked(problem, vx_[u], vy_[u], vx_[v], vy_[v], work)) {
            dist_[v] = d;
            prev_[v] = static_cast<std::uint8_t>(u);
        }
    }
    return false;
}

// The shortest path's legs into legPoint_ (start first); false without one.
bool CcVisibilitySeed::legs(std::size_t steps, std::size_t* count) {
    if (!std::isfinite(dist_[1])) {
        return false;
    }
    // The path, goal back to start, then reversed into legPoint_.
    std::size_t points = 0;
    std::size_t v = 1;
    for (std::size_t guard = 0; guard <= vertexCount_; ++guard) {
        legPoint_[points++] = static_cast<std::uint8_t>(v);
        if (v == 0) {
            break;
        }
        v = prev_[v];
    }
    if (legPoint_[points - 1] != 0) {
        return false;
    }
    for (std::size_t a = 0, b = points - 1; a < b; ++a, --b) {
        const std::uint8_t tmp = legPoint_[a];
        legPoint_[a] = legPoint_[b];
        legPoint_[b] = tmp;
    }
    *count = points - 1;
    return *count >= 1 && *count <= steps;
}

bool CcVisibilitySeed::cutPath(const CcProblem& problem, bool frontLoaded, double* x, double* y) {
    const std::size_t steps = problem.steps;
    std::size_t legCount = 0;
    if (!legs(steps, &legCount)) {
        return false;
    }
    // Segments per leg: one each, the rest one at a time to the leg with the
    // longest segments.
    std::size_t share[kMaxPlanSteps];  // legs <= steps (legs())
    double length[kMaxPlanSteps];
    for (std::size_t l = 0; l < legCount; ++l) {
        share[l] = 1;
        length[l] = euclidean(vx_[legPoint_[l + 1]] - vx_[legPoint_[l]], vy_[legPoint_[l + 1]] - vy_[legPoint_[l]]);
    }
    for (std::size_t extra = legCount; extra < steps && !frontLoaded; ++extra) {
        std::size_t best = 0;
        for (std::size_t l = 1; l < legCount; ++l) {
            if (length[l] / static_cast<double>(share[l]) > length[best] / static_cast<double>(share[best])) {
                best = l;
            }
        }
        ++share[best];
    }
    std::size_t tau = 0;
    for (std::size_t l = 0; l < legCount; ++l) {
        const double ax = vx_[legPoint_[l]];
        const double ay = vy_[legPoint_[l]];
        const double bx = vx_[legPoint_[l + 1]];
        const double by = vy_[legPoint_[l + 1]];
        for (std::size_t k = 0; k < share[l]; ++k, ++tau) {
            const double f = static_cast<double>(k) / static_cast<double>(share[l]);
            x[tau] = ax + f * (bx - ax);
            y[tau] = ay + f * (by - ay);
        }
    }
    for (; tau <= steps; ++tau) {
        x[tau] = problem.goalX;
        y[tau] = problem.goalY;
    }
    return true;
}

}  // namespace rse::deliberative
