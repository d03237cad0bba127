#include "ground/site_map_encoder.hpp"

#include "fsw/core/byte_codec.hpp"

namespace rse::ground {

namespace {

void putPolygon(core::BeWriter& out, const std::vector<MapVertex>& vertices) {
    out.u8(static_cast<std::uint8_t>(vertices.size()));
    for (const MapVertex& v : vertices) {
        out.f32(v.x);
        out.f32(v.y);
    }
}

}  // namespace

std::vector<std::uint8_t> encodeSiteMap(const SiteMapSpec& spec) {
    std::size_t size = site_map::kSiteMapHeaderSize;
    for (const auto& r : spec.rocks) {
        size += 1 + 8 * r.size();
    }
    for (const auto& z : spec.keepOuts) {
        size += 2 + 8 * z.vertices.size();
    }
    std::vector<std::uint8_t> image(size);
    core::BeWriter out(image.data(), image.size());
    out.u32(site_map::kSiteMapMagic);
    out.u16(site_map::kSiteMapVersion);
    out.u16(0);
    out.f32(spec.site.xMin);
    out.f32(spec.site.yMin);
    out.f32(spec.site.xMax);
    out.f32(spec.site.yMax);
    out.u32(static_cast<std::uint32_t>(spec.rocks.size()));
    out.u16(static_cast<std::uint16_t>(spec.keepOuts.size()));
    out.u16(0);
    for (const auto& r : spec.rocks) {
        putPolygon(out, r);
    }
    for (const auto& z : spec.keepOuts) {
        out.u8(static_cast<std::uint8_t>(z.kind));
        putPolygon(out, z.vertices);
    }
    image.resize(out.size());
    return image;
}

}  // namespace rse::ground
