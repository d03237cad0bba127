#include "fsw/cmdtlm/service_commands.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

CommandOutcome ServiceCommands::execute(const CommandVerdict& verdict) {
    switch (verdict.command->code) {
        case CommandCode::NOOP:
            parts_.events.report(events::kNoop, core::Severity::kInfo, "cmd: NOOP (key %u, seq %u)",
                                 static_cast<unsigned>(verdict.keyId), static_cast<unsigned>(verdict.authSequence));
            return {};
        case CommandCode::RESET_COUNTERS:
            resetEveryCounter();
            parts_.events.report(events::kCountersReset, core::Severity::kInfo, "cmd: counters reset");
            return {};
        case CommandCode::REQUEST_HK:
            parts_.housekeeping.requestHousekeeping();
            return {};
        case CommandCode::AUTH_RESYNC:
            // The validator did the work (the nonce matched, the floor moved and
            // was persisted); unauthenticated, in the lab setting, there is no key to resync.
            if (verdict.keyId == kNoKey) {
                return commandFailed(1);
            }
            parts_.events.report(events::kAuthResynced, core::Severity::kWarning,
                                 "cmd: AUTH_RESYNC: key %u re-synchronised (seq %u, floor in HK and the store)",
                                 static_cast<unsigned>(verdict.keyId), static_cast<unsigned>(verdict.authSequence));
            return {};
        case CommandCode::SET_MODE:
            parts_.mode.setMode(static_cast<Mode>(decodedArgs<SET_MODE_Args>(verdict).mode));
            return {};
        default:
            break;
    }
    return commandFailed(-1);
}

void ServiceCommands::resetEveryCounter() {
    parts_.executive.resetCounters();
    parts_.bus.resetCounters();
    parts_.events.resetCounters();
    parts_.telemetry.resetCounters();
    parts_.router.resetAppCounters();  // the table service's, through its commands
    parts_.commands.resetCounters();
}

}  // namespace rse::cmdtlm
