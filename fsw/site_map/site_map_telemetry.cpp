#include "fsw/site_map/site_map_telemetry.hpp"

namespace rse::site_map {

cmdtlm::SITE_MAP_Tlm SiteMapTelemetry::packet() const {
    cmdtlm::SITE_MAP_Tlm t{};
    const SiteMap& map = service_.map();
    const SiteMapCounters& c = service_.counters();
    t.revision = map.loaded() ? map.revision() : 0U;
    t.rocks = static_cast<std::uint32_t>(map.rockCount());
    t.keep_outs = static_cast<std::uint16_t>(map.keepOutCount());
    t.x_min = map.site().xMin;
    t.y_min = map.site().yMin;
    t.x_max = map.site().xMax;
    t.y_max = map.site().yMax;
    t.map_bytes = service_.mapBytes();
    t.map_crc32 = service_.mapCrc();
    t.upload_bytes = static_cast<std::uint32_t>(service_.upload().length());
    t.upload_open = service_.upload().open() ? 1U : 0U;
    t.last_refusal = static_cast<std::uint8_t>(service_.lastRefusal());
    t.last_refusal_item = service_.lastRefusalItem();
    t.chunks_taken = c.chunksTaken;
    t.chunks_refused = c.chunksRefused;
    t.maps_loaded = c.mapsLoaded;
    t.commits_refused = c.commitsRefused;
    t.uploads_aborted = c.uploadsAborted;
    t.aborts_refused = c.abortsRefused;
    t.commit_phase = static_cast<std::uint8_t>(service_.commitPhase());
    t.commit_runs = service_.commitRuns();
    t.commits_started = service_.commitsStarted();
    t.commits_cancelled = service_.commitsCancelled();
    return t;
}

void SiteMapTelemetry::send(cmdtlm::TelemetrySink& sink) {
    sink.send(packet());
}

}  // namespace rse::site_map
