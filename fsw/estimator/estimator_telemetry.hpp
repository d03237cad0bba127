// The estimator's packets (docs/icd.md §5.5), packed from what the estimator
// tasks publish (a telemetry packer, cmdtlm/telemetry_packer.hpp):
//   ROVER_STATE  slot kRoverStateSlot of every second: the pose estimate
//                (PoseEstimateMsg), its covariance and the fixes taken
//   HEALTH       slot kHealthSlot of every second, and in the run after the
//                active faults (FaultStatusMsg) or a drive's declared mode
//                (DriveModesMsg) changed: faults, and each drive's mode beliefs
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"

namespace rse::estimator {

constexpr std::uint32_t kRoverStateSlot = 60;
constexpr std::uint32_t kHealthSlot = 70;

class EstimatorTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override;
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    void takePose(const msg::PoseEstimateMsg& pose) { pose_ = pose; }
    void takeFaults(const msg::FaultStatusMsg& faults);
    void takeDriveModes(const msg::DriveModesMsg& modes);
    void sendRoverState(cmdtlm::TelemetrySink& sink) const;
    void sendHealth(cmdtlm::TelemetrySink& sink) const;

    msg::PoseEstimateMsg pose_{};
    msg::FaultStatusMsg faults_{};
    msg::DriveModesMsg driveModes_{};
    bool healthChanged_ = false;  // HEALTH goes in the next run
};

}  // namespace rse::estimator
