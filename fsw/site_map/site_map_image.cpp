#include "fsw/site_map/site_map_image.hpp"

#include <cmath>

#include "fsw/core/byte_codec.hpp"
#include "fsw/site_map/site_grid.hpp"

namespace rse::site_map {

const char* toString(SiteMapReject reason) {
    switch (reason) {
        case SiteMapReject::kOk: return "ok";
        case SiteMapReject::kTooShort: return "image ends inside a record";
        case SiteMapReject::kBadMagic: return "not a site map image";
        case SiteMapReject::kBadVersion: return "unknown image version";
        case SiteMapReject::kBadSite: return "site bounds empty, not finite or too large";
        case SiteMapReject::kTooManyRocks: return "too many rocks";
        case SiteMapReject::kTooManyKeepOuts: return "too many keep-out zones";
        case SiteMapReject::kBadVertexCount: return "bad vertex count";
        case SiteMapReject::kNotFinite: return "vertex not finite";
        case SiteMapReject::kOutsideSite: return "vertex outside the site";
        case SiteMapReject::kClockwise: return "polygon clockwise";
        case SiteMapReject::kNotConvex: return "polygon not convex";
        case SiteMapReject::kBadKind: return "unknown keep-out kind";
        case SiteMapReject::kTrailingBytes: return "bytes after the last record";
        case SiteMapReject::kIndexFull: return "rocks span more cells than the index holds";
        case SiteMapReject::kBadHeader: return "header flags or reserved not 0";
    }
    return "?";
}

bool convexCounterClockwise(const float* x, const float* y, std::size_t count, bool* clockwise) {
    *clockwise = false;
    if (count < 3) {
        return false;
    }
    const auto px = [x](std::size_t i) { return static_cast<double>(x[i]); };
    const auto py = [y](std::size_t i) { return static_cast<double>(y[i]); };
    double twiceArea = 0.0;
    for (std::size_t v = 0; v < count; ++v) {
        const std::size_t w = (v + 1) % count;
        twiceArea += px(v) * py(w) - px(w) * py(v);
    }
    if (!(twiceArea > 0.0)) {
        *clockwise = true;
        return false;
    }
    for (std::size_t v = 0; v < count; ++v) {
        const std::size_t b = (v + 1) % count;
        // Every other vertex strictly left of edge v -> b: convex, every turn
        // strictly left, and no second winding (a pentagram fails here).
        for (std::size_t u = 0; u < count; ++u) {
            if (u == v || u == b) {
                continue;
            }
            const double c = (px(b) - px(v)) * (py(u) - py(v)) - (py(b) - py(v)) * (px(u) - px(v));
            if (!(c > 0.0)) {
                return false;
            }
        }
    }
    return true;
}

namespace {

// One polygon record's vertices read and checked; the cells its bounding box
// touches added to *cellRefs (rocks only).
SiteMapReject readPolygon(core::BeReader& in, std::size_t maxVertices, const SiteBounds& site,
                          const GridShape* grid, std::size_t* cellRefs) {
    const std::size_t n = in.u8();
    if (!in.ok()) {
        return SiteMapReject::kTooShort;
    }
    if (n < 3 || n > maxVertices) {
        return SiteMapReject::kBadVertexCount;
    }
    float x[kMaxKeepOutVertices] = {};
    float y[kMaxKeepOutVertices] = {};
    for (std::size_t v = 0; v < n; ++v) {
        x[v] = in.f32();
        y[v] = in.f32();
    }
    if (!in.ok()) {
        return SiteMapReject::kTooShort;
    }
    float minX = x[0], maxX = x[0], minY = y[0], maxY = y[0];
    for (std::size_t v = 0; v < n; ++v) {
        if (!std::isfinite(x[v]) || !std::isfinite(y[v])) {
            return SiteMapReject::kNotFinite;
        }
        if (x[v] < site.xMin || x[v] > site.xMax || y[v] < site.yMin || y[v] > site.yMax) {
            return SiteMapReject::kOutsideSite;
        }
        minX = x[v] < minX ? x[v] : minX;
        maxX = x[v] > maxX ? x[v] : maxX;
        minY = y[v] < minY ? y[v] : minY;
        maxY = y[v] > maxY ? y[v] : maxY;
    }
    bool clockwise = false;
    if (!convexCounterClockwise(x, y, n, &clockwise)) {
        return clockwise ? SiteMapReject::kClockwise : SiteMapReject::kNotConvex;
    }
    if (grid != nullptr) {
        const std::size_t columns = grid->column(maxX) - grid->column(minX) + 1;
        const std::size_t rows = grid->row(maxY) - grid->row(minY) + 1;
        *cellRefs += columns * rows;
    }
    return SiteMapReject::kOk;
}

bool siteOk(const SiteBounds& s) {
    const bool finite = std::isfinite(s.xMin) && std::isfinite(s.yMin) && std::isfinite(s.xMax) && std::isfinite(s.yMax);
    return finite && s.xMax > s.xMin && s.yMax > s.yMin &&
           static_cast<double>(s.xMax) - static_cast<double>(s.xMin) <= kMaxSiteExtentM &&
           static_cast<double>(s.yMax) - static_cast<double>(s.yMin) <= kMaxSiteExtentM;
}

}  // namespace

SiteMapCheck checkSiteMapImage(const std::uint8_t* image, std::size_t length) {
    SiteMapImageCheck check;
    check.begin(image, length);
    (void)check.step(kMaxSiteRocks + kMaxKeepOuts);  // every record a header that passed can name: one step
    return check.result();
}

bool SiteMapImageCheck::fail(SiteMapReject reason) {
    check_.reason = reason;
    ended_ = true;
    return true;
}

void SiteMapImageCheck::begin(const std::uint8_t* image, std::size_t length) {
    in_ = core::BeReader(image, image != nullptr ? length : 0);
    check_ = SiteMapCheck{};
    next_ = 0;
    cellRefs_ = 0;
    ended_ = false;
    const std::uint32_t magic = in_.u32();
    const std::uint16_t version = in_.u16();
    const std::uint16_t flags = in_.u16();
    site_.xMin = in_.f32();
    site_.yMin = in_.f32();
    site_.xMax = in_.f32();
    site_.yMax = in_.f32();
    check_.rocks = in_.u32();
    check_.keepOuts = in_.u16();
    const std::uint16_t reserved = in_.u16();
    if (!in_.ok()) {
        (void)fail(SiteMapReject::kTooShort);
    } else if (magic != kSiteMapMagic) {
        (void)fail(SiteMapReject::kBadMagic);
    } else if (version != kSiteMapVersion) {
        (void)fail(SiteMapReject::kBadVersion);
    } else if (flags != 0 || reserved != 0) {
        (void)fail(SiteMapReject::kBadHeader);
    } else if (!siteOk(site_)) {
        (void)fail(SiteMapReject::kBadSite);
    } else if (check_.rocks > kMaxSiteRocks) {
        (void)fail(SiteMapReject::kTooManyRocks);
    } else if (check_.keepOuts > kMaxKeepOuts) {
        (void)fail(SiteMapReject::kTooManyKeepOuts);
    }
}

bool SiteMapImageCheck::step(std::size_t maxRecords) {
    if (ended_) {
        return true;
    }
    const GridShape grid = gridFor(site_);
    const std::size_t records = static_cast<std::size_t>(check_.rocks) + check_.keepOuts;
    const std::size_t quota = maxRecords > 0 ? maxRecords : 1;
    for (std::size_t n = 0; n < quota && next_ < records; ++n, ++next_) {
        if (next_ < check_.rocks) {
            check_.item = static_cast<std::uint32_t>(next_);
            const SiteMapReject why = readPolygon(in_, kMaxRockVertices, site_, &grid, &cellRefs_);
            if (why != SiteMapReject::kOk) {
                return fail(why);
            }
            continue;
        }
        check_.keepOut = true;
        check_.item = static_cast<std::uint32_t>(next_ - check_.rocks);
        const std::uint8_t kind = in_.u8();
        if (in_.ok() && kind != static_cast<std::uint8_t>(KeepOutKind::kSteep) &&
            kind != static_cast<std::uint8_t>(KeepOutKind::kSoft)) {
            return fail(SiteMapReject::kBadKind);
        }
        const SiteMapReject why = readPolygon(in_, kMaxKeepOutVertices, site_, nullptr, nullptr);
        if (why != SiteMapReject::kOk) {
            return fail(why);
        }
    }
    if (next_ < records) {
        return false;
    }
    check_.keepOut = false;
    check_.item = 0;
    if (in_.remaining() != 0) {
        return fail(SiteMapReject::kTrailingBytes);
    }
    if (cellRefs_ > kMaxCellRefs) {
        return fail(SiteMapReject::kIndexFull);
    }
    ended_ = true;
    return true;
}

}  // namespace rse::site_map
