#include "fsw/habitual/map_builder.hpp"

#include <cmath>

#include "fsw/geometry/coarse_map.hpp"

namespace rse::habitual {

using geometry::coarseMapSlotsUsed;
using geometry::coarseMapVertex;
using geometry::coarseMapVerticesUsed;
using geometry::distanceToCoarseMap;
using geometry::kCoarseMapVerticesPerSlot;
using geometry::Point2;

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
    const std::size_t slots = coarseMapSlotsUsed(coarse);
    for (std::size_t s = 0; s < slots; ++s) {
        const std::size_t n = coarseMapVerticesUsed(coarse, s);
        if (n == 0) {
            continue;
        }
        Point2 vertices[kCoarseMapVerticesPerSlot];
        for (std::size_t v = 0; v < n; ++v) {
            vertices[v] = coarseMapVertex(coarse, s, v);
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
