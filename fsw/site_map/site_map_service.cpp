#include "fsw/site_map/site_map_service.hpp"

#include "fsw/site_map/site_map_events.hpp"

namespace rse::site_map {

UploadRefusal SiteMapService::refuse(UploadRefusal why, std::uint32_t item) {
    lastRefusal_ = why;
    lastRefusalItem_ = item;
    return why;
}

UploadRefusal SiteMapService::loadChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length) {
    const UploadRefusal why = upload_.takeChunk(offset, data, length);
    if (why == UploadRefusal::kNone) {
        ++counters_.chunksTaken;
        return why;
    }
    ++counters_.chunksRefused;
    events_.report(events::kChunkRefused, core::Severity::kWarning,
                   "site_map: MAP_LOAD at %u (%u bytes) refused: %s (image so far %u bytes)",
                   static_cast<unsigned>(offset), static_cast<unsigned>(length), toString(why),
                   static_cast<unsigned>(upload_.length()));
    return refuse(why, 0);
}

UploadRefusal SiteMapService::commit(std::uint32_t length, std::uint32_t crc) {
    UploadRefusal why = upload_.checkCommit(length, crc);
    SiteMapCheck check;
    if (why == UploadRefusal::kNone && !core::isOk(map_.load(upload_.image(), upload_.length(), &check))) {
        why = static_cast<UploadRefusal>(refusalCode(check.reason));
    }
    if (why != UploadRefusal::kNone) {
        ++counters_.commitsRefused;
        if (static_cast<std::uint8_t>(why) >= static_cast<std::uint8_t>(UploadRefusal::kImage)) {
            events_.report(events::kCommitRefused, core::Severity::kWarning,
                           "site_map: MAP_COMMIT refused: %s (%s %u): the map in force is kept", toString(why),
                           check.keepOut ? "zone" : "rock", static_cast<unsigned>(check.item));
        } else {
            events_.report(events::kCommitRefused, core::Severity::kWarning,
                           "site_map: MAP_COMMIT refused: %s: the map in force is kept", toString(why));
        }
        return refuse(why, check.item);
    }
    ++counters_.mapsLoaded;
    mapCrc_ = crc;
    mapBytes_ = length;
    events_.report(events::kMapLoaded, core::Severity::kInfo,
                   "site_map: map %u in force: %u rocks, %u zones, %u bytes, CRC %08x",
                   static_cast<unsigned>(map_.revision()), static_cast<unsigned>(map_.rockCount()),
                   static_cast<unsigned>(map_.keepOutCount()), static_cast<unsigned>(length),
                   static_cast<unsigned>(crc));
    lastRefusal_ = UploadRefusal::kNone;
    lastRefusalItem_ = 0;
    return UploadRefusal::kNone;
}

UploadRefusal SiteMapService::abort() {
    const std::size_t dropped = upload_.length();
    if (!upload_.abort()) {
        ++counters_.abortsRefused;
        events_.report(events::kAbortRefused, core::Severity::kWarning, "site_map: MAP_ABORT refused: no upload open");
        return refuse(UploadRefusal::kNothingUploaded, 0);
    }
    ++counters_.uploadsAborted;
    events_.report(events::kUploadAborted, core::Severity::kInfo, "site_map: upload aborted (%u bytes dropped)",
                   static_cast<unsigned>(dropped));
    return UploadRefusal::kNone;
}

}  // namespace rse::site_map
