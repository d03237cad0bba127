#include "fsw/habitual/escape_search.hpp"

#include <cmath>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/geometry/site_bounds.hpp"

namespace rse::habitual {

using geometry::distanceToCoarseMap;
using geometry::Point2;

bool EscapeSearch::offSite(Point2 start) const {
    return geometry::outsideBy(geometry::siteBox(coarse_, 0.0), start.x, start.y) > 0.0;
}

bool EscapeSearch::findEscape(Point2 start, double headingRad, Point2* exit) const {
    // The seen hazard the start lies deepest inside (the planning map is at the
    // bare footprint here: its discs are the remembered ones plus the footprint).
    const RememberedHazard* deepest = nullptr;
    double depth = 0.0;
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = hazards_.slot(k);
        if (!h.used) {
            continue;
        }
        const double d = h.radiusM + footprintM_ - distance(start, h.centre);
        if (d > depth) {
            depth = d;
            deepest = &h;
        }
    }
    if (deepest == nullptr) {
        return false;  // blocked by a coarse-map polygon or the bounds: no escape from a disc
    }
    const double away = distance(start, deepest->centre);
    const double base = away > 1e-6 ? std::atan2(start.y - deepest->centre.y, start.x - deepest->centre.x)
                                    : headingRad + 3.141592653589793;
    // Straight away first; then turned either way, in case that runs towards
    // another obstacle.
    const double turns[] = {0.0, 0.5236, -0.5236, 1.0472, -1.0472, 1.5708, -1.5708};
    const double keep = footprintM_ + marginM_;
    for (const double turn : turns) {
        const Point2 u{std::cos(base + turn), std::sin(base + turn)};
        double reach = deepest->radiusM + keep + kEscapeExtraM;
        for (std::uint32_t i = 0; i < kEscapeSteps; ++i, reach += kEscapeStepM) {
            const Point2 p = deepest->centre + reach * u;
            if (distance(p, start) > kMaxEscapeM) {
                break;
            }
            if (planMap_.pointFree(p) && escapeClear(start, p, deepest)) {
                *exit = p;
                return true;
            }
        }
    }
    return false;
}

bool EscapeSearch::findReentry(Point2 start, Point2* exit) const {
    const double keep = footprintM_ + marginM_;
    const geometry::SiteBox site = geometry::siteBox(coarse_, keep + kEscapeExtraM);
    Point2 nearest{0.0, 0.0};
    if (!geometry::nearestInside(site, start.x, start.y, &nearest.x, &nearest.y)) {
        return false;  // a site narrower than the rover's keep: nowhere to go
    }
    // Along the edge either way from the nearest point, in case a rock stands there.
    const Point2 inward = nearest - start;
    const double length = std::hypot(inward.x, inward.y);
    const Point2 along = length > 1e-9 ? Point2{-inward.y / length, inward.x / length} : Point2{1.0, 0.0};
    for (std::uint32_t i = 0; i <= 2 * kEscapeSteps; ++i) {
        const double step = static_cast<double>((i + 1) / 2) * kEscapeStepM * ((i % 2 == 1) ? 1.0 : -1.0);
        const Point2 slid = nearest + step * along;
        Point2 p{0.0, 0.0};
        if (!geometry::nearestInside(site, slid.x, slid.y, &p.x, &p.y) || distance(p, start) > kMaxReentryM) {
            continue;
        }
        if (planMap_.pointFree(p) && escapeClear(start, p, nullptr)) {
            *exit = p;
            return true;
        }
    }
    return false;
}

bool EscapeSearch::escapeClear(Point2 start, Point2 exit, const RememberedHazard* leaving) const {
    // The end keeps the planning margin from every other obstacle; the way
    // there keeps the bare footprint from the mapped rocks.
    const double keep = footprintM_ + marginM_;
    if (distanceToCoarseMap(coarse_, exit) < keep) {
        return false;
    }
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = hazards_.slot(k);
        if (h.used && &h != leaving && distance(exit, h.centre) < h.radiusM + keep) {
            return false;
        }
    }
    const double length = distance(start, exit);
    for (std::uint32_t i = 1; i <= kEscapeChecks; ++i) {
        const double f = static_cast<double>(i) / static_cast<double>(kEscapeChecks);
        const Point2 q = start + f * (exit - start);
        if (length > 0.0 && distanceToCoarseMap(coarse_, q) < footprintM_) {
            return false;
        }
        if (length > 0.0 && intoOtherDisc(start, q, leaving)) {
            return false;
        }
    }
    return true;
}

bool EscapeSearch::intoOtherDisc(Point2 start, Point2 q, const RememberedHazard* leaving) const {
    // The way keeps the bare footprint from every other remembered disc (a
    // contact the follower felt is one: the way out once drove through it
    // again and again). A disc the start already lies in only blocks a way
    // that goes deeper into it.
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = hazards_.slot(k);
        if (!h.used || &h == leaving) {
            continue;
        }
        const double d = distance(q, h.centre);
        if (d < h.radiusM + footprintM_ && d < distance(start, h.centre)) {
            return true;
        }
    }
    return false;
}

}  // namespace rse::habitual
