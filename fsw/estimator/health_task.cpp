#include "fsw/estimator/health_task.hpp"

#include <cmath>

#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::estimator {

HealthTask::HealthTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
                       const core::Executive& executive)
    : bus_(bus),
      tables_(tables),
      executive_(executive),
      monitor_(events),
      input_(bus, events,
             core::InputPipeConfig{"health", kPipeDepth, events::kHealthInputRejected, "health",
                                   core::Severity::kWarning}) {}

core::Status HealthTask::init() {
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takeNodes>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takePower>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takeDrives>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takePose>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takeImu>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takeFix>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&HealthTask::takeHazards>(this);
    }
    return status;
}

void HealthTask::takeNodes(const msg::NodeStatusMsg& nodes) {
    nodes_ = nodes;
    haveNodes_ = true;
}

void HealthTask::takeDrives(const msg::DriveStatusMsg& drives) {
    drives_ = drives;
    haveDrives_ = true;
}

void HealthTask::takePose(const msg::PoseEstimateMsg& pose) {
    pose_ = pose;
    havePose_ = true;
}

void HealthTask::takePower(const msg::PowerMsg& power) {
    // Every sample, in order: persistence is measured on sample times.
    monitor_.onPower(power, limits_, now_);
    if (std::isfinite(power.busVoltageV) && std::isfinite(power.busCurrentA)) {
        monitor_.onSensorData(msg::DeviceNode::kPower, power.timeNs);
    }
}

// Staleness counts usable data only: a device that keeps sending samples it
// flags invalid leaves the estimator as blind as silence.
void HealthTask::takeImu(const msg::ImuMsg& imu) {
    if (imu.valid == 1 && std::isfinite(imu.yawRateRadS)) {
        monitor_.onSensorData(msg::DeviceNode::kImu, imu.timeNs);
    }
}

void HealthTask::takeFix(const msg::PositionFixMsg& fix) {
    if (std::isfinite(fix.xM) && std::isfinite(fix.yM) && std::isfinite(fix.headingRad) &&
        std::isfinite(fix.sigmaM) && fix.sigmaM > 0.0) {
        monitor_.onSensorData(msg::DeviceNode::kPositionFix, fix.timeNs);
    }
}

void HealthTask::takeHazards(const msg::HazardMsg& hazards) {
    hazards_ = hazards;
    monitor_.onHazards(hazards_);
}

void HealthTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    const bool firstRun = !monitor_.started();
    monitor_.start(now);
    ++runs_;
    now_ = now;
    limits_ = healthLimitsFrom(tables_.faultResponse(), tables_.estimatorNoise(), tables_.coarseMap());
    const HealthLimits& limits = limits_;
    const std::uint32_t transitionsBefore = monitor_.faults().raisedTotal() + monitor_.faults().clearedTotal();

    haveNodes_ = false;
    haveDrives_ = false;
    havePose_ = false;
    input_.drain();
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
