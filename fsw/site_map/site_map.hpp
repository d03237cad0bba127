// The site map in force (docs/site_map.md): the rocks and keep-out zones of a
// whole site, loaded from a checked image (site_map_image.hpp), in static
// memory, with a grid index (site_grid.hpp) so that asking for the rocks near
// a segment costs in proportion to the cells the segment's band crosses and
// the rocks in them, not to the map.
//
// Memory (static, checked in test_site_map): kBytesPerRock a rock slot
// (vertices, bounding box, count) for kMaxSiteRocks slots, plus the index
// (4 bytes a cell start for kMaxGridCells + 1 cells, 2 bytes a reference for
// kMaxCellRefs) and the zones: kSiteMapBytes in all.
//
// load() checks the image whole before it touches the map: a refused image
// leaves the map in force as it was. It is bounded by the image (one pass to
// read, one to index). Queries are const; their scratch (the stamps that list
// a rock once however many cells it spans) is the caller's SiteQuery, so any
// number of readers share one map.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/site_map/site_grid.hpp"
#include "fsw/site_map/site_map_image.hpp"

namespace rse::site_map {

struct Rock {
    float x[kMaxRockVertices];   // counter-clockwise
    float y[kMaxRockVertices];
    float minX, minY, maxX, maxY;  // bounding box
    std::uint8_t count;
};

struct KeepOut {
    float x[kMaxKeepOutVertices];
    float y[kMaxKeepOutVertices];
    KeepOutKind kind;
    std::uint8_t count;
};

// A reader's scratch for queries: one per reader (2 bytes a rock slot: 40 KB).
struct SiteQuery {
    std::uint16_t stamp[kMaxSiteRocks] = {};
    std::uint16_t current = 0;
};

// What one query looked at: its cost in cells and references, and whether
// the caller's buffer was too small (then the rocks beyond it are not listed).
struct QueryStats {
    std::uint32_t cellsVisited = 0;
    std::uint32_t refsExamined = 0;
    std::uint32_t found = 0;      // rocks within reach, listed or not
    bool overflow = false;        // found > capacity
    bool refused = false;         // a point not finite or beyond kMaxQueryCoordinateM, or a reach not in [0, that]: nothing looked at
};

// The largest coordinate or reach a query takes (m): far beyond any site
// (kMaxSiteExtentM), small enough that the band walk's arithmetic stays finite.
constexpr double kMaxQueryCoordinateM = 1.0e6;

class SiteMap {
public:
    static constexpr std::size_t kBytesPerRock = sizeof(Rock);

    // Replaces the map with the image's when it passes checkSiteMapImage
    // (kOk; revision() grows); else kInvalidArgument, the map unchanged and
    // *check (when not null) saying why.
    core::Status load(const std::uint8_t* image, std::size_t length, SiteMapCheck* check);
    // No rocks, no zones, an empty site.
    void clear();

    bool loaded() const { return loaded_; }
    std::uint32_t revision() const { return revision_; }
    const SiteBounds& site() const { return site_; }
    const GridShape& grid() const { return grid_; }
    std::size_t rockCount() const { return rockCount_; }
    std::size_t keepOutCount() const { return keepOutCount_; }
    const Rock& rock(std::size_t i) const { return rocks_[i < kMaxSiteRocks ? i : 0]; }
    const KeepOut& keepOut(std::size_t i) const { return zones_[i < kMaxKeepOuts ? i : 0]; }

    // The rocks whose bounding box comes within reach (m) of the segment
    // a -> b, each once, into out[0 .. capacity): their count (at most
    // capacity). A superset of the rocks within reach (the box, not the
    // polygon); the caller measures the polygon. *stats (when not null) says
    // what it cost and whether out was too small. A query it cannot answer (a
    // point not finite or beyond kMaxQueryCoordinateM, a reach negative, not
    // finite or beyond it) lists nothing and says so (QueryStats::refused):
    // "nothing near" is never the answer to a question not asked properly.
    std::size_t rocksNearSegment(geometry::Point2 a, geometry::Point2 b, double reach, SiteQuery* scratch,
                                 std::uint16_t* out, std::size_t capacity, QueryStats* stats) const;

private:
    void index();
    void visitCell(std::size_t cell, geometry::Point2 a, geometry::Point2 b, double reach2, SiteQuery* scratch,
                   std::uint16_t* out, std::size_t capacity, QueryStats* stats) const;

    Rock rocks_[kMaxSiteRocks] = {};
    KeepOut zones_[kMaxKeepOuts] = {};
    // Cell c's rocks: cellRefs_[cellStart_[c] .. cellStart_[c + 1]).
    std::uint32_t cellStart_[kMaxGridCells + 1] = {};
    std::uint16_t cellRefs_[kMaxCellRefs] = {};
    SiteBounds site_{};
    GridShape grid_{};
    std::size_t rockCount_ = 0;
    std::size_t keepOutCount_ = 0;
    std::uint32_t revision_ = 0;
    bool loaded_ = false;
};

// The whole store's static size (the figure docs/site_map.md states).
constexpr std::size_t kSiteMapBytes = sizeof(SiteMap);

}  // namespace rse::site_map
