// The site map service (docs/site_map.md): the map in force (SiteMap) and its
// upload (SiteMapUpload), as the commands of APID 0x186 drive them
// (site_map_commands.hpp). It owns what it decides: a chunk or a commit
// refused is counted and evented here (events 590-594), and the last refusal
// is kept for SITE_MAP. A committed image replaces the map only when it passes
// checkSiteMapImage whole; else the map in force is kept.
//
// Static: the map (about 0.96 MB) and the upload buffer (0.54 MB) are members.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/site_map/site_map_upload.hpp"

namespace rse::site_map {

struct SiteMapCounters {
    std::uint32_t chunksTaken = 0;
    std::uint32_t chunksRefused = 0;
    std::uint32_t mapsLoaded = 0;
    std::uint32_t commitsRefused = 0;
    std::uint32_t uploadsAborted = 0;
    std::uint32_t abortsRefused = 0;   // MAP_ABORT with no upload open
};

class SiteMapService {
public:
    explicit SiteMapService(core::EventLog& events) : events_(events) {}

    // MAP_LOAD: kNone when taken, else the refusal (event 591, counted).
    UploadRefusal loadChunk(std::uint32_t offset, const std::uint8_t* data, std::size_t length);
    // MAP_COMMIT: kNone when the image replaced the map in force (event 590),
    // else the refusal (event 592, counted; an image's reason names its rock
    // or zone in lastRefusalItem()).
    UploadRefusal commit(std::uint32_t length, std::uint32_t crc);
    // MAP_ABORT: kNone and event 593 when an upload was open; else
    // kNothingUploaded (event 594, counted).
    UploadRefusal abort();
    void resetCounters() { counters_ = SiteMapCounters{}; }

    const SiteMap& map() const { return map_; }
    const SiteMapUpload& upload() const { return upload_; }
    const SiteMapCounters& counters() const { return counters_; }
    UploadRefusal lastRefusal() const { return lastRefusal_; }
    std::uint32_t lastRefusalItem() const { return lastRefusalItem_; }
    std::uint32_t mapCrc() const { return mapCrc_; }
    std::uint32_t mapBytes() const { return mapBytes_; }

private:
    UploadRefusal refuse(UploadRefusal why, std::uint32_t item);

    core::EventLog& events_;
    SiteMap map_;
    SiteMapUpload upload_;
    SiteMapCounters counters_{};
    UploadRefusal lastRefusal_ = UploadRefusal::kNone;
    std::uint32_t lastRefusalItem_ = 0;
    std::uint32_t mapCrc_ = 0;     // CRC-32 of the image in force (0: none loaded)
    std::uint32_t mapBytes_ = 0;
};

}  // namespace rse::site_map
