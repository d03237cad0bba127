// The software e-stop as an application that commands it sees it: read it,
// set it, clear it; nothing of the rover mode. The mode owner
// (rover_mode.hpp, cmdtlm::RoverMode) implements it: a change is evented
// (206 set, 207 cleared) and announced (ModeMsg, which CAN I/O holds the
// drives on). Part of the application interface (app_commands.hpp), so the
// mobility commands (fsw/reflexive) can hold the e-stop while no layer can
// change the mode by a direct call: the mode is ground's (SET_MODE) and a
// call home's (SafeRequestMsg), both through the command service.
#pragma once

namespace rse::cmdtlm {

class EstopSwitch {
public:
    // True while the software e-stop holds the drives.
    virtual bool estop() const = 0;
    // ESTOP_SET (true) / ESTOP_CLEAR (false): evented and announced, even when
    // the e-stop is already so.
    virtual void setEstop(bool set) = 0;

protected:
    ~EstopSwitch() = default;
};

}  // namespace rse::cmdtlm
