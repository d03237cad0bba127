// The site map commands (APID 0x186), owned by the site map service: MAP_LOAD
// (a chunk of the image), MAP_COMMIT (length and CRC-32: the image put in
// force when it passes its check whole) and MAP_ABORT. Each is answered with
// SITE_MAP and refused (execution_failed) with the UploadRefusal code as
// CMD_ACK.detail. A commit that starts is accepted; its slices run here, one
// each command-task run (serviceOnboardRequests), and SITE_MAP is sent again
// in the run it ends (commit_phase 0: in force, or refused with its reason).
// A commit still under way when the rover is put in AUTONOMOUS or MANUAL is
// refused (8) in the next run: the rover does not change maps while driving.
// RESET_COUNTERS zeroes the service's counters.
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/site_map/site_map_service.hpp"
#include "fsw/site_map/site_map_telemetry.hpp"

namespace rse::site_map {

class SiteMapCommands final : public cmdtlm::AppCommands {
public:
    SiteMapCommands(SiteMapService& service, SiteMapTelemetry& telemetry, cmdtlm::TelemetrySink& sink)
        : service_(service), telemetry_(telemetry), sink_(sink) {}

    std::uint16_t apid() const override { return cmdtlm::describe(cmdtlm::CommandCode::MAP_LOAD).apid; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;
    void serviceOnboardRequests(cmdtlm::Mode mode) override {
        const bool driving = mode == cmdtlm::Mode::kAutonomous || mode == cmdtlm::Mode::kManual;
        if (service_.serviceCommit(driving)) {
            telemetry_.send(sink_);
        }
    }
    void resetCounters() override { service_.resetCounters(); }

private:
    SiteMapService& service_;
    SiteMapTelemetry& telemetry_;
    cmdtlm::TelemetrySink& sink_;
};

}  // namespace rse::site_map
