#include "fsw/fault_protection/fault_protection_telemetry.hpp"

#include <algorithm>

namespace rse::fault_protection {

core::Status FaultProtectionTelemetry::routeInputs(core::InputPipe& pipe) {
    core::Status status = pipe.route<&FaultProtectionTelemetry::takeStatus>(this);
    if (core::isOk(status)) {
        status = pipe.route<&FaultProtectionTelemetry::takeHold>(this);
    }
    return status;
}

void FaultProtectionTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot == kFaultProtectionSlot || changed_) {
        changed_ = false;
        send(sink);
    }
}

void FaultProtectionTelemetry::send(cmdtlm::TelemetrySink& sink) const {
    cmdtlm::FAULT_PROTECTION_Tlm tlm{};
    const msg::FaultProtectionStatusMsg& p = status_;
    tlm.hold_reasons = p.holdReasons;
    tlm.hold_estop = hold_.estop;
    tlm.resume_count = hold_.resumeCount;
    tlm.responses_started = p.responsesStarted;
    tlm.recoveries = p.recoveries;
    tlm.gave_up = p.gaveUp;
    tlm.actions_sent = p.actionsSent;
    tlm.response_count = std::min<std::uint8_t>(p.activeCount, static_cast<std::uint8_t>(msg::kResponseSlots));
    for (std::size_t i = 0; i < tlm.response_count; ++i) {
        const msg::ResponseTlm& r = p.responses[i];
        tlm.fault_id[i] = r.faultId;
        tlm.fault_class[i] = static_cast<std::uint8_t>(r.faultClass);
        tlm.state[i] = static_cast<std::uint8_t>(r.state);
        tlm.attempts_used[i] = r.attemptsUsed;
        tlm.last_action[i] = r.lastAction;
        tlm.state_since[i] = static_cast<float>(static_cast<double>(r.sinceNs) / static_cast<double>(core::kNsPerSec));
    }
    sink.send(tlm);
}

}  // namespace rse::fault_protection
