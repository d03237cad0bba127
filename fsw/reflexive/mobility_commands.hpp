// The mobility commands (APID 0x182), owned by the reflexive layer that turns
// them into wheel motion:
//   ESTOP_SET / ESTOP_CLEAR  the software e-stop, through its switch
//                            (cmdtlm::EstopSwitch, kept by the mode owner:
//                            evented, announced in ModeMsg, which CAN I/O holds
//                            the drives on); the rover mode is not theirs
//   DRIVE                    a manual drive (ManualDriveMsg to the manual-drive
//                            task); refused while the e-stop holds (detail 0:
//                            clear it first), or when the bus refuses it (detail 1)
//   RESET_INTERLOCK          asks CAN I/O to release the drive interlock
//                            (InterlockResetMsg); refused when the bus refuses it (detail 0)
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/estop_switch.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"

namespace rse::reflexive {

class MobilityCommands final : public cmdtlm::AppCommands {
public:
    MobilityCommands(const core::Clock& clock, core::SoftwareBus& bus, cmdtlm::EstopSwitch& estop)
        : clock_(clock), bus_(bus), estop_(estop) {}

    std::uint16_t apid() const override { return cmdtlm::describe(cmdtlm::CommandCode::DRIVE).apid; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;

private:
    cmdtlm::CommandOutcome drive(const cmdtlm::DRIVE_Args& args);

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    cmdtlm::EstopSwitch& estop_;
};

}  // namespace rse::reflexive
