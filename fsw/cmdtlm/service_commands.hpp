// The command and telemetry service's own commands (APID 0x180): NOOP (proves
// the link), RESET_COUNTERS (the counters ground reads, everywhere), REQUEST_HK
// (HK and TASK_TIMING now), SET_MODE (through the mode owner) and AUTH_RESYNC
// (the validator already did the work; this reports it).
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/command_router.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/cmdtlm/housekeeping_telemetry.hpp"
#include "fsw/cmdtlm/rover_mode.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"

namespace rse::cmdtlm {

class ServiceCommands final : public AppCommands {
public:
    // What the commands reach; all owned by the application (fsw/app).
    struct Parts {
        core::EventLog& events;
        core::SoftwareBus& bus;
        core::Executive& executive;
        TelemetryOutput& telemetry;
        CommandTask& commands;
        CommandRouter& router;  // RESET_COUNTERS reaches every application through it
        RoverMode& mode;
        HousekeepingTelemetry& housekeeping;
    };
    explicit ServiceCommands(const Parts& parts) : parts_(parts) {}

    std::uint16_t apid() const override { return describe(CommandCode::NOOP).apid; }
    CommandOutcome execute(const CommandVerdict& verdict) override;

private:
    // RESET_COUNTERS: executive, bus, events, telemetry, every application (its
    // resetCounters()), commands. Not named resetCounters: this app has none of its own.
    void resetEveryCounter();

    Parts parts_;
};

}  // namespace rse::cmdtlm
