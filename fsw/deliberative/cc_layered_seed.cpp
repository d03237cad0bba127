#include "fsw/deliberative/cc_layered_seed.hpp"

#include <cmath>

#include "fsw/deliberative/cc_lp.hpp"

namespace rse::deliberative {

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

std::size_t CcLayeredSeed::lineCount(const CcProblem& problem) const {
    std::size_t n = 4;  // the site's sides
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        n += problem.obstacles[i].faceCount;
    }
    return n;
}

// Line k at layer tau as {x : nx x + ny y = c}, the free side nx x + ny y >= c.
void CcLayeredSeed::line(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, std::size_t k,
                         double* nx, double* ny, double* c) const {
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
        if (k < o.faceCount) {
            *nx = o.normalX[k];
            *ny = o.normalY[k];
            *c = o.offset[k] + margins.margin(tau, i, k) + kLayerSafetyM;
            return;
        }
        k -= o.faceCount;
    }
    const double sx[4] = {1.0, -1.0, 0.0, 0.0};
    const double sy[4] = {0.0, 0.0, 1.0, -1.0};
    const double sc[4] = {problem.xMin + kLayerSideM, -(problem.xMax - kLayerSideM), problem.yMin + kLayerSideM,
                          -(problem.yMax - kLayerSideM)};
    *nx = sx[k & 3U];
    *ny = sy[k & 3U];
    *c = sc[k & 3U];
}

// The point named by two line indices at layer tau (or the start or goal).
bool CcLayeredSeed::point(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, std::uint8_t a,
                          std::uint8_t b, double* x, double* y) const {
    if (a == kStartPoint || a == kGoalPoint) {
        *x = a == kStartPoint ? problem.startX : problem.goalX;
        *y = a == kStartPoint ? problem.startY : problem.goalY;
        return true;
    }
    double ax = 0.0, ay = 0.0, ac = 0.0, bx = 0.0, by = 0.0, bc = 0.0;
    line(problem, margins, tau, a, &ax, &ay, &ac);
    line(problem, margins, tau, b, &bx, &by, &bc);
    const double det = ax * by - ay * bx;
    if (std::fabs(det) < 1e-9) {
        return false;
    }
    *x = (ac * by - ay * bc) / det;
    *y = (ax * bc - ac * bx) / det;
    return *x >= problem.xMin + kBoundSafetyM && *x <= problem.xMax - kBoundSafetyM &&
           *y >= problem.yMin + kBoundSafetyM && *y <= problem.yMax - kBoundSafetyM;
}

// Byte i, bit j: the point clears face j of obstacle i by its margin at tau
// (by kSafetyM more, as the LP wants, unless it is the fixed start or goal).
std::uint64_t CcLayeredSeed::mask(const CcProblem& problem, const CcEndMargins& margins, std::size_t tau, double x,
                                  double y, bool fixedEnd, std::uint64_t* work) const {
    *work += kLayerPointWork * kMaxObstacleFaces * problem.obstacleCount;
    std::uint64_t bits = 0;
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        const PlanObstacle& o = problem.obstacles[i];
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            double s = endSlack(o, j, x, y, margins.margin(tau, i, j));
            s -= fixedEnd ? 0.0 : kSafetyM;
            if (s >= 0.0) {
                bits |= 1ULL << (8U * i + j);
            }
        }
    }
    return bits;
}

// Layer 0: the start alone.
void CcLayeredSeed::startLayers(const CcProblem& problem, const CcEndMargins& margins, std::uint64_t* work) {
    layerLines_[0][0][0] = kStartPoint;
    layerLines_[0][0][1] = kStartPoint;
    reachX_[0][0] = problem.startX;
    reachY_[0][0] = problem.startY;
    reachMask_[0][0] = mask(problem, margins, 0, problem.startX, problem.startY, true, work);
    layerCount_[0] = 1;
    layerTau_ = 1;
    layerLineA_ = 0;
    layerBuilt_ = 0;
}

// A candidate point of layer layerTau_ (two of its lines crossing inside the
// site, or the goal): kept when it clears every obstacle, no point kept
// covers its mask, and it is one feasible segment from a point of the layer
// before.
void CcLayeredSeed::consider(const CcProblem& problem, const CcEndMargins& margins, std::uint64_t wanted,
                             std::uint8_t a, std::uint8_t b, std::uint64_t* work) {
    const std::size_t tau = layerTau_;
    const std::size_t from = (tau - 1) & 1U;
    const std::size_t to = tau & 1U;
    double x = 0.0;
    double y = 0.0;
    if (layerBuilt_ >= kMaxLayerPoints || !point(problem, margins, tau, a, b, &x, &y)) {
        return;
    }
    const bool fixedEnd = a == kStartPoint || a == kGoalPoint;
    const std::uint64_t bits = mask(problem, margins, tau, x, y, fixedEnd, work);
    if (!everyObstacle(bits, wanted)) {
        return;
    }
    // A point's future moves depend on its mask alone: one whose faces
    // include this one's already does all it could (exact, and it keeps
    // the layers far below kMaxLayerPoints).
    *work += kLayerEdgeWork * layerBuilt_;
    for (std::size_t v = 0; v < layerBuilt_; ++v) {
        if ((reachMask_[to][v] & bits) == bits) {
            return;
        }
    }
    const std::size_t prevCount = layerCount_[tau - 1];
    for (std::size_t u = 0; u < prevCount; ++u) {
        if (everyObstacle(bits & reachMask_[from][u], wanted)) {
            *work += kLayerEdgeWork * (u + 1U);
            layerLines_[tau][layerBuilt_][0] = a;
            layerLines_[tau][layerBuilt_][1] = b;
            layerPrev_[tau][layerBuilt_] = static_cast<std::uint16_t>(u);
            reachX_[to][layerBuilt_] = x;
            reachY_[to][layerBuilt_] = y;
            reachMask_[to][layerBuilt_] = bits;
            ++layerBuilt_;
            return;
        }
    }
    *work += kLayerEdgeWork * prevCount;
}

CcLayeredSeed::Progress CcLayeredSeed::step(const CcProblem& problem, const CcEndMargins& margins,
                                            std::uint64_t* work) {
    const std::size_t obstacles = problem.obstacleCount;
    const std::uint64_t wanted = kByteLow & (obstacles >= 8 ? ~0ULL : ((1ULL << (8U * obstacles)) - 1U));
    if (layerTau_ == 0) {
        startLayers(problem, margins, work);
        return Progress::kRunning;
    }
    const std::size_t lines = lineCount(problem);
    bool goalReached = false;
    if (layerLineA_ == 0 && layerBuilt_ == 0) {
        // The goal first: once it is reached the rest of the steps park there.
        consider(problem, margins, wanted, kGoalPoint, kGoalPoint, work);
        goalReached = layerBuilt_ == 1;
        if (layerTau_ == problem.steps || goalReached) {
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
            consider(problem, margins, wanted, static_cast<std::uint8_t>(a), static_cast<std::uint8_t>(b), work);
        }
    }
    if (layerLineA_ < lines) {
        return Progress::kRunning;  // this layer goes on in the next unit
    }
    return closeLayer(problem.steps, goalReached);
}

// The layer is complete: a path (the goal is in it), no path (the layer is
// empty, or the last has no goal), or on to the next layer.
CcLayeredSeed::Progress CcLayeredSeed::closeLayer(std::size_t steps, bool goalReached) {
    const std::size_t tau = layerTau_;
    const std::size_t count = layerBuilt_;
    layerCount_[tau] = static_cast<std::uint16_t>(count);
    layerFull_ += count >= kMaxLayerPoints ? 1U : 0U;
    layerLineA_ = 0;
    layerBuilt_ = 0;
    if (count == 0 || (tau == steps && !goalReached)) {
        return Progress::kNoPath;
    }
    if (!goalReached) {
        ++layerTau_;
        return Progress::kRunning;
    }
    return Progress::kFound;
}

double CcLayeredSeed::path(const CcProblem& problem, const CcEndMargins& margins, double* x, double* y) const {
    // The goal at layer tau: the rest of the steps park there (the goal
    // clears some face of every obstacle by its margin at N, the largest).
    const std::size_t tau = layerTau_;
    std::size_t k = 0;  // the goal's index in layer tau
    for (std::size_t t = problem.steps; t > tau; --t) {
        x[t] = problem.goalX;
        y[t] = problem.goalY;
    }
    double length = 0.0;
    for (std::size_t t = tau + 1; t-- > 0;) {
        double px = 0.0;
        double py = 0.0;
        (void)point(problem, margins, t, layerLines_[t][k][0], layerLines_[t][k][1], &px, &py);
        x[t] = px;
        y[t] = py;
        if (t < tau) {
            length += polygonLength(x[t + 1] - px, y[t + 1] - py);
        }
        k = t > 0 ? layerPrev_[t][k] : 0U;
    }
    return length;
}

}  // namespace rse::deliberative
