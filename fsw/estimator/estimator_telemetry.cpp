#include "fsw/estimator/estimator_telemetry.hpp"

namespace rse::estimator {

core::Status EstimatorTelemetry::routeInputs(core::InputPipe& pipe) {
    core::Status status = pipe.route<&EstimatorTelemetry::takePose>(this);
    if (core::isOk(status)) {
        status = pipe.route<&EstimatorTelemetry::takeFaults>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&EstimatorTelemetry::takeDriveModes>(this);
    }
    return status;
}

void EstimatorTelemetry::takeFaults(const msg::FaultStatusMsg& faults) {
    healthChanged_ = healthChanged_ || faults.activeMask != faults_.activeMask;
    faults_ = faults;
}

void EstimatorTelemetry::takeDriveModes(const msg::DriveModesMsg& modes) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        healthChanged_ = healthChanged_ || modes.drives[w].declared != driveModes_.drives[w].declared;
    }
    driveModes_ = modes;
}

void EstimatorTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot == kRoverStateSlot) {
        sendRoverState(sink);
    }
    if (frame.slot == kHealthSlot || healthChanged_) {
        healthChanged_ = false;
        sendHealth(sink);
    }
}

void EstimatorTelemetry::sendRoverState(cmdtlm::TelemetrySink& sink) const {
    cmdtlm::ROVER_STATE_Tlm tlm{};
    tlm.estimate_valid = pose_.initialised;
    tlm.yaw_from_imu = pose_.yawFromImu;
    tlm.x = pose_.xM;
    tlm.y = pose_.yM;
    tlm.heading = pose_.headingRad;
    for (std::size_t i = 0; i < 9; ++i) {
        tlm.covariance[i] = static_cast<float>(pose_.covariance[i]);
    }
    tlm.position_sigma = static_cast<float>(pose_.positionSigmaM);
    tlm.speed = static_cast<float>(pose_.speedMS);
    tlm.turn_rate = static_cast<float>(pose_.yawRateRadS);
    tlm.gyro_bias = static_cast<float>(pose_.gyroBiasRadS);
    tlm.fixes_accepted = pose_.fixesAccepted;
    tlm.fixes_rejected = pose_.fixesRejected;
    tlm.fixes_invalid = pose_.fixesInvalid;
    sink.send(tlm);
}

void EstimatorTelemetry::sendHealth(cmdtlm::TelemetrySink& sink) const {
    cmdtlm::HEALTH_Tlm tlm{};
    tlm.active_faults = faults_.activeMask;
    tlm.faults_raised = faults_.raisedTotal;
    tlm.faults_cleared = faults_.clearedTotal;
    tlm.last_fault_id = faults_.lastFaultId;
    tlm.last_fault_raised = faults_.lastRaised;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const msg::DriveModeBelief& b = driveModes_.drives[w];
        tlm.drive_mode[w] = static_cast<std::uint8_t>(b.declared);
        tlm.p_nominal[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kNominal)];
        tlm.p_degraded[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kDegraded)];
        tlm.p_failed[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kFailed)];
        tlm.p_unknown[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kUnknown)];
        tlm.power_factor[w] = b.powerFactor;
    }
    sink.send(tlm);
}

}  // namespace rse::estimator
