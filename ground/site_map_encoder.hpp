// The ground's side of the site map image (fsw/site_map/site_map_image.hpp):
// a site, its rocks and keep-out zones as the ground holds them, encoded as
// the image rse-fsw checks and loads. Host only; the flight check is the
// judge of what it writes (encodeSiteMap writes what it is given, so that a
// test can build a bad image on purpose).
#pragma once

#include <cstdint>
#include <vector>

#include "fsw/site_map/site_map_image.hpp"

namespace rse::ground {

struct MapVertex {
    float x = 0.0F;
    float y = 0.0F;
};

struct SiteMapSpec {
    site_map::SiteBounds site;
    std::vector<std::vector<MapVertex>> rocks;  // counter-clockwise convex polygons
    struct Zone {
        site_map::KeepOutKind kind = site_map::KeepOutKind::kSteep;
        std::vector<MapVertex> vertices;
    };
    std::vector<Zone> keepOuts;
};

std::vector<std::uint8_t> encodeSiteMap(const SiteMapSpec& spec);

}  // namespace rse::ground
