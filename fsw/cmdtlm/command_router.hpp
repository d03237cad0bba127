// The command service's dispatch to the applications (cFS's software bus
// routing a command to the app that owns its message id): the command task
// (command_task.hpp) checks each command and hands an accepted one here; the
// router gives it to the application registered for its APID (app_commands.hpp).
//   start-up   init() creates the onboard-request pipe ("mode_requests"), then
//              each application registers (add) and routes the onboard
//              requests it takes on requests(): the mode owner call homes
//              (SafeRequestMsg), the executive's commands fault protection's
//              task restarts (TaskRestartMsg)
//   each run   serviceOnboardRequests(): the pipe drained in arrival order
//              (each request to its owner), then each application's own
//              serviceOnboardRequests() in registration order; then the
//              command task's commands, each through execute()
// A command whose APID no application owns fails (execution_failed, detail
// -1), counted and evented (510); the dictionary and the registrations in
// fsw/app/fsw_app.cpp keep that from happening.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/command_handler.hpp"
#include "fsw/cmdtlm/rover_mode.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"

namespace rse::cmdtlm {

// Applications that own commands: APIDs 0x180-0x185 today, two spare.
constexpr std::size_t kMaxAppCommands = 8;
// Call homes and task restarts a frame (one per stalled row at most).
constexpr std::uint16_t kOnboardRequestDepth = 8;

class CommandRouter final : public CommandHandler {
public:
    CommandRouter(core::SoftwareBus& bus, core::EventLog& events, const RoverMode& mode);
    CommandRouter(const CommandRouter&) = delete;
    CommandRouter& operator=(const CommandRouter&) = delete;

    // Start-up: the onboard-request pipe. The bus's refusal as it is.
    core::Status init() { return requests_.create(); }
    // Start-up, after init(): where applications route their onboard requests.
    core::InputPipe& requests() { return requests_; }
    // Start-up: app owns the commands of app->apid(). kInvalidArgument (null),
    // kAlreadyExists (the APID has an owner), kNoCapacity (kMaxAppCommands):
    // refused and evented (509).
    core::Status add(AppCommands* app);

    Mode mode() const override { return mode_.mode(); }
    CommandOutcome execute(const CommandVerdict& verdict) override;
    void serviceOnboardRequests() override;
    // RESET_COUNTERS: every registered application's counters.
    void resetAppCounters();

    std::size_t size() const { return count_; }
    std::uint32_t commandsWithoutOwner() const { return withoutOwner_; }
    std::uint32_t malformedRequests() const { return requests_.malformed(); }

private:
    AppCommands* ownerOf(std::uint16_t apid) const;

    core::EventLog& events_;
    const RoverMode& mode_;
    core::InputPipe requests_;
    AppCommands* apps_[kMaxAppCommands] = {};
    std::size_t count_ = 0;
    std::uint32_t withoutOwner_ = 0;
};

}  // namespace rse::cmdtlm
