#include "fsw/habitual/path_shortcut.hpp"

#include <cmath>

namespace rse::habitual {

using geometry::Point2;

double pathLength(const Point2* path, std::size_t count) {
    double length = 0.0;
    for (std::size_t i = 1; path != nullptr && i < count; ++i) {
        length += distance(path[i - 1], path[i]);
    }
    return length;
}

std::size_t shortcutPath(const LocalMap& map, Point2* path, std::size_t count) {
    if (path == nullptr) {
        return 0;
    }
    if (count < 3 || count > kMaxShortcutPoints) {
        return count;
    }
    // path[0..kept) is the output so far; `from` indexes the input point it ends at.
    // Writing never overtakes reading: kept <= from + 1 <= the next index read.
    std::size_t kept = 1;
    std::size_t from = 0;
    while (from + 1 < count) {  // from rises by at least one per pass: at most count passes
        std::size_t to = from + 1;
        for (std::size_t j = count - 1; j > from + 1; --j) {
            if (map.segmentFree(path[from], path[j])) {
                to = j;
                break;
            }
        }
        path[kept++] = path[to];
        from = to;
    }
    return kept;
}

std::size_t cutPathAtDisc(Point2* path, std::size_t count, Point2 centre, double radiusM) {
    if (path == nullptr) {
        return 0;
    }
    const double r2 = radiusM * radiusM;
    if (!(radiusM > 0.0) || count < 2 || distanceSquared(path[0], centre) <= r2) {
        return count;
    }
    // Segment i: p(t) = path[i] + t d, t in [0, 1]; |p(t) - centre|^2 = r^2 is
    // a t^2 + b t + c = 0 with c > 0 while path[i] lies outside (every point
    // before the first entry does), so the smaller root is the entry.
    for (std::size_t i = 0; i + 1 < count; ++i) {
        const Point2 d = path[i + 1] - path[i];
        const Point2 f = path[i] - centre;
        const double a = dot(d, d);
        const double b = 2.0 * dot(f, d);
        const double c = dot(f, f) - r2;
        const double disc = b * b - 4.0 * a * c;
        if (!(a > 0.0) || disc < 0.0) {
            continue;
        }
        const double t = (-b - std::sqrt(disc)) / (2.0 * a);
        if (t >= 0.0 && t <= 1.0) {
            path[i + 1] = path[i] + t * d;
            return i + 2;
        }
    }
    return count;
}

}  // namespace rse::habitual
