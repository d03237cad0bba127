// The site map the display draws (GET /api/map, docs/mission_control.md): the
// site bounds and the known rocks of the COARSE_MAP table (table 9) in force
// on the ground, compiled from its source in the tables folder
// (DIR/coarse_map.toml) by the table compiler and checked with the flight's
// own table checks, as `rse-ground report` reads it:
//
//   {"site": {"x_min": -5, "x_max": 30, "y_min": -10, "y_max": 10},
//    "rocks": [{"id": 0, "points": [[5, 1.8], [6.5, 1.8], ...]}, ...]}
//
// A rock's id is its slot in the table (0 first); its points are the
// polygon's vertices in the table's order, metres in the site frame.
#pragma once

#include <optional>
#include <string>

#include "fsw/tables/table_types.hpp"
#include "ground/mission_control/telemetry_datum.hpp"

namespace rse::ground::mission_control {

struct SiteMap {
    std::optional<Json> json;  // the map, when it could be read
    std::string error;         // why not, naming the file (json empty)
    std::string file;          // the source it was read from
};

// The map from tablesDir/coarse_map.toml.
SiteMap loadSiteMap(const std::string& tablesDir);

// The map's JSON.
Json siteMapJson(const tables::CoarseMapTable& map);

}  // namespace rse::ground::mission_control
