// PLAN_EXEC (docs/icd.md §5.5), packed from what the plan executive publishes
// (a telemetry packer, cmdtlm/telemetry_packer.hpp): slot kPlanExecSlot of
// every second, and in the run after a PlanExecutiveStatusMsg whose state,
// counters, selection or activities changed (published at 1 Hz and on change;
// its slack and plan time alone are not news).
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"

namespace rse::plan_executive {

constexpr std::uint32_t kPlanExecSlot = 40;

class PlanExecTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override {
        return pipe.route<&PlanExecTelemetry::takeStatus>(this);
    }
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    void takeStatus(const msg::PlanExecutiveStatusMsg& status);
    void send(cmdtlm::TelemetrySink& sink) const;

    msg::PlanExecutiveStatusMsg status_{};
    bool changed_ = false;  // PLAN_EXEC goes in the next run
};

}  // namespace rse::plan_executive
