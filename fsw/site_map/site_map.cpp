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
    rockCount_ = 0;
    keepOutCount_ = 0;
    site_ = SiteBounds{};
    grid_ = GridShape{};
    for (std::uint32_t& s : cellStart_) {
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
    core::BeReader in(image, length);
    (void)in.u32();  // magic
    (void)in.u16();  // version
    (void)in.u16();  // flags
    site_.xMin = in.f32();
    site_.yMin = in.f32();
    site_.xMax = in.f32();
    site_.yMax = in.f32();
    rockCount_ = in.u32();
    keepOutCount_ = in.u16();
    (void)in.u16();
    for (std::size_t r = 0; r < rockCount_; ++r) {
        Rock& rock = rocks_[r];
        rock.count = readVertices(in, rock.x, rock.y);
        rock.minX = rock.maxX = rock.x[0];
        rock.minY = rock.maxY = rock.y[0];
        for (std::size_t v = 1; v < rock.count; ++v) {
            rock.minX = rock.x[v] < rock.minX ? rock.x[v] : rock.minX;
            rock.maxX = rock.x[v] > rock.maxX ? rock.x[v] : rock.maxX;
            rock.minY = rock.y[v] < rock.minY ? rock.y[v] : rock.minY;
            rock.maxY = rock.y[v] > rock.maxY ? rock.y[v] : rock.maxY;
        }
    }
    for (std::size_t z = 0; z < keepOutCount_; ++z) {
        zones_[z].kind = static_cast<KeepOutKind>(in.u8());
        zones_[z].count = readVertices(in, zones_[z].x, zones_[z].y);
    }
    grid_ = gridFor(site_);
    index();
    loaded_ = true;
    ++revision_;
    return core::Status::kOk;
}

void SiteMap::index() {
    // Counting sort of (cell, rock): counts, then each cell's end, then the
    // references written backwards so each cell's start is left behind.
    const std::size_t cells = static_cast<std::size_t>(grid_.columns) * grid_.rows;
    for (std::size_t c = 0; c <= cells; ++c) {
        cellStart_[c] = 0;
    }
    const auto forEachCell = [this](const Rock& r, auto&& f) {
        for (std::uint32_t row = grid_.row(r.minY); row <= grid_.row(r.maxY); ++row) {
            for (std::uint32_t col = grid_.column(r.minX); col <= grid_.column(r.maxX); ++col) {
                f(grid_.cell(col, row));
            }
        }
    };
    for (std::size_t r = 0; r < rockCount_; ++r) {
        forEachCell(rocks_[r], [this](std::size_t c) { ++cellStart_[c]; });
    }
    std::uint32_t end = 0;
    for (std::size_t c = 0; c < cells; ++c) {
        end += cellStart_[c];
        cellStart_[c] = end;  // the image check bounds end by kMaxCellRefs
    }
    cellStart_[cells] = end;
    for (std::size_t r = rockCount_; r-- > 0;) {
        forEachCell(rocks_[r], [this, r](std::size_t c) { cellRefs_[--cellStart_[c]] = static_cast<std::uint16_t>(r); });
    }
}

void SiteMap::visitCell(std::size_t cell, Point2 a, Point2 b, double reach2, SiteQuery* scratch, std::uint16_t* out,
                        std::size_t capacity, QueryStats* stats) const {
    ++stats->cellsVisited;
    for (std::size_t k = cellStart_[cell]; k < cellStart_[cell + 1]; ++k) {
        const std::uint16_t r = cellRefs_[k];
        ++stats->refsExamined;
        if (scratch->stamp[r] == scratch->current) {
            continue;
        }
        scratch->stamp[r] = scratch->current;
        if (segmentBoxDistanceSquared(a, b, rocks_[r]) <= reach2) {
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
    if (rockCount_ == 0) {
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
    for (std::uint32_t row = grid_.row(lowY); row <= grid_.row(highY); ++row) {
        const double bandLow = grid_.y0 + grid_.cellM * row - reach;
        const double bandHigh = bandLow + grid_.cellM + 2.0 * reach;
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
        const std::uint32_t c0 = grid_.column((xa < xb ? xa : xb) - reach);
        const std::uint32_t c1 = grid_.column((xa > xb ? xa : xb) + reach);
        for (std::uint32_t col = c0; col <= c1; ++col) {
            visitCell(grid_.cell(col, row), a, b, reach2, scratch, out, capacity, s);
        }
    }
    s->overflow = s->found > capacity;
    return s->found < capacity ? s->found : capacity;
}

}  // namespace rse::site_map
