#include "ground/mission_control/site_map.hpp"

#include <exception>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/table_compiler.hpp"

namespace rse::ground::mission_control {

Json siteMapJson(const tables::CoarseMapTable& map) {
    Json rocks = Json::array();
    const std::size_t slots = geometry::coarseMapSlotsUsed(map);
    for (std::size_t slot = 0; slot < slots; ++slot) {
        Json points = Json::array();
        const std::size_t vertices = geometry::coarseMapVerticesUsed(map, slot);
        for (std::size_t v = 0; v < vertices; ++v) {
            const geometry::Point2 p = geometry::coarseMapVertex(map, slot, v);
            // The table's floats as written in its source (1.8, not 1.7999999523162842).
            points.push_back(Json::array({shortestFloat(static_cast<float>(p.x)), shortestFloat(static_cast<float>(p.y))}));
        }
        rocks.push_back({{"id", slot}, {"points", std::move(points)}});
    }
    return {{"site",
             {{"x_min", shortestFloat(map.x_min_m)},
              {"x_max", shortestFloat(map.x_max_m)},
              {"y_min", shortestFloat(map.y_min_m)},
              {"y_max", shortestFloat(map.y_max_m)}}},
            {"rocks", std::move(rocks)}};
}

SiteMap loadSiteMap(const std::string& tablesDir) {
    SiteMap result;
    result.file = tablesDir + "/coarse_map.toml";
    try {
        const std::vector<std::uint8_t> bytes = readTableFile(result.file);
        tables::CoarseMapTable map{};
        if (!tables::decodeTable(bytes.data(), bytes.size(), &map).ok()) {
            result.error = result.file + " is not a good COARSE_MAP image: " + describeCheck(bytes.data(), bytes.size());
            return result;
        }
        result.json = siteMapJson(map);
    } catch (const std::exception& e) {
        result.error = e.what();
    }
    return result;
}

}  // namespace rse::ground::mission_control
