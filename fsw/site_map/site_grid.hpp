// The site map's spatial index shape (site_map.hpp): square cells over the
// site, as few as kMaxGridCells allow but never under kMinCellM a side. Both
// the image check (to refuse a map whose index would not fit) and the store
// use it, so they agree on every cell. Pure.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/site_map/site_map_image.hpp"

namespace rse::site_map {

constexpr std::size_t kMaxGridCells = 65536;
constexpr double kMinCellM = 2.0;
// Rock references the cells may hold in all (a rock is listed in every cell
// its bounding box touches): 8 a rock at the most rocks. A reference is a
// rock's number (u16: kMaxSiteRocks < 65 536), a cell's start a u32.
constexpr std::size_t kMaxCellRefs = 8 * kMaxSiteRocks;
static_assert(kMaxSiteRocks < 65536, "a cell reference is a u16 rock number");

struct GridShape {
    double x0 = 0.0, y0 = 0.0;  // the site's lower-left corner
    double cellM = kMinCellM;
    std::uint32_t columns = 1, rows = 1;

    // The cell column (row) of x (y), clamped to the grid.
    std::uint32_t column(double x) const { return clampIndex((x - x0) / cellM, columns); }
    std::uint32_t row(double y) const { return clampIndex((y - y0) / cellM, rows); }
    std::size_t cell(std::uint32_t c, std::uint32_t r) const { return static_cast<std::size_t>(r) * columns + c; }

private:
    static std::uint32_t clampIndex(double v, std::uint32_t n) {
        if (!(v > 0.0)) {
            return 0;
        }
        const double top = static_cast<double>(n - 1);
        return v >= top ? n - 1 : static_cast<std::uint32_t>(v);
    }
};

// The grid of a site (bounds already checked: finite, non-empty, within kMaxSiteExtentM).
inline GridShape gridFor(const SiteBounds& site) {
    GridShape g;
    g.x0 = static_cast<double>(site.xMin);
    g.y0 = static_cast<double>(site.yMin);
    const double w = static_cast<double>(site.xMax) - g.x0;
    const double h = static_cast<double>(site.yMax) - g.y0;
    double cell = std::sqrt(w * h / static_cast<double>(kMaxGridCells));
    cell = cell > kMinCellM ? cell : kMinCellM;
    // Round the columns and rows up; grow the cell until they fit.
    for (int i = 0; i < 64; ++i) {
        const double columns = std::ceil(w / cell);
        const double rows = std::ceil(h / cell);
        if (columns * rows <= static_cast<double>(kMaxGridCells)) {
            g.columns = static_cast<std::uint32_t>(columns > 1.0 ? columns : 1.0);
            g.rows = static_cast<std::uint32_t>(rows > 1.0 ? rows : 1.0);
            break;
        }
        cell *= 1.01;
    }
    g.cellM = cell;
    return g;
}

}  // namespace rse::site_map
