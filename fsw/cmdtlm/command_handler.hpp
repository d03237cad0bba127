// What the command task needs from the application: the mode (a precondition of
// every command) and someone to carry out a command that passed every check.
// The application implements it (fsw/app/command_handlers.*), so the command
// service stays free of the subsystems the commands reach.
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::cmdtlm {

struct CommandOutcome {
    bool ok = true;
    std::int16_t detail = -1;  // CMD_ACK.detail when !ok (e.g. the table reject code)
};

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
