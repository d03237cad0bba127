// The site map's packet (SITE_MAP, docs/site_map.md), sent right after each
// site map command through the command task's telemetry sink: the map in
// force, the upload and its last refusal, the service's counters.
#pragma once

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/site_map/site_map_service.hpp"

namespace rse::site_map {

class SiteMapTelemetry {
public:
    explicit SiteMapTelemetry(const SiteMapService& service) : service_(service) {}

    void send(cmdtlm::TelemetrySink& sink);
    // What send() packs (for tests and the housekeeping of later users).
    cmdtlm::SITE_MAP_Tlm packet() const;

private:
    const SiteMapService& service_;
};

}  // namespace rse::site_map
