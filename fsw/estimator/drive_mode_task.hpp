// The drive mode estimator on the bus (every minor frame, after the CAN I/O task):
//   in:  DriveStatusMsg, every frame; each is one frame of the current window
//        (one that does not decode, or carries a non-finite value or a health that
//        is no DriveHealth, is ignored whole, counted and evented, throttled:
//        core::InputPipe, event 770)
//   out: DriveModesMsg every 10th run (100 ms): per wheel the mode probabilities,
//        the estimated power factor and the declared mode; an event on every
//        change of a declared mode (drive_mode_events.hpp).
// The model and its documented bounds: drive_mode_estimator.hpp. The table
// DRIVE_HEALTH_MODEL is read on every run, so an activation applies from the next
// frame. No heap; every loop is bounded by the pipe depth or the wheel count.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/drive_mode_estimator.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::estimator {

constexpr std::uint16_t kDriveModePipeDepth = 4;
constexpr std::uint32_t kDriveModeUpdateRuns = 10;  // runs per belief update (100 ms at 100 Hz)

class DriveModeTask final : public core::Task {
public:
    DriveModeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables);

    // Pipe "drive_modes" (depth 4) subscribed to DriveStatusMsg. A refusal is
    // evented (772) and returned; run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    // The latest published beliefs (before the first update: the start belief).
    const msg::DriveModesMsg& latest() const { return latest_; }
    // kUnknown for a wheel index >= kWheelCount.
    msg::DriveMode declared(std::size_t wheel) const;
    const DriveModeEstimator& estimator() const { return estimator_; }

    std::uint32_t statusesTaken() const { return taken_; }
    std::uint32_t malformed() const { return input_.malformed(); }
    std::uint32_t windowsWithoutStatus() const { return emptyWindows_; }
    std::uint32_t modeChanges() const { return modeChanges_; }
    std::uint32_t updates() const { return estimator_.updates(); }

private:
    // One frame of the window; kInvalidArgument (the pipe counts and events
    // it) for a non-finite value or a health that is no DriveHealth.
    core::Status takeStatus(const msg::DriveStatusMsg& status);
    void update(const core::FrameContext& frame, const DriveHealthModel& model);
    void fillLatest(core::TimeNs time);

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::InputPipe input_;
    bool initialised_ = false;
    DriveModeEstimator estimator_;
    msg::DriveModesMsg latest_{};
    std::uint32_t runs_ = 0;
    std::uint32_t taken_ = 0;
    std::uint32_t emptyWindows_ = 0;
    std::uint32_t modeChanges_ = 0;
};

}  // namespace rse::estimator
