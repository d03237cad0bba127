// A scenario's generated rock field (scenario [field], issue 31 item 4): the
// rocks of Golombek and Rapp's model (rock_field.hpp) at the field's k and
// seed, appended to the scenario's obstacles with ids from kFirstFieldRockId
// on, known at or above the orbital resolution and hidden below it. Rocks
// are left out where they would not fit the world: a vertex off the map, or
// within clearM of the start or of the mission's goal (so the rover starts
// free and its goal is reachable). A scenario whose known rocks exceed the
// site map's kMaxSiteRocks is refused (the rover could not be told of them).
//
// Host side (sim_stub/): full language.
#pragma once

#include <cstddef>
#include <cstdint>

#include "sim_stub/scenario/rock_field.hpp"

namespace rse::sim {

struct Scenario;

constexpr std::uint16_t kFirstFieldRockId = 256;   // after the file's own obstacles (1..255)

struct FieldSpec {
    bool present = false;
    RockFieldParams rocks;     // k, seed, diameters, orbital resolution; the site is the map's
    double clearM = 5.0;       // no rock within this of the start or the mission's goal
};

// Appends the field's rocks to scenario->obstacles. Throws ScenarioError
// (scenario_parser.hpp) naming what does not fit.
void addFieldRocks(const FieldSpec& field, Scenario* scenario);

// Rocks the field added (ids from kFirstFieldRockId), known ones among them.
struct FieldCounts {
    std::size_t rocks = 0;
    std::size_t known = 0;
};
FieldCounts fieldCounts(const Scenario& scenario);

}  // namespace rse::sim
