#include "fsw/estimator/health_task.hpp"

#include <cmath>

#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::estimator {

core::Status HealthTask::init() {
    core::Status status = bus_.createPipe("health", kPipeDepth, &pipe_);
    const core::MsgId inputs[] = {msg::ids::kNodeStatus, msg::ids::kPower,       msg::ids::kDriveStatus,
                                  msg::ids::kPoseEstimate, msg::ids::kImu,      msg::ids::kPositionFix,
                                  msg::ids::kHazards};
    for (core::MsgId id : inputs) {
        if (core::isOk(status)) {
            status = bus_.subscribe(pipe_, id);
        }
    }
    return status;
}

void HealthTask::rejectMessage() {
    ++malformed_;
    if (core::isReportableOccurrence(malformed_)) {
        events_.report(events::kHealthInputRejected, core::Severity::kWarning,
                       "health: malformed bus message 0x%04x (%u bytes) ignored (%u so far)",
                       static_cast<unsigned>(inbox_.header.id), static_cast<unsigned>(inbox_.header.length),
                       static_cast<unsigned>(malformed_));
    }
}

void HealthTask::drainInputs(const HealthLimits& limits, core::TimeNs now) {
    // Bounded by the pipe depth: nothing is published to the pipe while we drain.
    for (std::uint16_t n = 0; n < kPipeDepth; ++n) {
        if (!core::isOk(bus_.receive(pipe_, &inbox_))) {
            break;
        }
        core::Status decoded = core::Status::kWrongType;
        switch (inbox_.header.id) {
            case msg::ids::kNodeStatus:
                decoded = inbox_.decode(&nodes_);
                haveNodes_ = haveNodes_ || core::isOk(decoded);
                break;
            case msg::ids::kDriveStatus:
                decoded = inbox_.decode(&drives_);
                haveDrives_ = haveDrives_ || core::isOk(decoded);
                break;
            case msg::ids::kPoseEstimate:
                decoded = inbox_.decode(&pose_);
                havePose_ = havePose_ || core::isOk(decoded);
                break;
            case msg::ids::kPower: {
                // Every sample, in order: persistence is measured on sample times.
                msg::PowerMsg power{};
                decoded = inbox_.decode(&power);
                if (core::isOk(decoded)) {
                    monitor_.onPower(power, limits, now);
                    if (std::isfinite(power.busVoltageV) && std::isfinite(power.busCurrentA)) {
                        monitor_.onSensorData(msg::DeviceNode::kPower, power.timeNs);
                    }
                }
                break;
            }
            // Staleness counts usable data only: a device that keeps sending
            // samples it flags invalid leaves the estimator as blind as silence.
            case msg::ids::kImu: {
                msg::ImuMsg imu{};
                decoded = inbox_.decode(&imu);
                if (core::isOk(decoded) && imu.valid == 1 && std::isfinite(imu.yawRateRadS)) {
                    monitor_.onSensorData(msg::DeviceNode::kImu, imu.timeNs);
                }
                break;
            }
            case msg::ids::kPositionFix: {
                msg::PositionFixMsg fix{};
                decoded = inbox_.decode(&fix);
                if (core::isOk(decoded) && std::isfinite(fix.xM) && std::isfinite(fix.yM) &&
                    std::isfinite(fix.headingRad) && std::isfinite(fix.sigmaM) && fix.sigmaM > 0.0) {
                    monitor_.onSensorData(msg::DeviceNode::kPositionFix, fix.timeNs);
                }
                break;
            }
            case msg::ids::kHazards:
                decoded = inbox_.decode(&hazards_);
                if (core::isOk(decoded)) {
                    monitor_.onHazards(hazards_);
                }
                break;
            default:
                break;
        }
        if (!core::isOk(decoded)) {
            rejectMessage();
        }
    }
}

void HealthTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    const bool firstRun = !monitor_.started();
    monitor_.start(now);
    ++runs_;
    const HealthLimits limits = healthLimitsFrom(tables_.faultResponse(), tables_.estimatorNoise(), tables_.coarseMap());
    const std::uint32_t transitionsBefore = monitor_.faults().raisedTotal() + monitor_.faults().clearedTotal();

    haveNodes_ = false;
    haveDrives_ = false;
    havePose_ = false;
    drainInputs(limits, now);
    if (haveNodes_) {
        monitor_.onNodeStatus(nodes_, now);
    }
    if (haveDrives_) {
        monitor_.onDriveStatus(drives_, limits, now);
    }
    if (havePose_) {
        monitor_.onPose(pose_);
    }
    monitor_.checkPose(limits, now);
    monitor_.checkOffMap(limits, now);
    monitor_.checkSensors(limits, now);
    monitor_.checkTasks(executive_, this, limits, now);

    const bool changed = monitor_.faults().raisedTotal() + monitor_.faults().clearedTotal() != transitionsBefore;
    ++runsSincePublish_;
    if (firstRun || changed || runsSincePublish_ >= kPublishPeriodRuns) {
        publishStatus(now);
    }
}

void HealthTask::publishStatus(core::TimeNs now) {
    const FaultBook& faults = monitor_.faults();
    status_.timeNs = now;
    status_.activeMask = faults.activeMask();
    status_.raisedTotal = faults.raisedTotal();
    status_.clearedTotal = faults.clearedTotal();
    status_.lastFaultId = faults.lastFaultId();
    status_.lastRaised = faults.lastRaised() ? 1 : 0;
    (void)bus_.publish(status_);
    ++published_;
    runsSincePublish_ = 0;
}

}  // namespace rse::estimator
