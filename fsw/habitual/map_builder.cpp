#include "fsw/habitual/map_builder.hpp"

#include <cmath>

namespace rse::habitual {

namespace {

std::size_t usedVertices(const tables::CoarseMapTable& coarse, std::size_t slot) {
    const std::size_t n = coarse.vertex_count[slot];
    return n >= 3 && n <= kCoarseMapVerticesPerSlot ? n : 0;
}

std::size_t usedSlots(const tables::CoarseMapTable& coarse) {
    const std::size_t n = coarse.obstacle_count;
    return n <= kCoarseMapSlots ? n : kCoarseMapSlots;
}

Point2 vertexOf(const tables::CoarseMapTable& coarse, std::size_t slot, std::size_t vertex) {
    const std::size_t i = slot * kCoarseMapVerticesPerSlot + vertex;
    return Point2{static_cast<double>(coarse.vertex_x_m[i]), static_cast<double>(coarse.vertex_y_m[i])};
}

// Distance from p to one convex polygon of the table, either winding; 0 inside.
double distanceToPolygon(const tables::CoarseMapTable& coarse, std::size_t slot, std::size_t count, Point2 p) {
    bool left = true;   // p left of (or on) every edge
    bool right = true;  // p right of (or on) every edge
    double best = INFINITY;
    for (std::size_t v = 0; v < count; ++v) {
        const Point2 a = vertexOf(coarse, slot, v);
        const Point2 b = vertexOf(coarse, slot, v + 1 == count ? 0 : v + 1);
        const double side = cross(b - a, p - a);
        left = left && side >= 0.0;
        right = right && side <= 0.0;
        const double d2 = pointSegmentDistanceSquared(p, a, b);
        best = d2 < best ? d2 : best;
    }
    return (left || right) ? 0.0 : std::sqrt(best);
}

}  // namespace

double MapBuilder::distanceToCoarseMap(const tables::CoarseMapTable& coarse, Point2 p) {
    double best = INFINITY;
    const std::size_t slots = usedSlots(coarse);
    for (std::size_t s = 0; s < slots; ++s) {
        const std::size_t n = usedVertices(coarse, s);
        if (n == 0) {
            continue;
        }
        const double d = distanceToPolygon(coarse, s, n, p);
        best = d < best ? d : best;
    }
    return best;
}

SightingOutcome MapBuilder::remember(const tables::CoarseMapTable& coarse, Point2 roverPosition,
                                     double roverHeadingRad, const msg::HazardSightingTlm& sighting) {
    ++sightings_;
    const bool finite = std::isfinite(sighting.rangeM) && std::isfinite(sighting.bearingRad) &&
                        std::isfinite(sighting.halfWidthM) && isFinite(roverPosition) &&
                        std::isfinite(roverHeadingRad);
    if (!finite || sighting.obstacleId == 0 || sighting.rangeM < 0.0 || sighting.rangeM > kMaxSightingRangeM ||
        sighting.halfWidthM < 0.0 || sighting.halfWidthM > kMaxSightingRangeM) {
        ++rejected_;
        return SightingOutcome::kRejected;
    }
    const double direction = roverHeadingRad + sighting.bearingRad;
    const double reach = sighting.rangeM + sighting.halfWidthM;
    const Point2 centre{roverPosition.x + reach * std::cos(direction), roverPosition.y + reach * std::sin(direction)};
    if (distanceToCoarseMap(coarse, centre) <= kKnownObstacleMarginM) {
        ++known_;
        return SightingOutcome::kKnownObstacle;
    }
    const double radius = std::fmax(kSightingRadiusFactor * sighting.halfWidthM, kMinHazardRadiusM);

    // The id's own slot, else a free one, else the one seen longest ago.
    std::size_t chosen = kMaxMapDiscs;
    std::size_t freeSlot = kMaxMapDiscs;
    std::size_t oldest = 0;
    for (std::size_t i = 0; i < kMaxMapDiscs; ++i) {
        const RememberedHazard& s = slots_[i];
        if (s.used && s.obstacleId == sighting.obstacleId) {
            chosen = i;
            break;
        }
        if (!s.used && freeSlot == kMaxMapDiscs) {
            freeSlot = i;
        }
        if (s.used && s.lastSeen < slots_[oldest].lastSeen) {
            oldest = i;
        }
    }
    SightingOutcome outcome = SightingOutcome::kUpdated;
    Point2 mergedCentre = centre;
    double mergedRadius = radius;
    if (chosen != kMaxMapDiscs) {
        RememberedHazard& old = slots_[chosen];
        const double apart = distance(old.centre, centre);
        if (apart + radius <= old.radiusM) {
            old.lastSeen = sightings_;
            ++unchanged_;
            return SightingOutcome::kUnchanged;
        }
        if (apart + old.radiusM > radius) {  // neither encloses the other: the disc round both
            const double enclosing = 0.5 * (apart + old.radiusM + radius);
            if (enclosing <= kMaxMergedRadiusM) {
                mergedCentre = old.centre + ((enclosing - old.radiusM) / apart) * (centre - old.centre);
                mergedRadius = enclosing;
            }
        }
    }
    if (chosen == kMaxMapDiscs) {
        if (freeSlot != kMaxMapDiscs) {
            chosen = freeSlot;
            outcome = SightingOutcome::kAdded;
            ++added_;
        } else {
            chosen = oldest;
            outcome = SightingOutcome::kReplacedOldest;
            ++replaced_;
        }
    } else {
        ++updated_;
    }
    slots_[chosen] = RememberedHazard{mergedCentre, mergedRadius, sightings_, sighting.obstacleId, true};
    ++revision_;
    return outcome;
}

void MapBuilder::forgetAll() {
    for (RememberedHazard& s : slots_) {
        s = RememberedHazard{};
    }
    ++revision_;
}

std::size_t MapBuilder::rememberedCount() const {
    std::size_t n = 0;
    for (const RememberedHazard& s : slots_) {
        n += s.used ? 1U : 0U;
    }
    return n;
}

core::Status MapBuilder::build(const tables::CoarseMapTable& coarse, double clearanceM, LocalMap* map,
                              const MapRelief* relief) const {
    if (map == nullptr) {
        return core::Status::kInvalidArgument;
    }
    core::Status first = map->reset(Point2{static_cast<double>(coarse.x_min_m), static_cast<double>(coarse.y_min_m)},
                                    Point2{static_cast<double>(coarse.x_max_m), static_cast<double>(coarse.y_max_m)},
                                    clearanceM);
    if (!core::isOk(first)) {
        return first;
    }
    const std::size_t slots = usedSlots(coarse);
    for (std::size_t s = 0; s < slots; ++s) {
        const std::size_t n = usedVertices(coarse, s);
        if (n == 0) {
            continue;
        }
        Point2 vertices[kCoarseMapVerticesPerSlot];
        for (std::size_t v = 0; v < n; ++v) {
            vertices[v] = vertexOf(coarse, s, v);
        }
        const core::Status st = map->addPolygon(vertices, n);
        if (!core::isOk(st) && core::isOk(first)) {
            first = st;
        }
    }
    for (const RememberedHazard& h : slots_) {
        if (!h.used) {
            continue;
        }
        double radius = h.radiusM;
        for (std::size_t i = 0; relief != nullptr && i < relief->count && i < 2; ++i) {
            if (distance(relief->at[i], h.centre) < h.radiusM + clearanceM) {
                radius = h.radiusM > relief->marginM ? h.radiusM - relief->marginM : 0.0;
            }
        }
        const core::Status st = map->addDisc(h.centre, radius);
        if (!core::isOk(st) && core::isOk(first)) {
            first = st;
        }
    }
    return first;
}

}  // namespace rse::habitual
