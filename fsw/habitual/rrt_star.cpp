#include "fsw/habitual/rrt_star.hpp"

#include <cmath>

namespace rse::habitual {

using geometry::Point2;

namespace {

// A steered point this close to its nearest node adds nothing (a repeated goal
// sample lands exactly on the goal node).
constexpr double kMinSeparationM = 1e-9;
// A rewire must gain more than rounding: costs pushed down a subtree collect
// rounding, and a "gain" of 1e-16 could otherwise hang a node under its own
// descendant.
constexpr double kMinGainM = 1e-9;
// Draws of the unit square per informed sample (acceptance pi/4 each) and of
// ellipse points per sample that must land inside the bounds.
constexpr int kUnitDiscTries = 8;
constexpr int kEllipseTries = 8;
// A full pool is pruned only when that frees at least 1/8 of it; less would
// make the O(pool) compaction run too often for what it gains.
constexpr std::size_t kMinPruneFraction = 8;
// The grid starts with kMinGridCells cells and is re-cut to kGridCellsPerNode
// per node whenever the nodes outnumber the cells (up to the grid's maximum):
// a young tree is not searched through thousands of empty cells, a dense one
// not through crowded ones. Four per node: a re-cut at every 4x growth.
constexpr std::size_t kMinGridCells = 256;
constexpr std::size_t kGridCellsPerNode = 4;

}  // namespace

void RrtStar::Random::seed(std::uint64_t seed) {
    std::uint64_t x = seed;
    for (std::uint64_t& word : s) {
        x += 0x9E3779B97F4A7C15ULL;
        std::uint64_t z = x;
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        word = z ^ (z >> 31);
    }
}

std::uint64_t RrtStar::Random::next() {
    const auto rotl = [](std::uint64_t v, int k) { return (v << k) | (v >> (64 - k)); };
    const std::uint64_t result = rotl(s[1] * 5, 7) * 9;
    const std::uint64_t t = s[1] << 17;
    s[2] ^= s[0];
    s[3] ^= s[1];
    s[1] ^= s[2];
    s[0] ^= s[3];
    s[2] ^= t;
    s[3] = rotl(s[3], 45);
    return result;
}

double RrtStar::Random::uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }

core::Status RrtStar::start(const LocalMap& map, Point2 start, Point2 goal, const RrtStarParams& params,
                            std::uint64_t seed) {
    started_ = false;
    bestNode_ = kNone;
    bestCost_ = INFINITY;
    if (!map.valid() || !std::isfinite(params.stepM) || !(params.stepM > 0.0) || !(params.goalBias >= 0.0) ||
        !(params.goalBias < 1.0) || !std::isfinite(params.goalToleranceM) || !(params.goalToleranceM >= 0.0) ||
        params.kCap < 1 || params.kCap > kMaxRrtNeighbours || !map.pointFree(start) || !map.pointFree(goal)) {
        return core::Status::kInvalidArgument;
    }
    // The grid's frame: origin at the start, axis towards the goal, its box the
    // bounds' corners seen in that frame.
    const double focal = distance(start, goal);
    const Point2 axis = focal > 0.0 ? (1.0 / focal) * (goal - start) : Point2{1.0, 0.0};
    const Point2 lo = map.min();
    const Point2 hi = map.max();
    const Point2 corners[4] = {lo, Point2{hi.x, lo.y}, hi, Point2{lo.x, hi.y}};
    boundsLo_ = Point2{INFINITY, INFINITY};
    boundsHi_ = Point2{-INFINITY, -INFINITY};
    for (const Point2 corner : corners) {
        const Point2 d = corner - start;
        const Point2 l{dot(d, axis), cross(axis, d)};
        boundsLo_ = Point2{std::fmin(boundsLo_.x, l.x), std::fmin(boundsLo_.y, l.y)};
        boundsHi_ = Point2{std::fmax(boundsHi_.x, l.x), std::fmax(boundsHi_.y, l.y)};
    }
    const double area = (hi.x - lo.x) * (hi.y - lo.y);
    gridCells_ = kMinGridCells;
    if (grid_.reset(start, axis, boundsLo_, boundsHi_, gridCells_) != core::Status::kOk) {
        return core::Status::kInvalidArgument;
    }
    map_ = &map;
    params_ = params;
    start_ = start;
    goal_ = goal;
    random_.seed(seed);
    focalDistance_ = focal;
    centre_ = 0.5 * (start + goal);
    axis_ = axis;
    boundsArea_ = area;
    goalNext_ = false;
    goalNodeExists_ = false;
    bestNode_ = kNone;
    bestCost_ = INFINITY;
    iterations_ = 0;
    firstSolutionIteration_ = 0;
    kForN_ = 0;
    kCached_ = 1;
    largestK_ = 0;
    largestNeighbourSet_ = 0;
    rewires_ = 0;
    segmentChecks_ = 0;
    samplesRejected_ = 0;
    regrids_ = 0;
    prunedNodes_ = 0;
    pruneRefusedAtCost_ = INFINITY;
    regridCheckedCost_ = INFINITY;
    gridBoxArea_ = (boundsHi_.x - boundsLo_.x) * (boundsHi_.y - boundsLo_.y);

    std::uint32_t root = kNone;
    if (grid_.insert(start, &root) != core::Status::kOk) {
        return core::Status::kInvalidArgument;
    }
    const double toGoal = distance(start, goal);
    const bool atGoal = toGoal <= params.goalToleranceM && (toGoal == 0.0 || map.segmentFree(start, goal));
    nodes_[root] = Node{0.0, kNone, kNone, kNone, kNone, atGoal};
    goalNodeExists_ = toGoal == 0.0;
    started_ = true;
    considerGoal(root);
    return core::Status::kOk;
}

std::uint32_t RrtStar::iterate(std::uint32_t maxIterations) {
    if (!started_) {
        return 0;
    }
    for (std::uint32_t i = 0; i < maxIterations; ++i) {
        if (poolFull()) {
            if (!rebuild(grid_.size() / kMinPruneFraction)) {
                return i;
            }
        } else if ((grid_.size() > gridCells_ && gridCells_ < PointGrid<kMaxRrtNodes>::kMaxCells) || regridDue()) {
            static_cast<void>(rebuild(0));
        }
        ++iterations_;
        step();
    }
    return maxIterations;
}

std::size_t RrtStar::bestPathPointCount() const {
    if (!solved()) {
        return 0;
    }
    std::size_t count = 0;
    for (std::uint32_t id = bestNode_; id != kNone && count < kMaxRrtNodes; id = nodes_[id].parent) {
        ++count;
    }
    const Point2 last = grid_.point(bestNode_);
    return count + ((last.x == goal_.x && last.y == goal_.y) ? 0U : 1U);
}

std::size_t RrtStar::bestPath(Point2* out, std::size_t maxPoints) const {
    const std::size_t count = bestPathPointCount();
    if (count == 0 || out == nullptr || count > maxPoints) {
        return 0;
    }
    std::size_t i = count;
    const Point2 last = grid_.point(bestNode_);
    if (last.x != goal_.x || last.y != goal_.y) {
        out[--i] = goal_;
    }
    for (std::uint32_t id = bestNode_; id != kNone && i > 0; id = nodes_[id].parent) {
        out[--i] = grid_.point(id);
    }
    return count;
}

Point2 RrtStar::nodePoint(std::size_t id) const {
    const double nan = std::nan("");
    return id < grid_.size() ? grid_.point(static_cast<std::uint32_t>(id)) : Point2{nan, nan};
}

double RrtStar::nodeCost(std::size_t id) const { return id < grid_.size() ? nodes_[id].cost : std::nan(""); }

std::uint32_t RrtStar::nodeParent(std::size_t id) const { return id < grid_.size() ? nodes_[id].parent : kNone; }

void RrtStar::step() {
    Point2 sample{0.0, 0.0};
    if (goalNext_) {
        goalNext_ = false;
        sample = goal_;
    } else if (random_.uniform() < params_.goalBias) {
        sample = goal_;
    } else if (!drawSample(&sample)) {
        return;
    }
    const std::uint32_t nearest = grid_.nearest(sample);
    const Point2 from = grid_.point(nearest);
    const double d = distance(from, sample);
    if (d <= kMinSeparationM) {
        return;
    }
    const Point2 x = d > params_.stepM ? from + (params_.stepM / d) * (sample - from) : sample;
    if (solved() && distance(start_, x) + distance(x, goal_) >= bestCost_) {
        ++samplesRejected_;
        return;
    }
    if (!segmentFree(from, x)) {
        return;
    }

    // Candidates: the k nearest within one step, and the nearest node itself
    // (steering put x within one step of it, but rounding may put it a hair out).
    const std::uint16_t k = kFor(grid_.size());
    std::size_t count = grid_.nearestWithin(x, params_.stepM, k, candidates_);
    bool haveNearest = false;
    for (std::size_t i = 0; i < count; ++i) {
        haveNearest = haveNearest || candidates_[i].id == nearest;
    }
    if (!haveNearest) {
        candidates_[count++] = Neighbour{nearest, distanceSquared(from, x)};
    }
    largestNeighbourSet_ = count > largestNeighbourSet_ ? static_cast<std::uint16_t>(count) : largestNeighbourSet_;
    for (std::size_t i = 0; i < count; ++i) {
        edge_[i] = std::sqrt(candidates_[i].distanceSquared);
        throughCost_[i] = nodes_[candidates_[i].id].cost + edge_[i];
        free_[i] = candidates_[i].id == nearest ? 1 : 0;
    }
    // Cheapest candidate first until one is free (usually the first): a
    // selection per pick instead of a full sort. A blocked candidate drops out.
    std::size_t parentSlot = count;
    for (std::size_t pick = 0; pick < count && parentSlot == count; ++pick) {
        std::size_t best = count;
        for (std::size_t i = 0; i < count; ++i) {
            if (free_[i] >= 0 && (best == count || throughCost_[i] < throughCost_[best])) {
                best = i;
            }
        }
        if (best == count) {
            break;
        }
        if (free_[best] == 0) {
            free_[best] = segmentFree(grid_.point(candidates_[best].id), x) ? 1 : -1;
        }
        parentSlot = free_[best] > 0 ? best : count;
    }
    // The nearest node's segment is free, so a parent is always found.
    std::uint32_t id = kNone;
    if (parentSlot == count || grid_.insert(x, &id) != core::Status::kOk) {
        return;
    }
    const std::uint32_t parent = candidates_[parentSlot].id;
    const double cost = throughCost_[parentSlot];
    nodes_[id] = Node{cost, kNone, kNone, kNone, kNone, false};
    link(id, parent);

    const double toGoal = distance(x, goal_);
    if (toGoal <= params_.goalToleranceM && (toGoal == 0.0 || segmentFree(x, goal_))) {
        nodes_[id].goal = true;
        goalNodeExists_ = goalNodeExists_ || toGoal == 0.0;
        considerGoal(id);
    }
    if (!goalNodeExists_ && toGoal > 0.0 && toGoal <= params_.stepM) {
        goalNext_ = true;
    }

    for (std::size_t i = 0; i < count; ++i) {
        const std::uint32_t other = candidates_[i].id;
        const double through = cost + edge_[i];
        if (i == parentSlot || !(through < nodes_[other].cost - kMinGainM)) {
            continue;
        }
        if (free_[i] == 0) {
            free_[i] = segmentFree(x, grid_.point(other)) ? 1 : -1;
        }
        if (free_[i] > 0) {
            rewire(other, id, through);
        }
    }
}

bool RrtStar::drawSample(Point2* sample) {
    if (solved() && drawInformed(sample)) {
        return true;
    }
    const Point2 lo = map_->min();
    const Point2 hi = map_->max();
    *sample = Point2{lo.x + (hi.x - lo.x) * random_.uniform(), lo.y + (hi.y - lo.y) * random_.uniform()};
    return true;
}

bool RrtStar::drawInformed(Point2* sample) {
    const double a = 0.5 * bestCost_;  // semi-axes of the ellipse of better paths
    const double b = 0.5 * std::sqrt(std::fmax(0.0, bestCost_ * bestCost_ - focalDistance_ * focalDistance_));
    constexpr double kPi = 3.14159265358979323846;
    if (!(kPi * a * b < boundsArea_)) {
        return false;  // the bounds are the smaller set: sample them directly
    }
    const Point2 lo = map_->min();
    const Point2 hi = map_->max();
    for (int tries = 0; tries < kEllipseTries; ++tries) {
        Point2 u{1.0, 1.0};
        for (int i = 0; i < kUnitDiscTries && dot(u, u) > 1.0; ++i) {
            u = Point2{2.0 * random_.uniform() - 1.0, 2.0 * random_.uniform() - 1.0};
        }
        if (dot(u, u) > 1.0) {
            continue;
        }
        const Point2 local{a * u.x, b * u.y};
        const Point2 p{centre_.x + axis_.x * local.x - axis_.y * local.y,
                       centre_.y + axis_.y * local.x + axis_.x * local.y};
        if (p.x >= lo.x && p.x <= hi.x && p.y >= lo.y && p.y <= hi.y) {
            *sample = p;
            return true;
        }
    }
    return false;
}

std::uint16_t RrtStar::kFor(std::size_t n) {
    if (n != kForN_) {
        kForN_ = n;
        const double k = std::ceil(kRrt * std::log(static_cast<double>(n) + 1.0));
        const double cap = static_cast<double>(params_.kCap);
        kCached_ = static_cast<std::uint16_t>(k < 1.0 ? 1.0 : (k > cap ? cap : k));
    }
    largestK_ = kCached_ > largestK_ ? kCached_ : largestK_;
    return kCached_;
}

void RrtStar::link(std::uint32_t child, std::uint32_t parent) {
    Node& c = nodes_[child];
    Node& p = nodes_[parent];
    c.parent = parent;
    c.prevSibling = kNone;
    c.nextSibling = p.firstChild;
    if (p.firstChild != kNone) {
        nodes_[p.firstChild].prevSibling = child;
    }
    p.firstChild = child;
}

void RrtStar::unlink(std::uint32_t child) {
    Node& c = nodes_[child];
    if (c.prevSibling != kNone) {
        nodes_[c.prevSibling].nextSibling = c.nextSibling;
    } else {
        nodes_[c.parent].firstChild = c.nextSibling;
    }
    if (c.nextSibling != kNone) {
        nodes_[c.nextSibling].prevSibling = c.prevSibling;
    }
    c.parent = kNone;
    c.prevSibling = kNone;
    c.nextSibling = kNone;
}

void RrtStar::rewire(std::uint32_t id, std::uint32_t newParent, double newCost) {
    ++rewires_;
    unlink(id);
    link(id, newParent);
    const double gain = nodes_[id].cost - newCost;
    nodes_[id].cost = newCost;
    considerGoal(id);
    // Threaded pre-order walk of the subtree: down to the first child, else on to
    // the next sibling, else back up until an ancestor below id has one. Each
    // node is entered once and left once: 2 x pool steps bound the walk.
    std::uint32_t u = nodes_[id].firstChild;
    for (std::size_t steps = 0; u != kNone && steps < 2 * kMaxRrtNodes; ++steps) {
        nodes_[u].cost -= gain;
        considerGoal(u);
        if (nodes_[u].firstChild != kNone) {
            u = nodes_[u].firstChild;
            continue;
        }
        for (; u != id && nodes_[u].nextSibling == kNone && steps < 2 * kMaxRrtNodes; ++steps) {
            u = nodes_[u].parent;
        }
        u = u == id ? kNone : nodes_[u].nextSibling;
    }
}

bool RrtStar::regridDue() {
    if (!solved() || bestCost_ == regridCheckedCost_) {
        return false;
    }
    regridCheckedCost_ = bestCost_;
    Point2 lo{0.0, 0.0};
    Point2 hi{0.0, 0.0};
    ellipseBox(&lo, &hi);
    return (hi.x - lo.x) * (hi.y - lo.y) <= 0.5 * gridBoxArea_;
}

void RrtStar::ellipseBox(Point2* lo, Point2* hi) const {
    // In the grid's frame (origin start, x towards the goal) the ellipse of paths
    // shorter than c is centred at (|goal - start| / 2, 0) with semi-axes a, b.
    // The pad absorbs rounding at its rim.
    const double a = 0.5 * bestCost_;
    const double b = 0.5 * std::sqrt(std::fmax(0.0, bestCost_ * bestCost_ - focalDistance_ * focalDistance_));
    const double pad = 1e-6 + 1e-9 * bestCost_;
    *lo = Point2{std::fmax(boundsLo_.x, 0.5 * focalDistance_ - a - pad), std::fmax(boundsLo_.y, -b - pad)};
    *hi = Point2{std::fmin(boundsHi_.x, 0.5 * focalDistance_ + a + pad), std::fmin(boundsHi_.y, b + pad)};
}

bool RrtStar::rebuild(std::size_t minFreed) {
    const std::size_t n = grid_.size();
    if (minFreed > 0 && (!solved() || !(bestCost_ < pruneRefusedAtCost_))) {
        return false;
    }
    std::size_t kept = n;
    for (std::size_t i = 0; i < n; ++i) {
        keep_[i] = solved() ? 0 : 1;
    }
    if (solved()) {
        kept = markPromising();
        if (n - kept < minFreed) {
            pruneRefusedAtCost_ = bestCost_;  // not worth compacting until the best improves
            return false;
        }
        if (kept < n) {
            compact(n);
        }
    }
    // Every kept node and every node still to come lies in the ellipse of the
    // best cost (in the bounds before a solution): re-grid over its box with
    // about four cells per node, so the cells match the density there until the
    // node count passes the cell count.
    Point2 lo = boundsLo_;
    Point2 hi = boundsHi_;
    if (solved()) {
        ellipseBox(&lo, &hi);
    }
    gridBoxArea_ = (hi.x - lo.x) * (hi.y - lo.y);
    gridCells_ = kGridCellsPerNode * kept;
    gridCells_ = gridCells_ < kMinGridCells ? kMinGridCells : gridCells_;
    gridCells_ = gridCells_ > PointGrid<kMaxRrtNodes>::kMaxCells ? PointGrid<kMaxRrtNodes>::kMaxCells : gridCells_;
    grid_.regrid(keep_, lo, hi, gridCells_);
    ++regrids_;
    prunedNodes_ += static_cast<std::uint32_t>(n - kept);
    return true;
}

std::size_t RrtStar::markPromising() {
    // Keep a node while its parent is kept and it could still lie on a path
    // shorter than the best: cost + |p - goal| <= best. That bound never falls
    // from parent to child (triangle inequality), so a dropped node's subtree is
    // dropped whole and the walk skips it.
    keep_[0] = 1;
    std::uint32_t u = nodes_[0].firstChild;
    for (std::size_t steps = 0; u != kNone && steps < 2 * kMaxRrtNodes; ++steps) {
        const bool keep = nodes_[u].cost + distance(grid_.point(u), goal_) <= bestCost_;
        keep_[u] = keep ? 1 : 0;
        if (keep && nodes_[u].firstChild != kNone) {
            u = nodes_[u].firstChild;
            continue;
        }
        for (; u != 0 && nodes_[u].nextSibling == kNone && steps < 2 * kMaxRrtNodes; ++steps) {
            u = nodes_[u].parent;
        }
        u = u == 0 ? kNone : nodes_[u].nextSibling;
    }
    // The best path is kept whatever rounding says about its bound.
    std::size_t guard = 0;
    for (std::uint32_t id = bestNode_; id != kNone && guard < kMaxRrtNodes; id = nodes_[id].parent, ++guard) {
        keep_[id] = 1;
    }
    std::size_t kept = 0;
    for (std::size_t i = 0; i < grid_.size(); ++i) {
        kept += keep_[i];
    }
    return kept;
}

void RrtStar::compact(std::size_t n) {
    // In id order: the new id (rank among kept nodes) is never above the old
    // one, so moving node i only overwrites a slot already moved. The new id
    // goes in prevSibling, then the new parent in nextSibling, before the move.
    std::uint32_t next = 0;
    for (std::size_t i = 0; i < n; ++i) {
        nodes_[i].prevSibling = keep_[i] != 0 ? next++ : kNone;
    }
    for (std::size_t i = 0; i < n; ++i) {
        const std::uint32_t parent = nodes_[i].parent;
        nodes_[i].nextSibling = (keep_[i] == 0 || parent == kNone) ? kNone : nodes_[parent].prevSibling;
    }
    bestNode_ = nodes_[bestNode_].prevSibling;
    goalNodeExists_ = false;
    for (std::size_t i = 0; i < n; ++i) {
        if (keep_[i] != 0) {
            const Node moved = nodes_[i];
            const Point2 p = grid_.point(static_cast<std::uint32_t>(i));
            goalNodeExists_ = goalNodeExists_ || (p.x == goal_.x && p.y == goal_.y);
            nodes_[moved.prevSibling] = Node{moved.cost, moved.nextSibling, kNone, kNone, kNone, moved.goal};
        }
    }
    for (std::uint32_t id = 1; id < next; ++id) {
        link(id, nodes_[id].parent);
    }
}

void RrtStar::considerGoal(std::uint32_t id) {
    if (!nodes_[id].goal) {
        return;
    }
    const double cost = nodes_[id].cost + distance(grid_.point(id), goal_);
    if (cost < bestCost_) {
        if (bestNode_ == kNone) {
            firstSolutionIteration_ = iterations_;
        }
        bestCost_ = cost;
        bestNode_ = id;
    }
}

bool RrtStar::segmentFree(Point2 a, Point2 b) {
    ++segmentChecks_;
    return map_->segmentFree(a, b);
}

}  // namespace rse::habitual
