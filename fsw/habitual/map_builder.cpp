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

namespace {

// The smallest disc enclosing discs a and b (a or b itself when it encloses the other).
Point2 enclosingDisc(Point2 a, double ra, Point2 b, double rb, double* radius) {
    const double apart = distance(a, b);
    if (apart + rb <= ra) {
        *radius = ra;
        return a;
    }
    if (apart + ra <= rb) {
        *radius = rb;
        return b;
    }
    const double enclosing = 0.5 * (apart + ra + rb);
    *radius = enclosing;
    return a + ((enclosing - ra) / apart) * (b - a);
}

bool siteUsable(const SiteWindow* site) { return site != nullptr && site->map != nullptr && site->query != nullptr && site->map->loaded(); }

// A site rock's vertices; their count.
std::size_t siteRockVertices(const site_map::SiteMap& map, std::uint16_t id, Point2* out) {
    const site_map::Rock& rock = map.rock(id);
    const std::size_t n = rock.count < kMaxPolygonVertices ? rock.count : kMaxPolygonVertices;
    for (std::size_t v = 0; v < n; ++v) {
        out[v] = Point2{rock.x[v], rock.y[v]};
    }
    return n;
}

// p within marginM of a site-map rock (a rock's polygon, measured exactly).
bool nearSiteRock(const SiteWindow* site, Point2 p, double marginM) {
    if (!siteUsable(site)) {
        return false;
    }
    std::uint16_t near[16];
    site_map::QueryStats stats;
    const std::size_t found = site->map->rocksNearSegment(p, p, marginM, site->query, near, 16, &stats);
    for (std::size_t k = 0; k < found; ++k) {
        Point2 v[kMaxPolygonVertices];
        const std::size_t n = siteRockVertices(*site->map, near[k], v);
        if (geometry::segmentConvexPolygonDistanceSquared(p, p, v, n) <= marginM * marginM) {
            return true;
        }
    }
    return false;
}

}  // namespace

SightingOutcome MapBuilder::remember(const tables::CoarseMapTable& coarse, Point2 roverPosition,
                                     double roverHeadingRad, const msg::HazardSightingTlm& sighting,
                                     const SiteWindow* site) {
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
    const Point2 nearest{roverPosition.x + sighting.rangeM * std::cos(direction),
                         roverPosition.y + sighting.rangeM * std::sin(direction)};
    const bool onMappedRock = distanceToCoarseMap(coarse, nearest) <= kKnownObstacleMarginM ||
                              nearSiteRock(site, nearest, kKnownObstacleMarginM);
    // A mapped rock seen again: both the surface seen (the nearest point) and
    // the centre estimated behind it lie on it (within the margin). The centre
    // alone is not enough: a hidden rock beside a mapped one has its centre
    // within the margin of it while its surface stands clear in front, and was
    // dismissed as the mapped rock (a field of issue 31: the rover, passing the
    // mapped rock at 0.3 m, drove into the hidden one beside it).
    if (onMappedRock && (distanceToCoarseMap(coarse, centre) <= kKnownObstacleMarginM ||
                         nearSiteRock(site, centre, kKnownObstacleMarginM))) {
        ++known_;
        return SightingOutcome::kKnownObstacle;
    }
    // The seen part's disc (the deliberative layer's estimate) and the cover of
    // every rock the sighting allows (the habitual layer's): same centre. A
    // nearest point on (within the margin of) a mapped rock is that rock's
    // surface: the map has the rock whole, so the cover is the seen disc.
    const double seenRadius = std::fmax(kSightingRadiusFactor * sighting.halfWidthM, kMinHazardRadiusM);
    const double coverRadius =
        onMappedRock ? seenRadius : std::fmax(kCoverRadiusFactor * sighting.halfWidthM, kMinHazardRadiusM);

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
        // A contact's disc is never the oldest sighting: nothing will see it again.
        if (s.used && s.obstacleId != kContactObstacleId &&
            (slots_[oldest].obstacleId == kContactObstacleId || s.lastSeen < slots_[oldest].lastSeen)) {
            oldest = i;
        }
    }
    SightingOutcome outcome = SightingOutcome::kUpdated;
    Point2 seenCentre = centre;
    double seenR = seenRadius;
    Point2 coverCentre = centre;
    double coverR = coverRadius;
    if (chosen != kMaxMapDiscs) {
        RememberedHazard& old = slots_[chosen];
        const bool seenInside = distance(old.seenCentre, centre) + seenRadius <= old.seenRadiusM;
        const bool coverInside = distance(old.centre, centre) + coverRadius <= old.radiusM;
        if (seenInside && coverInside) {
            old.lastSeen = sightings_;
            ++unchanged_;
            return SightingOutcome::kUnchanged;
        }
        // The seen discs decide whether it is the same obstacle: round both
        // within kMaxMergedRadiusM, each disc becomes the disc round its old and
        // new self; otherwise the new sighting replaces both.
        double mergedSeenR = 0.0;
        const Point2 mergedSeen = enclosingDisc(old.seenCentre, old.seenRadiusM, centre, seenRadius, &mergedSeenR);
        if (mergedSeenR <= kMaxMergedRadiusM) {
            seenCentre = mergedSeen;
            seenR = mergedSeenR;
            coverCentre = enclosingDisc(old.centre, old.radiusM, centre, coverRadius, &coverR);
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
    slots_[chosen] = RememberedHazard{coverCentre, coverR, seenCentre, seenR, sightings_, sighting.obstacleId, true};
    ++revision_;
    return outcome;
}

SightingOutcome MapBuilder::rememberContact(Point2 centre, double seenRadiusM, double coverRadiusM) {
    if (!isFinite(centre) || !std::isfinite(seenRadiusM) || !std::isfinite(coverRadiusM) || seenRadiusM <= 0.0 ||
        coverRadiusM < seenRadiusM || coverRadiusM > kMaxMergedRadiusM) {
        ++rejected_;
        return SightingOutcome::kRejected;
    }
    // A free slot; else, with kMaxContactDiscs contacts held, the oldest
    // contact; else the sighting seen longest ago.
    std::size_t freeSlot = kMaxMapDiscs;
    std::size_t oldestContact = kMaxMapDiscs;
    std::size_t oldestSighting = kMaxMapDiscs;
    std::size_t contacts = 0;
    for (std::size_t i = 0; i < kMaxMapDiscs; ++i) {
        const RememberedHazard& h = slots_[i];
        if (!h.used) {
            freeSlot = freeSlot == kMaxMapDiscs ? i : freeSlot;
        } else if (h.obstacleId == kContactObstacleId) {
            ++contacts;
            oldestContact = oldestContact == kMaxMapDiscs || h.lastSeen < slots_[oldestContact].lastSeen ? i : oldestContact;
        } else {
            oldestSighting =
                oldestSighting == kMaxMapDiscs || h.lastSeen < slots_[oldestSighting].lastSeen ? i : oldestSighting;
        }
    }
    std::size_t chosen = freeSlot;
    SightingOutcome outcome = SightingOutcome::kAdded;
    if (chosen == kMaxMapDiscs) {
        chosen = contacts >= kMaxContactDiscs || oldestSighting == kMaxMapDiscs ? oldestContact : oldestSighting;
        outcome = SightingOutcome::kReplacedOldest;
        ++replaced_;
    } else {
        ++added_;
    }
    ++sightings_;
    slots_[chosen] = RememberedHazard{centre, coverRadiusM, centre, seenRadiusM, sightings_, kContactObstacleId, true};
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
                              const MapRelief* relief, SiteWindow* site) const {
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
    if (siteUsable(site)) {
        std::uint16_t near[kMaxMapPolygons + 1];
        site_map::QueryStats stats;
        const std::size_t found = site->map->rocksNearSegment(site->centre, site->centre, site->reachM, site->query,
                                                              near, kMaxMapPolygons + 1, &stats);
        if (stats.overflow || stats.refused) {
            site->incomplete = true;
            first = core::isOk(first) ? core::Status::kFull : first;
        }
        for (std::size_t k = 0; k < found; ++k) {
            Point2 vertices[kMaxPolygonVertices];
            const std::size_t n = siteRockVertices(*site->map, near[k], vertices);
            const core::Status st = map->addPolygon(vertices, n);
            if (!core::isOk(st)) {
                site->incomplete = true;
                first = core::isOk(first) ? st : first;
            }
        }
    }
    for (const RememberedHazard& h : slots_) {
        if (!h.used) {
            continue;
        }
        Point2 centre = h.centre;
        double full = h.radiusM;
        if (relief != nullptr && relief->hasSeenAt && distance(relief->seenAt, h.centre) < h.radiusM + clearanceM) {
            centre = h.seenCentre;
            full = h.seenRadiusM;
        }
        double radius = full;
        for (std::size_t i = 0; relief != nullptr && i < relief->count && i < 2; ++i) {
            if (distance(relief->at[i], centre) < full + clearanceM) {
                radius = full > relief->marginM ? full - relief->marginM : 0.0;
            }
        }
        const core::Status st = map->addDisc(centre, radius);
        if (!core::isOk(st) && core::isOk(first)) {
            first = st;
        }
    }
    return first;
}

}  // namespace rse::habitual
