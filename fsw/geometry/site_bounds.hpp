// The site: the rectangle of the coarse (orbital) map, COARSE_MAP's bounds.
// Off it the orbital map says nothing, so the health monitor raises "off the
// map" there, and both planning layers bring a rover that stands off it back
// on along the shortest way in (the deliberative layer plans from that point,
// the habitual layer drives to it). Shared by them, so it sits below both.
#pragma once

#include <cmath>

#include "fsw/tables/table_types.hpp"

namespace rse::geometry {

struct SiteBox {
    double minX = 0.0, maxX = 0.0, minY = 0.0, maxY = 0.0;
};

// The site shrunk by insetM on every side (insetM 0: the bounds themselves).
// An inset larger than half the site gives an empty box (min > max).
inline SiteBox siteBox(const tables::CoarseMapTable& map, double insetM) {
    return SiteBox{static_cast<double>(map.x_min_m) + insetM, static_cast<double>(map.x_max_m) - insetM,
                   static_cast<double>(map.y_min_m) + insetM, static_cast<double>(map.y_max_m) - insetM};
}

// How far (x, y) lies outside the box along the worse axis; negative: inside,
// by that much from the nearest edge.
inline double outsideBy(const SiteBox& box, double x, double y) {
    return std::fmax(std::fmax(box.minX - x, x - box.maxX), std::fmax(box.minY - y, y - box.maxY));
}

// The point of the box nearest to (x, y): (x, y) itself when inside. False
// (nothing written) for an empty box or a non-finite point.
inline bool nearestInside(const SiteBox& box, double x, double y, double* outX, double* outY) {
    if (!(box.minX <= box.maxX && box.minY <= box.maxY) || !std::isfinite(x) || !std::isfinite(y)) {
        return false;
    }
    *outX = std::fmin(std::fmax(x, box.minX), box.maxX);
    *outY = std::fmin(std::fmax(y, box.minY), box.maxY);
    return true;
}

}  // namespace rse::geometry
