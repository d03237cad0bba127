// The site map in force (docs/site_map.md): the rocks and keep-out zones of a
// whole site, loaded from a checked image (site_map_image.hpp), in static
// memory, with a grid index (site_grid.hpp) so that asking for the rocks near
// a segment costs in proportion to the cells the segment's band crosses and
// the rocks in them, not to the map.
//
// Memory (static, checked in test_site_map): kBytesPerRock a rock slot
// (vertices, bounding box, count) for kMaxSiteRocks slots, plus the index
// (4 bytes a cell start for kMaxGridCells + 1 cells, 2 bytes a reference for
// kMaxCellRefs) and the zones: kSiteMapSlotBytes a map, twice (in force and
// staged), kSiteMapBytes in all.
//
// Two slots: the map in force and the one being staged. An image (checked
// whole first) is decoded and indexed into the slot not in force, in steps of
// a bounded number of rocks (MAP_COMMIT runs a step a command-task run), and
// put in force in one step when whole: readers use the map in force, all of
// it, until then, and revision() tells them it changed. load() is the same
// in one call. Queries are const; their scratch (the stamps that list a rock
// once however many cells it spans) is the caller's SiteQuery, so any number
// of readers share one map.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/byte_codec.hpp"
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

// One whole map: its rocks, zones and index.
struct SiteMapSlot {
    Rock rocks[kMaxSiteRocks] = {};
    KeepOut zones[kMaxKeepOuts] = {};
    // Cell c's rocks: cellRefs[cellStart[c] .. cellStart[c + 1]).
    std::uint32_t cellStart[kMaxGridCells + 1] = {};
    std::uint16_t cellRefs[kMaxCellRefs] = {};
    SiteBounds site{};
    GridShape grid{};
    std::size_t rockCount = 0;
    std::size_t keepOutCount = 0;
};

// Work units of a staging step: a rock decoded is one, and one a cell when it
// is counted into the index or filed in it (a rock spanning many cells costs
// them all); the zones are one; kCellsPerStageUnit cells of the index cleared
// or summed are one. A step starts no rock once its units are spent, so it
// goes over them by one rock's cells at most (kMaxGridCells, a rock as wide
// as the site).
constexpr std::size_t kCellsPerStageUnit = 16;

class SiteMap {
public:
    static constexpr std::size_t kBytesPerRock = sizeof(Rock);

    // Replaces the map with the image's when it passes checkSiteMapImage
    // (kOk; revision() grows); else kInvalidArgument, the map unchanged and
    // *check (when not null) saying why. Drops a staging under way.
    core::Status load(const std::uint8_t* image, std::size_t length, SiteMapCheck* check);
    // No rocks, no zones, an empty site.
    void clear();

    // Staging, for an image that passed its check whole (checkSiteMapImage or
    // SiteMapImageCheck) and stays as it is until put in force or dropped:
    // beginStaging() starts, stage() does up to workUnits of work (true when
    // the staged map is whole), putStagedInForce() makes it the map in force
    // (revision() grows; false when it was not whole), dropStaged() forgets it.
    void beginStaging(const std::uint8_t* image, std::size_t length);
    bool stage(std::size_t workUnits);
    bool putStagedInForce();
    void dropStaged() { staging_ = StagePhase::kNone; }
    bool staging() const { return staging_ != StagePhase::kNone; }

    bool loaded() const { return loaded_; }
    std::uint32_t revision() const { return revision_; }
    const SiteBounds& site() const { return live().site; }
    const GridShape& grid() const { return live().grid; }
    std::size_t rockCount() const { return live().rockCount; }
    std::size_t keepOutCount() const { return live().keepOutCount; }
    const Rock& rock(std::size_t i) const { return live().rocks[i < kMaxSiteRocks ? i : 0]; }
    const KeepOut& keepOut(std::size_t i) const { return live().zones[i < kMaxKeepOuts ? i : 0]; }

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
    // Where a staging is: rocks decoded, then zones, then the index's cells
    // cleared, counted, summed and filled (rocks from the last: each cell's
    // start left behind).
    enum class StagePhase : std::uint8_t { kNone, kRocks, kZones, kClear, kCount, kSum, kFill, kWhole };

    const SiteMapSlot& live() const { return slots_[inForce_]; }
    SiteMapSlot& spare() { return slots_[1U - inForce_]; }
    void visitCell(std::size_t cell, geometry::Point2 a, geometry::Point2 b, double reach2, SiteQuery* scratch,
                   std::uint16_t* out, std::size_t capacity, QueryStats* stats) const;

    SiteMapSlot slots_[2];
    std::uint8_t inForce_ = 0;
    bool loaded_ = false;
    std::uint32_t revision_ = 0;
    // The staging under way (into spare()).
    core::BeReader image_{nullptr, 0};
    StagePhase staging_ = StagePhase::kNone;
    std::size_t next_ = 0;   // the phase's next rock (kFill: one past it) or cell
    std::uint32_t runningSum_ = 0;   // kSum: the references of the cells before next_
};

// One map's static size, and the whole store's (the figures docs/site_map.md states).
constexpr std::size_t kSiteMapSlotBytes = sizeof(SiteMapSlot);
constexpr std::size_t kSiteMapBytes = sizeof(SiteMap);

}  // namespace rse::site_map
