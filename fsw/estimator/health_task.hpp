// The health task (every minor frame, after the CAN I/O task and the pose
// estimator task in the same frame): feeds the health monitor's rules
// (fsw/estimator/health_monitor.hpp, where the detection bounds are) and tells
// the executive and telemetry which faults are active.
//   in:  NodeStatusMsg, DriveStatusMsg, PoseEstimateMsg (the latest of each per
//        run), PowerMsg (every sample, in order), ImuMsg, PositionFixMsg and
//        HazardMsg (for the sensor-stale rules); the executive's task liveness
//        (read directly: it is the executive's own state, not a message).
//   out: FaultStatusMsg in every run in which a fault changed state, otherwise
//        every kPublishPeriodRuns runs (1 s), and in the first run.
// A message that does not decode is counted and evented (throttled, event 740 as
// a warning) and ignored: core::InputPipe.
// Limits are read from the fault-response and estimator-noise tables at every
// run, so a table activated at a frame boundary applies from that frame.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/health_monitor.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::estimator {

class HealthTask final : public core::Task {
public:
    // Up to seven inputs in one frame (node, drive, pose, IMU every frame; power,
    // hazard, fix at 10 / 10 / 1 Hz), plus margin for a frame the task misses.
    static constexpr std::uint16_t kPipeDepth = 16;
    static constexpr std::uint32_t kPublishPeriodRuns = 100;

    HealthTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
               const core::Executive& executive);

    // Pipe "health" (kPipeDepth) routing the inputs above to their takers.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    bool active(std::uint8_t faultId) const { return monitor_.faults().isActive(faultId); }
    std::uint32_t raisedCount(std::uint8_t faultId) const { return monitor_.faults().raisedCount(faultId); }
    std::uint32_t clearedCount(std::uint8_t faultId) const { return monitor_.faults().clearedCount(faultId); }
    // The latest FaultStatusMsg published.
    const msg::FaultStatusMsg& status() const { return status_; }
    const HealthMonitor& monitor() const { return monitor_; }

    // Bus messages that did not decode as the type their id names.
    std::uint32_t malformedMessages() const { return input_.malformed(); }
    // Input values that were not finite (or out of their domain); see HealthMonitor.
    std::uint32_t nonFiniteInputs() const { return monitor_.nonFiniteInputs(); }
    std::uint32_t statusPublished() const { return published_; }
    std::uint32_t runs() const { return runs_; }

private:
    // The pipe's takers, in arrival order. Node, drive and pose statuses: the
    // latest is kept for after the drain; power samples, each in order, and
    // the sensor samples go to the monitor at once (limits_ and now_ of this run).
    void takeNodes(const msg::NodeStatusMsg& nodes);
    void takeDrives(const msg::DriveStatusMsg& drives);
    void takePose(const msg::PoseEstimateMsg& pose);
    void takePower(const msg::PowerMsg& power);
    void takeImu(const msg::ImuMsg& imu);
    void takeFix(const msg::PositionFixMsg& fix);
    void takeHazards(const msg::HazardMsg& hazards);
    void publishStatus(core::TimeNs now);

    core::SoftwareBus& bus_;
    const tables::TableService& tables_;
    const core::Executive& executive_;
    HealthMonitor monitor_;
    core::InputPipe input_;
    HealthLimits limits_{};  // read from the tables at the start of every run
    core::TimeNs now_ = 0;   // this run's frame start
    msg::NodeStatusMsg nodes_{};
    msg::DriveStatusMsg drives_{};
    msg::PoseEstimateMsg pose_{};
    msg::HazardMsg hazards_{};
    bool haveNodes_ = false;
    bool haveDrives_ = false;
    bool havePose_ = false;
    msg::FaultStatusMsg status_{};
    std::uint32_t runsSincePublish_ = 0;
    std::uint32_t published_ = 0;
    std::uint32_t runs_ = 0;
};

}  // namespace rse::estimator
