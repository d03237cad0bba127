// The fault-protection task (every minor frame, right after the health task):
// the onboard response to every fault the rover detects (cFS Health and
// Safety's role, with the recoveries of a field rover executive). The
// decisions are FaultResponder's (fault_responder.hpp, where each response is
// described); this task feeds it from the bus and publishes what it decides.
//   in:  FaultStatusMsg (health), DriveStatusMsg (drive states, interlock),
//        ModeMsg (holds apply in AUTONOMOUS); the latest of each per run. A
//        message that does not decode, or a drive status with a wheel health
//        outside DriveHealth, is refused whole: counted (malformedMessages())
//        and evented (938) by its core::InputPipe, the previous one stands.
//   out: MissionHoldMsg on every change and at 1 Hz (CAN I/O holds the wheels,
//        the habitual and deliberative layers hold the mission);
//        DriveRecoveryMsg (CAN I/O: fault reset, NMT reset node, interlock reset);
//        TaskRestartMsg (the executive's commands, fsw/cmdtlm: run a stalled row again);
//        SafeRequestMsg (call home: mode SAFE) when a response gives up;
//        FaultProtectionStatusMsg on every change and at 1 Hz (telemetry).
// Running in the same frame as the health task, a fault's first response (the
// hold's e-stop) reaches CAN I/O at the start of the next minor frame.
// Limits are read from FAULT_PROTECTION and FAULT_RESPONSE at every run.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/fault_protection/fault_responder.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::fault_protection {

class FaultProtectionTask final : public core::Task {
public:
    // One fault status, one drive status and a mode change per frame, with margin.
    static constexpr std::uint16_t kPipeDepth = 8;
    static constexpr std::uint32_t kPublishPeriodRuns = 100;

    FaultProtectionTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables);

    // Pipe "fault_protection" (kPipeDepth) routing the inputs above to their
    // takers. A refusal is evented (939) and returned.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    const FaultResponder& responder() const { return responder_; }
    const msg::MissionHoldMsg& hold() const { return hold_; }
    const msg::FaultProtectionStatusMsg& status() const { return status_; }
    std::uint32_t malformedMessages() const { return input_.malformed(); }
    std::uint32_t publishFailures() const { return publishFailed_; }
    std::uint32_t callHomes() const { return callHomes_; }

private:
    // The pipe's takers: each keeps the latest of its input in inputs_.
    void takeFaultStatus(const msg::FaultStatusMsg& f);
    core::Status takeDriveStatus(const msg::DriveStatusMsg& d);
    void takeMode(const msg::ModeMsg& m);
    void publish(core::Status s);
    void publishHold(core::TimeNs now, std::uint32_t reasons, bool force);

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    FaultResponder responder_;
    core::InputPipe input_;
    ResponderInputs inputs_{};
    msg::MissionHoldMsg hold_{};
    msg::FaultProtectionStatusMsg status_{};
    std::uint32_t runsSincePublish_ = kPublishPeriodRuns;  // publish in the first run
    std::uint32_t publishFailed_ = 0;
    std::uint32_t callHomes_ = 0;
};

}  // namespace rse::fault_protection
