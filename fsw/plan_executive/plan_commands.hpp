// The plan commands (APID 0x185), owned by the plan executive: PLAN_LOAD,
// PLAN_START, PLAN_SHORT, PLAN_ABORT and PLAN_EXTEND go to the plan executive
// task as they are (PlanCommandMsg): it checks them (offsets, length, CRC,
// the text) and events every refusal. A command is carried out when the bus
// took the message (execution_failed detail 0: it did not).
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"

namespace rse::plan_executive {

class PlanCommands final : public cmdtlm::AppCommands {
public:
    PlanCommands(const core::Clock& clock, core::SoftwareBus& bus) : clock_(clock), bus_(bus) {}

    std::uint16_t apid() const override { return cmdtlm::describe(cmdtlm::CommandCode::PLAN_LOAD).apid; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;

private:
    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    msg::PlanCommandMsg message_{};  // about 1 KiB: kept off the command task's stack
};

}  // namespace rse::plan_executive
