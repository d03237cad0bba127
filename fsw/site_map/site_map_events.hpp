// Event ids raised by the site map service (range 590-599, the end of the
// table service's 560-599). Texts start with "site_map: ". Documented in
// docs/site_map.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::site_map::events {

constexpr core::EventId kMapLoaded = 590;       // INFO: a committed image replaced the map in force (rocks, zones, bytes, CRC, revision)
constexpr core::EventId kChunkRefused = 591;    // WARN: MAP_LOAD refused (gap, overflow, spoiled, nothing open): offset, length, image so far
constexpr core::EventId kCommitRefused = 592;   // WARN: MAP_COMMIT refused (length, CRC, spoiled, nothing uploaded, or the image's reason and rock): the map in force kept
constexpr core::EventId kUploadAborted = 593;   // INFO: MAP_ABORT dropped the upload (bytes dropped)
constexpr core::EventId kAbortRefused = 594;    // WARN: MAP_ABORT with no upload open

}  // namespace rse::site_map::events
