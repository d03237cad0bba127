// `rse-ground map check`, `map load` and `map abort`: the site map image
// (fsw/site_map/site_map_image.hpp, docs/site_map.md) checked on the ground
// with the flight check, and sent over the link with the site map commands
// (APID 0x186).
//
// load: MAP_LOAD chunks of the image (offset 0 first, 200 B each, the command's
// data blob), each waiting for its acknowledgement before the next goes (the
// pacing: one chunk a command-task frame), then MAP_COMMIT with the image's
// length and CRC-32. The rover answers every command with SITE_MAP; a refused
// chunk stops the load. An accepted commit runs in slices on board, so its
// verdict is the SITE_MAP sent when it ends (commit_phase 0, maps_loaded or
// commits_refused grown): a refused commit, at once or in its slices, is
// reported with its reason and the rock or zone it is about
// (SITE_MAP.last_refusal_item).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include "ground/ground_session.hpp"

namespace rse::ground {

// The MAP_LOAD argument bytes of each chunk of image, in order.
std::vector<std::vector<std::uint8_t>> mapLoadChunks(const std::vector<std::uint8_t>& image);
// The MAP_COMMIT argument bytes: u32 length, u32 CRC-32 of the image.
std::vector<std::uint8_t> mapCommitArgs(const std::vector<std::uint8_t>& image);

// The flight check on the ground: 0 and a summary on out when the image
// passes, 2 and the reason (and rock or zone) on err when it does not.
int checkSiteMapFile(const std::vector<std::uint8_t>& image, const std::string& where, std::ostream& out,
                     std::ostream& err);

// Sends the image and commits it: 0 in force, 1 no acknowledgement or no
// end of the commit told within 10 s, 3 refused.
int loadSiteMap(GroundSession& session, const std::vector<std::uint8_t>& image, std::ostream& out, std::ostream& err);

}  // namespace rse::ground
