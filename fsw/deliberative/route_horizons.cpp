#include "fsw/deliberative/route_horizons.hpp"

#include <cmath>

#include "fsw/deliberative/plan_maker.hpp"

namespace rse::deliberative {

using geometry::Point2;

void RouteHorizons::announce(core::TimeNs foundAt, std::uint8_t goalIndex) {
    ++routeNumber_;
    foundAt_ = foundAt;
    goalIndex_ = goalIndex;
    nextChunk_ = 0;
    const std::size_t n = route_.pointCount();
    chunkCount_ = routed() ? (n + msg::kRouteChunkPoints - 1) / msg::kRouteChunkPoints : 0;
}

bool RouteHorizons::nextChunk(msg::RouteChunkMsg* out) {
    if (nextChunk_ >= chunkCount_ || !routed()) {
        return false;
    }
    *out = msg::RouteChunkMsg{};
    out->timeNs = foundAt_;
    out->routeNumber = routeNumber_;
    out->pointCount = static_cast<std::uint16_t>(route_.pointCount());
    out->chunkIndex = static_cast<std::uint8_t>(nextChunk_);
    out->chunkCount = static_cast<std::uint8_t>(chunkCount_);
    out->goalIndex = goalIndex_;
    out->lengthM = route_.lengthM();
    out->goalX = goal_.x;
    out->goalY = goal_.y;
    const std::size_t first = nextChunk_ * msg::kRouteChunkPoints;
    for (std::size_t k = 0; k < msg::kRouteChunkPoints && first + k < route_.pointCount(); ++k) {
        out->x[k] = static_cast<float>(route_.point(first + k).x);
        out->y[k] = static_cast<float>(route_.point(first + k).y);
        out->count = static_cast<std::uint8_t>(k + 1);
    }
    ++nextChunk_;
    return true;
}

RouteRefusal RouteHorizons::begin(const site_map::SiteMap& map, Point2 from, Point2 goal, double footprintRadiusM,
                                  const RouteMargins& margins) {
    valid_ = false;
    chunkCount_ = 0;
    progress_ = 0;
    map_ = &map;
    goal_ = goal;
    revision_ = map.revision();
    RouteParams params;
    params.clearanceM = footprintRadiusM + margins.marginM;
    params.comfortM = params.clearanceM + margins.comfortM;
    params.zoneMarginM = margins.zoneMarginM;
    const RouteRefusal refusal = route_.start(map, from, goal, params);
    valid_ = refusal == RouteRefusal::kNone;
    return refusal;
}

bool RouteHorizons::step() { return route_.step(kSliceWork); }

bool RouteHorizons::routes(Point2 goal, std::uint32_t revision) const {
    return routed() && goal.x == goal_.x && goal.y == goal_.y && revision == revision_ && map_ != nullptr &&
           map_->revision() == revision;
}

bool RouteHorizons::next(Point2 from, const HorizonReach& reach, Horizon* out) {
    const std::size_t n = route_.pointCount();
    if (!routed() || n < 2 || !geometry::isFinite(from)) {
        return false;
    }
    // The rover's place: the nearest point of the segments from the last place on.
    std::size_t segment = progress_ < n - 1 ? progress_ : n - 2;
    Point2 place = route_.point(segment);
    double nearest = INFINITY;
    for (std::size_t k = segment; k + 1 < n; ++k) {
        const Point2 q = geometry::closestOnSegment(from, route_.point(k), route_.point(k + 1));
        const double d = geometry::distanceSquared(from, q);
        if (d < nearest) {
            nearest = d;
            place = q;
            segment = k;
        }
    }
    progress_ = segment;
    double remaining = geometry::distance(place, route_.point(segment + 1));
    for (std::size_t k = segment + 1; k + 1 < n; ++k) {
        remaining += geometry::distance(route_.point(k), route_.point(k + 1));
    }
    out->last = remaining <= reach.lastFactor * reach.lengthM;
    out->count = 0;
    const auto add = [out](Point2 p) {
        // The last slot is kept for the horizon's goal.
        if (out->count + 1 < kMaxCorridorPoints &&
            (out->count == 0 || geometry::distanceSquared(out->corridor[out->count - 1], p) > 1e-12)) {
            out->corridor[out->count++] = p;
        }
    };
    add(from);
    add(place);
    double left = out->last ? HUGE_VAL : reach.lengthM;
    Point2 at = place;
    out->goal = route_.point(n - 1);
    for (std::size_t k = segment; k + 1 < n; ++k) {
        const Point2 end = route_.point(k + 1);
        const double length = geometry::distance(at, end);
        if (length >= left) {
            out->goal = at + (left / length) * (end - at);
            break;
        }
        left -= length;
        at = end;
        if (k + 2 < n) {
            add(end);
        }
    }
    if (out->count == 0 || geometry::distanceSquared(out->corridor[out->count - 1], out->goal) > 1e-12) {
        out->corridor[out->count++] = out->goal;
    }
    if (out->count < 2) {
        // The rover at the goal itself: a corridor of the point, twice.
        out->corridor[out->count++] = out->goal;
    }
    return true;
}

}  // namespace rse::deliberative
