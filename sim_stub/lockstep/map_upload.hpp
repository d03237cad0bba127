// The scenario's orbital map into the flight software the way an operator
// puts it there: the COARSE_MAP source made from the scenario
// (coarse_map_source.hpp), compiled with the ground's table compiler, sent as
// authenticated TABLE_LOAD chunks, TABLE_VALIDATE and TABLE_ACTIVATE through
// the in-memory ground link, and confirmed from the TABLE_STATUS telemetry
// (the active image's CRC equal to the one sent). The rover then plans on the
// scenario's site and rocks, not the compiled-in demo map. Table commands are
// taken in SAFE, STANDBY and MANUAL: call it before SET_MODE AUTONOMOUS.
//
// Host side (sim_stub/): full language.
#pragma once

#include <cstdint>
#include <functional>
#include <string>

#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"
#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

constexpr core::TimeNs kMapUploadLimitNs = 5 * core::kNsPerSec;

struct MapUploadResult {
    bool ok = false;
    std::string error;        // why not, when !ok
    std::size_t chunks = 0;   // TABLE_LOAD commands sent
    std::size_t bytes = 0;    // image size
    std::uint32_t crc = 0;    // the image's CRC-32 (TABLE_STATUS active_crc once active)
    std::size_t obstacles = 0;  // known obstacles on the map
};

// `service` is called every frame while waiting (drain the downlink, the
// caller's watches). Sends nothing and fails if the scenario's known rocks do
// not fit the table.
MapUploadResult uploadCoarseMap(const Scenario& scenario, MemoryGround& ground, LockstepRig& rig,
                                const std::function<void()>& service);

// The scenario's site map (siteMapSpec: the map's bounds and every known
// rock) the way `rse-ground map load` sends it: MAP_LOAD chunks, each waiting
// for its SITE_MAP answer, then MAP_COMMIT, whose slices' end is confirmed
// from SITE_MAP (commit_phase 0, the map in force with the image's CRC and
// rock count). In SAFE or STANDBY (before
// SET_MODE AUTONOMOUS). The result's obstacles are the known rocks.
MapUploadResult uploadSiteMap(const Scenario& scenario, MemoryGround& ground, LockstepRig& rig,
                              const std::function<void()>& service);

}  // namespace rse::sim
