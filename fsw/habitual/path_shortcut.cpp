#include "fsw/habitual/path_shortcut.hpp"

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

}  // namespace rse::habitual
