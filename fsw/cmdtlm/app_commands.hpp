// What an application implements to own one APID's ground commands, as a cFS
// app owns its command message id and dispatch: the command service
// (command_task.hpp) checks a packet (length, checksum, key, MAC, anti-replay,
// arguments, mode) and the command router (command_router.hpp) hands an
// accepted one to the application registered for its APID. The application
// decodes the arguments (decodedArgs), acts, and says whether it could
// (CommandOutcome: CMD_ACK's execution_failed and detail when it could not).
//
// The application interface of fsw/cmdtlm: the only headers of this folder an
// application outside it may include (a layer, fsw/tables, fsw/io), so the
// command service's checks, crypto, links and tasks, and the mode owner
// (rover_mode.hpp: no application sets the mode by a call), stay inside it.
// unit_test/system/layering/test_layer_includes.cpp holds the layers and
// fsw/tables to this list (kCmdTlmInterface, checked against these lines):
//   dictionary.hpp               generated command arguments and telemetry packets
//   command_verdict.hpp          CommandVerdict: the accepted command and its argument bytes
//   app_commands.hpp             this: AppCommands, CommandOutcome, decodedArgs
//   telemetry_sink.hpp           TelemetrySink: send one telemetry packet
//   telemetry_packer.hpp         TelemetryPacker: own a packet family, scheduled by the telemetry task
//   housekeeping_contributor.hpp HousekeepingContributor: fill an application's own HK fields
//   estop_switch.hpp             EstopSwitch: set, clear and read the software e-stop (mobility)
//   event_data.hpp               generated event data: the numbers an event carries, set by name
// fsw/io also includes ccsds.hpp (packet sizes: its CAN ground link carries packets).
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::cmdtlm {

struct CommandOutcome {
    bool ok = true;
    std::int16_t detail = -1;  // CMD_ACK.detail when !ok (e.g. the table reject code)
};

// The outcome of a command the application could not carry out.
constexpr CommandOutcome commandFailed(std::int16_t detail) { return CommandOutcome{false, detail}; }

// An accepted command's arguments. The validator has checked their length and
// ranges against the dictionary, so decoding cannot fail.
template <typename Args>
Args decodedArgs(const CommandVerdict& verdict) {
    Args args{};
    core::BeReader r(verdict.args, verdict.argLength);
    decodeArgs(r, &args);
    return args;
}

class AppCommands {
public:
    // The APID whose commands this application owns (from the dictionary).
    virtual std::uint16_t apid() const = 0;
    // verdict.reason is kAccepted and verdict.command one of apid()'s commands.
    virtual CommandOutcome execute(const CommandVerdict& verdict) = 0;
    // Once per command-task run, before the commands and after the router took
    // the onboard requests off its pipe: work the application does on its own
    // behalf in the command task's frame, in the rover's mode now (a command's
    // mode check is at its acceptance; work that spans runs checks again).
    virtual void serviceOnboardRequests(Mode mode) { (void)mode; }
    // RESET_COUNTERS: the counters the application keeps for ground.
    virtual void resetCounters() {}

protected:
    ~AppCommands() = default;
};

}  // namespace rse::cmdtlm
