// What the command task needs from the application: the mode (a precondition of
// every command) and someone to carry out a command that passed every check.
// The command router implements it (command_router.hpp): it hands each command
// to the application that owns its APID (app_commands.hpp), so the command
// service stays free of the subsystems the commands reach.
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::cmdtlm {

class CommandHandler {
public:
    virtual Mode mode() const = 0;
    // verdict.reason is kAccepted; verdict.command and verdict.args are set.
    virtual CommandOutcome execute(const CommandVerdict& verdict) = 0;
    // Once per command-task run, before the commands: requests the onboard
    // layers make of what the application owns (e.g. a call home asking for SAFE).
    virtual void serviceOnboardRequests() {}

protected:
    ~CommandHandler() = default;
};

}  // namespace rse::cmdtlm
