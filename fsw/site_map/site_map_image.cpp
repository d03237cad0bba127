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
    SiteMapCheck check;
    core::BeReader in(image, image != nullptr ? length : 0);
    const std::uint32_t magic = in.u32();
    const std::uint16_t version = in.u16();
    const std::uint16_t flags = in.u16();
    SiteBounds site;
    site.xMin = in.f32();
    site.yMin = in.f32();
    site.xMax = in.f32();
    site.yMax = in.f32();
    check.rocks = in.u32();
    check.keepOuts = in.u16();
    const std::uint16_t reserved = in.u16();
    const auto fail = [&check](SiteMapReject reason) {
        check.reason = reason;
        return check;
    };
    if (!in.ok()) {
        return fail(SiteMapReject::kTooShort);
    }
    if (magic != kSiteMapMagic) {
        return fail(SiteMapReject::kBadMagic);
    }
    if (version != kSiteMapVersion) {
        return fail(SiteMapReject::kBadVersion);
    }
    if (flags != 0 || reserved != 0) {
        return fail(SiteMapReject::kBadHeader);
    }
    if (!siteOk(site)) {
        return fail(SiteMapReject::kBadSite);
    }
    if (check.rocks > kMaxSiteRocks) {
        return fail(SiteMapReject::kTooManyRocks);
    }
    if (check.keepOuts > kMaxKeepOuts) {
        return fail(SiteMapReject::kTooManyKeepOuts);
    }
    const GridShape grid = gridFor(site);
    std::size_t cellRefs = 0;
    for (std::uint32_t r = 0; r < check.rocks; ++r) {
        check.item = r;
        const SiteMapReject why = readPolygon(in, kMaxRockVertices, site, &grid, &cellRefs);
        if (why != SiteMapReject::kOk) {
            return fail(why);
        }
    }
    check.keepOut = true;
    for (std::uint16_t z = 0; z < check.keepOuts; ++z) {
        check.item = z;
        const std::uint8_t kind = in.u8();
        if (in.ok() && kind != static_cast<std::uint8_t>(KeepOutKind::kSteep) &&
            kind != static_cast<std::uint8_t>(KeepOutKind::kSoft)) {
            return fail(SiteMapReject::kBadKind);
        }
        const SiteMapReject why = readPolygon(in, kMaxKeepOutVertices, site, nullptr, nullptr);
        if (why != SiteMapReject::kOk) {
            return fail(why);
        }
    }
    check.keepOut = false;
    check.item = 0;
    if (in.remaining() != 0) {
        return fail(SiteMapReject::kTrailingBytes);
    }
    if (cellRefs > kMaxCellRefs) {
        return fail(SiteMapReject::kIndexFull);
    }
    return check;
}

}  // namespace rse::site_map
