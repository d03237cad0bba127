// A scenario's orbital map as the rover flies it: the COARSE_MAP table source
// (tables/coarse_map.toml's form, docs/tables.md) for the scenario's site
// bounds and its known obstacles, in the scenario's order. Hidden obstacles
// are not on it: only the hazard detector can find them. The mission runner
// compiles it and uploads it over the ground link before the GOTO, as an
// operator would (sim_stub/lockstep/map_upload.hpp); `rse-sim
// --coarse-map-source SCENARIO` prints it for `rse-ground table build` and
// `table load`.
//
// Host side (sim_stub/): full language.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

#include "ground/site_map_encoder.hpp"
#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

// A scenario whose known obstacles do not fit the table (more than 16, or one
// with more than 8 vertices): the rover could not be told of them.
class CoarseMapError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

constexpr std::size_t kCoarseMapSlots = 16;         // COARSE_MAP obstacle slots
constexpr std::size_t kCoarseMapSlotVertices = 8;   // vertices a slot

// The TOML source of the COARSE_MAP table for the scenario (version 1).
// Throws CoarseMapError naming the scenario and what does not fit. A
// scenario that uses the site map (Scenario::usesSiteMap) gets the bounds
// alone: its known rocks go with the site map (siteMapSpec).
std::string coarseMapSource(const Scenario& scenario);

// The site map of the scenario (ground/site_map_encoder.hpp): the map's
// bounds and every known rock (what the rover is sent), or every rock,
// hidden ones too (what an offline planner or a sampler that knew every rock
// would use), in the scenario's order.
enum class MapRocks : std::uint8_t { kKnown, kEvery };
ground::SiteMapSpec siteMapSpec(const Scenario& scenario, MapRocks which = MapRocks::kKnown);

}  // namespace rse::sim
