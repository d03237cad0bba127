#include "fsw/reflexive/mobility_commands.hpp"

#include "fsw/msg/mode_msgs.hpp"

namespace rse::reflexive {

using cmdtlm::CommandCode;
using cmdtlm::CommandOutcome;

CommandOutcome MobilityCommands::execute(const cmdtlm::CommandVerdict& verdict) {
    switch (verdict.command->code) {
        case CommandCode::ESTOP_SET:
            estop_.setEstop(true);
            return {};
        case CommandCode::ESTOP_CLEAR:
            estop_.setEstop(false);
            return {};
        case CommandCode::RESET_INTERLOCK: {
            msg::InterlockResetMsg request{};
            request.timeNs = clock_.now();
            return core::isOk(bus_.publish(request)) ? CommandOutcome{} : cmdtlm::commandFailed(0);
        }
        case CommandCode::DRIVE:
            return drive(cmdtlm::decodedArgs<cmdtlm::DRIVE_Args>(verdict));
        default:
            break;
    }
    return cmdtlm::commandFailed(-1);
}

CommandOutcome MobilityCommands::drive(const cmdtlm::DRIVE_Args& args) {
    if (estop_.estop()) {
        return cmdtlm::commandFailed(0);  // the e-stop holds: clear it first
    }
    msg::ManualDriveMsg request{};
    request.timeNs = clock_.now();
    request.speedMS = static_cast<double>(args.v);
    request.turnRateRadS = static_cast<double>(args.omega);
    request.durationS = static_cast<double>(args.duration);
    return core::isOk(bus_.publish(request)) ? CommandOutcome{} : cmdtlm::commandFailed(1);
}

}  // namespace rse::reflexive
