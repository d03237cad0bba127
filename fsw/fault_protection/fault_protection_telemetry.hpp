// FAULT_PROTECTION (docs/icd.md §5.5), packed from what the fault protection
// task publishes (a telemetry packer, cmdtlm/telemetry_packer.hpp): slot
// kFaultProtectionSlot of every second, and in the run after each
// FaultProtectionStatusMsg (published at 1 Hz and on every change: each one is
// news). The hold's e-stop and resume count come from the last MissionHoldMsg.
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"

namespace rse::fault_protection {

constexpr std::uint32_t kFaultProtectionSlot = 80;

class FaultProtectionTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override;
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    void takeStatus(const msg::FaultProtectionStatusMsg& status) {
        status_ = status;
        changed_ = true;
    }
    void takeHold(const msg::MissionHoldMsg& hold) { hold_ = hold; }
    void send(cmdtlm::TelemetrySink& sink) const;

    msg::FaultProtectionStatusMsg status_{};
    msg::MissionHoldMsg hold_{};
    bool changed_ = false;  // FAULT_PROTECTION goes in the next run
};

}  // namespace rse::fault_protection
