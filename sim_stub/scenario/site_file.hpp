// A site file (issue 31 item 4, "a scenario may reference a map file"): the
// rocks of a site in a text file of their own, so that a scenario of
// thousands of rocks stays readable. `rse-sim --site-file SCENARIO` writes
// one from any scenario (a [field] drawn from the rock size-frequency model
// at its k and seed is the generator); a scenario names one with
// `[site] file = "..."` (sim_stub/scenarios/README.md, "Site files").
//
//   rse-site 1
//   map X_MIN Y_MIN X_MAX Y_MAX
//   rock known|hidden seen|unseen X0 Y0 X1 Y1 ...   (one a line)
//
// Coordinates in metres (map frame), 3 to 16 vertices, convex and
// counter-clockwise; `#` starts a comment, blank lines are skipped; the
// writer prints each number so that it reads back the same double. The map
// line must be the scenario's [map]: a site file is for one site.
//
// Host side (sim_stub/): full language.
#pragma once

#include <cstddef>
#include <string>

namespace rse::sim {

struct Scenario;

// Lines a site file may have: far beyond any site the flight software holds
// (kMaxSiteRocks known rocks) with its hidden rocks.
constexpr std::size_t kMaxSiteFileRocks = 65535 - 256 + 1;

// The site file of the scenario's map and every obstacle in it.
std::string siteFileText(const Scenario& scenario);

// Reads the site file at path and appends its rocks to scenario->obstacles
// (ids from kFirstFieldRockId, in file order). Checks every line as the
// scenario's [[obstacles]] are checked (inside the map, convex,
// counter-clockwise), the map line against scenario->map, and the rover's
// footprint at the start and the mission's goal clear of every rock. Throws
// ScenarioError ("PATH:LINE: why") at the first fault.
void addSiteFileRocks(const std::string& path, Scenario* scenario);

}  // namespace rse::sim
