#include "fsw/site_map/site_map.hpp"

#include <cmath>

#include "fsw/core/byte_codec.hpp"

namespace rse::site_map {

using geometry::Point2;

namespace {

// Reads one polygon record (already checked) into x, y; its vertex count.
std::uint8_t readVertices(core::BeReader& in, float* x, float* y) {
    const std::uint8_t n = in.u8();
    for (std::size_t v = 0; v < n; ++v) {
        x[v] = in.f32();
        y[v] = in.f32();
    }
    return n;
}

// Reads one rock record (already checked) and its bounding box.
void readRock(core::BeReader& in, Rock* rock) {
    rock->count = readVertices(in, rock->x, rock->y);
    rock->minX = rock->maxX = rock->x[0];
    rock->minY = rock->maxY = rock->y[0];
    for (std::size_t v = 1; v < rock->count; ++v) {
        rock->minX = rock->x[v] < rock->minX ? rock->x[v] : rock->minX;
        rock->maxX = rock->x[v] > rock->maxX ? rock->x[v] : rock->maxX;
        rock->minY = rock->y[v] < rock->minY ? rock->y[v] : rock->minY;
        rock->maxY = rock->y[v] > rock->maxY ? rock->y[v] : rock->maxY;
    }
}

// Squared distance from the segment a -> b to the box (0 when they meet).
double segmentBoxDistanceSquared(Point2 a, Point2 b, const Rock& r) {
    const double x0 = r.minX, x1 = r.maxX, y0 = r.minY, y1 = r.maxY;
    const auto insideBox = [&](Point2 p) { return p.x >= x0 && p.x <= x1 && p.y >= y0 && p.y <= y1; };
    if (insideBox(a) || insideBox(b)) {
        return 0.0;
    }
    const Point2 c[4] = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
    double best = INFINITY;
    for (std::size_t k = 0; k < 4; ++k) {
        const double d = geometry::segmentSegmentDistanceSquared(a, b, c[k], c[(k + 1) % 4]);
        best = d < best ? d : best;
    }
    return best;
}

}  // namespace

void SiteMap::clear() {
    staging_ = StagePhase::kNone;
    SiteMapSlot& m = slots_[inForce_];
    m.rockCount = 0;
    m.keepOutCount = 0;
    m.site = SiteBounds{};
    m.grid = GridShape{};
    for (std::uint32_t& s : m.cellStart) {
        s = 0;
    }
    loaded_ = false;
    ++revision_;
}

core::Status SiteMap::load(const std::uint8_t* image, std::size_t length, SiteMapCheck* check) {
    const SiteMapCheck verdict = checkSiteMapImage(image, length);
    if (check != nullptr) {
        *check = verdict;
    }
    if (!verdict.ok()) {
        return core::Status::kInvalidArgument;
    }
    beginStaging(image, length);
    (void)stage(static_cast<std::size_t>(-1));  // every phase to its end in one step
    (void)putStagedInForce();
    return core::Status::kOk;
}

void SiteMap::beginStaging(const std::uint8_t* image, std::size_t length) {
    image_ = core::BeReader(image, length);
    SiteMapSlot& m = spare();
    (void)image_.u32();  // magic
    (void)image_.u16();  // version
    (void)image_.u16();  // flags
    m.site.xMin = image_.f32();
    m.site.yMin = image_.f32();
    m.site.xMax = image_.f32();
    m.site.yMax = image_.f32();
    m.rockCount = image_.u32();
    m.keepOutCount = image_.u16();
    (void)image_.u16();
    m.grid = gridFor(m.site);
    staging_ = StagePhase::kRocks;
    next_ = 0;
}

bool SiteMap::stage(std::size_t workUnits) {
    SiteMapSlot& m = spare();
    const std::size_t cells = static_cast<std::size_t>(m.grid.columns) * m.grid.rows;
    // A rock's cells, each given to f; the number of them (its work units).
    const auto forEachCell = [&m](const Rock& r, auto&& f) {
        std::size_t n = 0;
        for (std::uint32_t row = m.grid.row(r.minY); row <= m.grid.row(r.maxY); ++row) {
            for (std::uint32_t col = m.grid.column(r.minX); col <= m.grid.column(r.maxX); ++col) {
                f(m.grid.cell(col, row));
                ++n;
            }
        }
        return n;
    };
    std::size_t work = 0;
    // Each phase takes what is left of the step's work; a phase that ends
    // hands the rest to the next. The index is a counting sort of (cell,
    // rock): the cells cleared, the rocks counted into them, each cell's end
    // (a running sum), then the references written from the last rock back so
    // each cell's start is left behind.
    while (work < workUnits) {
        switch (staging_) {
            case StagePhase::kNone:
            case StagePhase::kWhole:
                return staging_ == StagePhase::kWhole;
            case StagePhase::kRocks:
                for (; next_ < m.rockCount && work < workUnits; ++next_, ++work) {
                    readRock(image_, &m.rocks[next_]);
                }
                if (next_ == m.rockCount) {
                    staging_ = StagePhase::kZones;
                }
                break;
            case StagePhase::kZones:
                for (std::size_t z = 0; z < m.keepOutCount; ++z) {  // at most kMaxKeepOuts: one unit
                    m.zones[z].kind = static_cast<KeepOutKind>(image_.u8());
                    m.zones[z].count = readVertices(image_, m.zones[z].x, m.zones[z].y);
                }
                ++work;
                staging_ = StagePhase::kClear;
                next_ = 0;
                break;
            case StagePhase::kClear:
                for (; next_ <= cells && work < workUnits; ++work) {
                    const std::size_t end = next_ + kCellsPerStageUnit < cells + 1 ? next_ + kCellsPerStageUnit : cells + 1;
                    for (; next_ < end; ++next_) {
                        m.cellStart[next_] = 0;
                    }
                }
                if (next_ > cells) {
                    staging_ = StagePhase::kCount;
                    next_ = 0;
                }
                break;
            case StagePhase::kCount:
                for (; next_ < m.rockCount && work < workUnits; ++next_) {
                    work += forEachCell(m.rocks[next_], [&m](std::size_t c) { ++m.cellStart[c]; });
                }
                if (next_ == m.rockCount) {
                    staging_ = StagePhase::kSum;
                    next_ = 0;
                    runningSum_ = 0;
                }
                break;
            case StagePhase::kSum:
                for (; next_ < cells && work < workUnits; ++work) {
                    const std::size_t end = next_ + kCellsPerStageUnit < cells ? next_ + kCellsPerStageUnit : cells;
                    for (; next_ < end; ++next_) {
                        runningSum_ += m.cellStart[next_];
                        m.cellStart[next_] = runningSum_;  // the image check bounds the sum by kMaxCellRefs
                    }
                }
                if (next_ == cells) {
                    m.cellStart[cells] = runningSum_;
                    staging_ = StagePhase::kFill;
                    next_ = m.rockCount;
                }
                break;
            case StagePhase::kFill:
                for (; next_ > 0 && work < workUnits; --next_) {
                    const std::size_t r = next_ - 1;
                    work += forEachCell(m.rocks[r], [&m, r](std::size_t c) {
                        m.cellRefs[--m.cellStart[c]] = static_cast<std::uint16_t>(r);
                    });
                }
                if (next_ == 0) {
                    staging_ = StagePhase::kWhole;
                }
                break;
        }
    }
    return staging_ == StagePhase::kWhole;
}

bool SiteMap::putStagedInForce() {
    if (staging_ != StagePhase::kWhole) {
        return false;
    }
    inForce_ = static_cast<std::uint8_t>(1U - inForce_);
    staging_ = StagePhase::kNone;
    loaded_ = true;
    ++revision_;
    return true;
}

void SiteMap::visitCell(std::size_t cell, Point2 a, Point2 b, double reach2, SiteQuery* scratch, std::uint16_t* out,
                        std::size_t capacity, QueryStats* stats) const {
    ++stats->cellsVisited;
    const SiteMapSlot& m = live();
    for (std::size_t k = m.cellStart[cell]; k < m.cellStart[cell + 1]; ++k) {
        const std::uint16_t r = m.cellRefs[k];
        ++stats->refsExamined;
        if (scratch->stamp[r] == scratch->current) {
            continue;
        }
        scratch->stamp[r] = scratch->current;
        if (segmentBoxDistanceSquared(a, b, m.rocks[r]) <= reach2) {
            if (stats->found < capacity) {
                out[stats->found] = r;
            }
            ++stats->found;
        }
    }
}

std::size_t SiteMap::rocksNearSegment(Point2 a, Point2 b, double reach, SiteQuery* scratch, std::uint16_t* out,
                                      std::size_t capacity, QueryStats* stats) const {
    QueryStats local;
    QueryStats* s = stats != nullptr ? stats : &local;
    *s = QueryStats{};
    const auto within = [](double v) { return std::fabs(v) <= kMaxQueryCoordinateM; };  // false for NaN
    if (!within(a.x) || !within(a.y) || !within(b.x) || !within(b.y) || !(reach >= 0.0) || !within(reach)) {
        s->refused = true;
        return 0;
    }
    const SiteMapSlot& m = live();
    if (m.rockCount == 0) {
        return 0;
    }
    // A fresh stamp; on wrap-around every stamp is cleared so none matches.
    if (++scratch->current == 0) {
        for (std::uint16_t& st : scratch->stamp) {
            st = 0;
        }
        scratch->current = 1;
    }
    const double reach2 = reach * reach;
    const double lowY = (a.y < b.y ? a.y : b.y) - reach;
    const double highY = (a.y > b.y ? a.y : b.y) + reach;
    // Row by row, the cells the segment's band (reach either side) can touch:
    // the segment clipped to the row's y band grown by reach, grown by reach in x.
    for (std::uint32_t row = m.grid.row(lowY); row <= m.grid.row(highY); ++row) {
        const double bandLow = m.grid.y0 + m.grid.cellM * row - reach;
        const double bandHigh = bandLow + m.grid.cellM + 2.0 * reach;
        double t0 = 0.0, t1 = 1.0;
        const double dy = b.y - a.y;
        if (dy != 0.0) {
            const double ta = (bandLow - a.y) / dy;
            const double tb = (bandHigh - a.y) / dy;
            t0 = std::fmax(0.0, std::fmin(ta, tb));
            t1 = std::fmin(1.0, std::fmax(ta, tb));
        } else if (a.y < bandLow || a.y > bandHigh) {
            continue;
        }
        // No part of the segment in the band (a segment off the grid, its
        // rows clamped to the edge row): no rock of the row is within reach.
        if (t0 > t1) {
            continue;
        }
        const double xa = a.x + (b.x - a.x) * t0;
        const double xb = a.x + (b.x - a.x) * t1;
        const std::uint32_t c0 = m.grid.column((xa < xb ? xa : xb) - reach);
        const std::uint32_t c1 = m.grid.column((xa > xb ? xa : xb) + reach);
        for (std::uint32_t col = c0; col <= c1; ++col) {
            visitCell(m.grid.cell(col, row), a, b, reach2, scratch, out, capacity, s);
        }
    }
    s->overflow = s->found > capacity;
    return s->found < capacity ? s->found : capacity;
}

}  // namespace rse::site_map
