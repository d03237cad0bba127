#include "fsw/deliberative/global_route.hpp"

#include <cmath>

namespace rse::deliberative {

using geometry::Point2;

namespace {

constexpr std::uint8_t kUsable = 1U;
constexpr std::uint8_t kBlocked = 2U;
constexpr std::uint8_t kClosed = 4U;

bool finitePositive(double v) { return std::isfinite(v) && v > 0.0; }

}  // namespace

const char* toString(RouteState state) {
    switch (state) {
        case RouteState::kIdle: return "idle";
        case RouteState::kSearching: return "searching";
        case RouteState::kFound: return "found";
        case RouteState::kNoRoute: return "no route";
        case RouteState::kBudgetSpent: return "budget spent";
        case RouteState::kRefused: return "refused";
    }
    return "unknown";
}

const char* toString(RouteRefusal refusal) {
    switch (refusal) {
        case RouteRefusal::kNone: return "none";
        case RouteRefusal::kNoMap: return "no site map in force";
        case RouteRefusal::kBadParams: return "route parameters out of range";
        case RouteRefusal::kBadPoint: return "start or goal not finite";
        case RouteRefusal::kStartOffSite: return "start off the site (shrunk by the clearance)";
        case RouteRefusal::kGoalOffSite: return "goal off the site (shrunk by the clearance)";
        case RouteRefusal::kStartBlocked: return "start within the clearance of a rock or zone";
        case RouteRefusal::kGoalBlocked: return "goal within the clearance of a rock or zone";
        case RouteRefusal::kRouteTooLong: return "route has more points than kMaxRoutePoints";
    }
    return "unknown";
}

RouteRefusal GlobalRoute::start(const site_map::SiteMap& map, Point2 start, Point2 goal, const RouteParams& params) {
    state_ = RouteState::kRefused;
    pointCount_ = 0;
    lengthM_ = 0.0;
    cost_ = 0.0;
    heapSize_ = 0;
    stats_ = RouteStats{};
    map_ = &map;
    const auto refuse = [this](RouteRefusal why) {
        refusal_ = why;
        return why;
    };
    if (!map.loaded()) {
        return refuse(RouteRefusal::kNoMap);
    }
    if (!finitePositive(params.clearanceM) || !std::isfinite(params.comfortM) || params.comfortM <= params.clearanceM ||
        !(params.proximityCost >= 0.0) || !std::isfinite(params.proximityCost) ||
        !(params.spacingM >= kMinRouteSpacingM) || !std::isfinite(params.spacingM) ||
        !(params.heuristicWeight >= 1.0) || !std::isfinite(params.heuristicWeight) || params.workBudget == 0 ||
        !(params.zoneMarginM >= 0.0) || !std::isfinite(params.zoneMarginM)) {
        return refuse(RouteRefusal::kBadParams);
    }
    if (!geometry::isFinite(start) || !geometry::isFinite(goal)) {
        return refuse(RouteRefusal::kBadPoint);
    }
    params_ = params;
    const site_map::SiteBounds& site = map.site();
    minX_ = static_cast<double>(site.xMin) + params.clearanceM;
    minY_ = static_cast<double>(site.yMin) + params.clearanceM;
    maxX_ = static_cast<double>(site.xMax) - params.clearanceM;
    maxY_ = static_cast<double>(site.yMax) - params.clearanceM;
    const auto onSite = [this](Point2 p) { return p.x >= minX_ && p.x <= maxX_ && p.y >= minY_ && p.y <= maxY_; };
    if (!onSite(start)) {
        return refuse(RouteRefusal::kStartOffSite);
    }
    if (!onSite(goal)) {
        return refuse(RouteRefusal::kGoalOffSite);
    }
    start_ = start;
    goal_ = goal;
    origin_ = Point2{minX_, minY_};

    if (!shapeLattice(params.spacingM)) {
        return refuse(RouteRefusal::kBadParams);
    }
    boxZones();
    if (!pointClear(start)) {
        return refuse(RouteRefusal::kStartBlocked);
    }
    if (!pointClear(goal)) {
        return refuse(RouteRefusal::kGoalBlocked);
    }
    goalBlock_ = blockOf(goal);

    const std::uint32_t s = lattice_;
    cost_g_[s] = 0.0F;
    parent_[s] = s;
    flags_[s] = kUsable;
    flags_[s + 1] = kUsable;
    key_[s] = static_cast<float>(heuristic(s));
    push(s);
    best_ = s;
    bestH_ = geometry::distance(start, goal);
    refusal_ = RouteRefusal::kNone;
    state_ = RouteState::kSearching;
    return RouteRefusal::kNone;
}

bool GlobalRoute::shapeLattice(double spacingM) {
    // The lattice: the spacing asked for, or the smallest that fits.
    const double w = maxX_ - minX_;
    const double h = maxY_ - minY_;
    double spacing = std::fmax(spacingM, std::sqrt(w * h / static_cast<double>(kMaxRouteNodes)));
    double columns = std::floor(w / spacing) + 1.0;
    double rows = std::floor(h / spacing) + 1.0;
    for (int i = 0; i < 256 && columns * rows > static_cast<double>(kMaxRouteNodes); ++i) {
        spacing *= 1.01;
        columns = std::floor(w / spacing) + 1.0;
        rows = std::floor(h / spacing) + 1.0;
    }
    // 256 steps of 1 % grow the spacing 12-fold, far more than any site
    // within kMaxSiteExtentM needs; the check keeps the arrays safe whatever.
    if (columns * rows > static_cast<double>(kMaxRouteNodes)) {
        return false;
    }
    stats_.columns = static_cast<std::uint32_t>(columns);
    stats_.rows = static_cast<std::uint32_t>(rows);
    stats_.spacingM = spacing;
    lattice_ = stats_.columns * stats_.rows;

    for (std::uint32_t n = 0; n < lattice_ + 2; ++n) {
        cost_g_[n] = INFINITY;
        parent_[n] = kNone;
        heapPos_[n] = kNone;
        flags_[n] = 0;
    }
    stats_.work += static_cast<std::uint64_t>(lattice_ + 2) * kRouteNodeResetWork;
    return true;
}

void GlobalRoute::boxZones() {
    const std::size_t zones = map_->keepOutCount();
    for (std::size_t z = 0; z < zones; ++z) {
        const site_map::KeepOut& zone = map_->keepOut(z);
        double box[4] = {zone.x[0], zone.y[0], zone.x[0], zone.y[0]};
        for (std::size_t k = 1; k < zone.count && k < site_map::kMaxKeepOutVertices; ++k) {
            box[0] = std::fmin(box[0], static_cast<double>(zone.x[k]));
            box[1] = std::fmin(box[1], static_cast<double>(zone.y[k]));
            box[2] = std::fmax(box[2], static_cast<double>(zone.x[k]));
            box[3] = std::fmax(box[3], static_cast<double>(zone.y[k]));
        }
        for (std::size_t c = 0; c < 4; ++c) {
            zoneBox_[z][c] = box[c];
        }
    }
}

bool GlobalRoute::step(std::uint64_t sliceWork) {
    if (state_ != RouteState::kSearching) {
        return true;
    }
    ++stats_.steps;
    const std::uint64_t before = stats_.work;
    // The expansions bound the loop whatever the units cost (each does work).
    for (std::uint32_t i = 0; i < kMaxRouteNodes + 2; ++i) {
        if (stats_.work >= params_.workBudget) {
            finish(RouteState::kBudgetSpent, best_);
            break;
        }
        if (heapSize_ == 0) {
            finish(RouteState::kNoRoute, kNone);
            break;
        }
        const std::uint32_t node = pop();
        if (node == lattice_ + 1) {
            finish(RouteState::kFound, node);
            break;
        }
        expand(node);
        if (stats_.work - before >= sliceWork) {
            break;
        }
    }
    const std::uint64_t did = stats_.work - before;
    stats_.maxStepWork = did > stats_.maxStepWork ? did : stats_.maxStepWork;
    return state_ != RouteState::kSearching;
}

Point2 GlobalRoute::nodePoint(std::uint32_t node) const {
    if (node == lattice_) {
        return start_;
    }
    if (node == lattice_ + 1) {
        return goal_;
    }
    const std::uint32_t i = node % stats_.columns;
    const std::uint32_t j = node / stats_.columns;
    return Point2{origin_.x + stats_.spacingM * i, origin_.y + stats_.spacingM * j};
}

double GlobalRoute::heuristic(std::uint32_t node) const {
    return params_.heuristicWeight * geometry::distance(nodePoint(node), goal_);
}

bool GlobalRoute::pointClear(Point2 p) { return edgeCost(p, p) >= 0.0; }

bool GlobalRoute::nodeUsable(std::uint32_t node) {
    if ((flags_[node] & (kUsable | kBlocked)) == 0) {
        const bool clear = pointClear(nodePoint(node));
        flags_[node] |= clear ? kUsable : kBlocked;
        stats_.nodesBlocked += clear ? 0U : 1U;
    }
    return (flags_[node] & kUsable) != 0;
}

double GlobalRoute::edgeCost(Point2 a, Point2 b) {
    ++stats_.sightLines;
    const double clearance2 = params_.clearanceM * params_.clearanceM;
    site_map::QueryStats q;
    const std::size_t found = map_->rocksNearSegment(a, b, params_.comfortM, &query_, near_, kMaxSightRocks, &q);
    stats_.work += q.cellsVisited * kRouteCellWork + q.refsExamined * kRouteRefWork;
    if (q.overflow || q.refused) {
        ++stats_.sightLinesCrowded;
        return -1.0;
    }
    const double length = geometry::distance(a, b);
    const double comfort2 = params_.comfortM * params_.comfortM;
    const double band = params_.comfortM - params_.clearanceM;
    double penalty = 0.0;
    for (std::size_t k = 0; k < found; ++k) {
        const site_map::Rock& rock = map_->rock(near_[k]);
        Point2 v[site_map::kMaxRockVertices];
        const std::size_t n = rock.count < site_map::kMaxRockVertices ? rock.count : site_map::kMaxRockVertices;
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = Point2{rock.x[i], rock.y[i]};
        }
        stats_.work += n * kRouteEdgeWork;
        const double d2 = geometry::segmentConvexPolygonDistanceSquared(a, b, v, n);
        if (d2 < clearance2) {
            return -1.0;
        }
        if (d2 < comfort2) {
            // How close, times the stretch passed within comfort: the chord
            // of the comfort circle at the least distance, or the edge when
            // shorter (so an edge cut in two costs no less than whole).
            const double closeness = std::fmin(1.0, (params_.comfortM - std::sqrt(d2)) / band);
            const double chord = 2.0 * std::sqrt(comfort2 - d2);
            penalty += closeness * (length < chord ? length : chord);
        }
    }
    const double zoneClearance = params_.clearanceM + params_.zoneMarginM;
    const double zoneClearance2 = zoneClearance * zoneClearance;
    const double loX = (a.x < b.x ? a.x : b.x) - zoneClearance;
    const double hiX = (a.x > b.x ? a.x : b.x) + zoneClearance;
    const double loY = (a.y < b.y ? a.y : b.y) - zoneClearance;
    const double hiY = (a.y > b.y ? a.y : b.y) + zoneClearance;
    const std::size_t zones = map_->keepOutCount();
    for (std::size_t z = 0; z < zones; ++z) {
        stats_.work += kRouteEdgeWork;
        if (hiX < zoneBox_[z][0] || loX > zoneBox_[z][2] || hiY < zoneBox_[z][1] || loY > zoneBox_[z][3]) {
            continue;
        }
        const site_map::KeepOut& zone = map_->keepOut(z);
        Point2 v[site_map::kMaxKeepOutVertices];
        const std::size_t n = zone.count < site_map::kMaxKeepOutVertices ? zone.count : site_map::kMaxKeepOutVertices;
        for (std::size_t i = 0; i < n; ++i) {
            v[i] = Point2{zone.x[i], zone.y[i]};
        }
        stats_.work += n * kRouteEdgeWork;
        if (geometry::segmentConvexPolygonDistanceSquared(a, b, v, n) < zoneClearance2) {
            return -1.0;
        }
    }
    return length + params_.proximityCost * penalty;
}

GlobalRoute::Block GlobalRoute::blockOf(Point2 p) const {
    const auto range = [](double v, std::uint32_t n, std::uint32_t* lo, std::uint32_t* hi) {
        const double f = std::floor(v);
        const double top = static_cast<double>(n - 1);
        const double l = f - 1.0 < 0.0 ? 0.0 : (f - 1.0 > top ? top : f - 1.0);
        const double h = f + 2.0 < 0.0 ? 0.0 : (f + 2.0 > top ? top : f + 2.0);
        *lo = static_cast<std::uint32_t>(l);
        *hi = static_cast<std::uint32_t>(h);
    };
    Block b;
    range((p.x - origin_.x) / stats_.spacingM, stats_.columns, &b.i0, &b.i1);
    range((p.y - origin_.y) / stats_.spacingM, stats_.rows, &b.j0, &b.j1);
    return b;
}

void GlobalRoute::neighboursOf(std::uint32_t node, std::uint32_t* out, std::size_t* count) const {
    *count = 0;
    if (node == lattice_) {
        // The start: the lattice nodes round it (two spacings each way), and
        // the goal straight, when a sight line may reach it.
        const Block b = blockOf(start_);
        for (std::uint32_t j = b.j0; j <= b.j1; ++j) {
            for (std::uint32_t i = b.i0; i <= b.i1; ++i) {
                out[(*count)++] = j * stats_.columns + i;
            }
        }
        if (geometry::distance(start_, goal_) <= kMaxSightM) {
            out[(*count)++] = lattice_ + 1;
        }
        return;
    }
    const std::uint32_t i = node % stats_.columns;
    const std::uint32_t j = node / stats_.columns;
    for (int dj = -1; dj <= 1; ++dj) {
        for (int di = -1; di <= 1; ++di) {
            const std::int64_t ni = static_cast<std::int64_t>(i) + di;
            const std::int64_t nj = static_cast<std::int64_t>(j) + dj;
            if ((di == 0 && dj == 0) || ni < 0 || nj < 0 || ni >= stats_.columns || nj >= stats_.rows) {
                continue;
            }
            out[(*count)++] = static_cast<std::uint32_t>(nj) * stats_.columns + static_cast<std::uint32_t>(ni);
        }
    }
    if (i >= goalBlock_.i0 && i <= goalBlock_.i1 && j >= goalBlock_.j0 && j <= goalBlock_.j1) {
        out[(*count)++] = lattice_ + 1;
    }
}

void GlobalRoute::expand(std::uint32_t node) {
    ++stats_.expansions;
    stats_.work += kRouteExpandWork;
    flags_[node] |= kClosed;
    const double h = geometry::distance(nodePoint(node), goal_);
    if (h < bestH_) {
        bestH_ = h;
        best_ = node;
    }
    std::uint32_t next[kMaxNeighbours];
    std::size_t count = 0;
    neighboursOf(node, next, &count);
    for (std::size_t k = 0; k < count; ++k) {
        const std::uint32_t n = next[k];
        if ((flags_[n] & kClosed) != 0 || !nodeUsable(n)) {
            continue;
        }
        relax(node, n);
    }
}

void GlobalRoute::relax(std::uint32_t from, std::uint32_t to) {
    const Point2 target = nodePoint(to);
    // Theta*: the parent's sight line first, the node's own edge only when
    // that may be cheaper (the edge costs at least its length).
    const std::uint32_t grand = parent_[from];
    double viaGrand = INFINITY;
    if (grand != from && geometry::distance(nodePoint(grand), target) <= kMaxSightM) {
        const double c = edgeCost(nodePoint(grand), target);
        if (c >= 0.0) {
            viaGrand = static_cast<double>(cost_g_[grand]) + c;
            offer(to, grand, viaGrand);
        }
    }
    const double lower = static_cast<double>(cost_g_[from]) + geometry::distance(nodePoint(from), target);
    if (lower < viaGrand && lower < static_cast<double>(cost_g_[to])) {
        const double c = edgeCost(nodePoint(from), target);
        if (c >= 0.0) {
            offer(to, from, static_cast<double>(cost_g_[from]) + c);
        }
    }
}

void GlobalRoute::offer(std::uint32_t node, std::uint32_t parent, double cost) {
    if (!(cost < static_cast<double>(cost_g_[node]))) {
        return;
    }
    cost_g_[node] = static_cast<float>(cost);
    parent_[node] = parent;
    key_[node] = static_cast<float>(cost + heuristic(node));
    if (heapPos_[node] == kNone) {
        push(node);
    } else {
        siftUp(heapPos_[node]);
    }
}

void GlobalRoute::finish(RouteState state, std::uint32_t last) {
    state_ = state;
    pointCount_ = 0;
    if (last == kNone) {
        return;
    }
    // Count the route's points (parents lead back to the start; each node
    // at most once, so lattice_ + 2 bounds the walk).
    std::size_t count = 1;
    std::uint32_t n = last;
    for (std::uint32_t guard = 0; n != lattice_ && guard < lattice_ + 2; ++guard) {
        n = parent_[n];
        ++count;
    }
    if (count > kMaxRoutePoints || n != lattice_) {
        state_ = RouteState::kRefused;
        refusal_ = RouteRefusal::kRouteTooLong;
        return;
    }
    if (count == 1) {
        // The best node is the start itself (nothing nearer the goal was
        // expanded): a route of the start alone, twice.
        points_[0] = start_;
        points_[1] = start_;
        pointCount_ = 2;
        return;
    }
    n = last;
    for (std::size_t k = count; k-- > 0;) {
        points_[k] = nodePoint(n);
        n = parent_[n];
    }
    pointCount_ = count;
    lengthM_ = 0.0;
    for (std::size_t k = 1; k < count; ++k) {
        lengthM_ += geometry::distance(points_[k - 1], points_[k]);
    }
    cost_ = static_cast<double>(cost_g_[last]);
}

void GlobalRoute::push(std::uint32_t node) {
    heap_[heapSize_] = node;
    heapPos_[node] = heapSize_;
    ++heapSize_;
    siftUp(heapSize_ - 1);
}

std::uint32_t GlobalRoute::pop() {
    const std::uint32_t top = heap_[0];
    --heapSize_;
    heapPos_[top] = kNone;
    if (heapSize_ > 0) {
        heap_[0] = heap_[heapSize_];
        heapPos_[heap_[0]] = 0;
        siftDown(0);
    }
    return top;
}

void GlobalRoute::siftUp(std::uint32_t at) {
    const std::uint32_t node = heap_[at];
    while (at > 0) {
        const std::uint32_t up = (at - 1) / 2;
        if (!(key_[node] < key_[heap_[up]])) {
            break;
        }
        heap_[at] = heap_[up];
        heapPos_[heap_[at]] = at;
        at = up;
    }
    heap_[at] = node;
    heapPos_[node] = at;
}

void GlobalRoute::siftDown(std::uint32_t at) {
    const std::uint32_t node = heap_[at];
    while (2 * at + 1 < heapSize_) {
        std::uint32_t child = 2 * at + 1;
        if (child + 1 < heapSize_ && key_[heap_[child + 1]] < key_[heap_[child]]) {
            ++child;
        }
        if (!(key_[heap_[child]] < key_[node])) {
            break;
        }
        heap_[at] = heap_[child];
        heapPos_[heap_[at]] = at;
        at = child;
    }
    heap_[at] = node;
    heapPos_[node] = at;
}

}  // namespace rse::deliberative
