// Manual driving (the DRIVE command, MANUAL mode only): body speed v and turn
// rate w for a duration, turned into skid-steer wheel speeds
//   left  = (v - w * track / 2) / r,   right = (v + w * track / 2) / r
// with the rover geometry table's wheel radius r and track width. A request
// beyond the table's limits is scaled down whole (same curvature), its duration
// capped. The drive ends with zero wheel speeds after the duration, on leaving
// MANUAL mode, or on a software e-stop (which CAN I/O also enforces at once).
#pragma once

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::reflexive {

// A DRIVE request and the mode changes around it.
constexpr std::uint16_t kManualDrivePipeDepth = 4;

struct WheelSpeeds {
    double radS[msg::kWheelCount];
    bool limited;  // scaled down to the table's limits
};
// The kinematics alone, for tests and the habitual layer.
WheelSpeeds skidSteerWheelSpeeds(double speedMS, double turnRateRadS, const tables::RoverGeometryTable& g);

class ManualDrive final : public core::Task {
public:
    ManualDrive(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                const tables::TableService& tables);

    // Pipe "manual_drive" (kManualDrivePipeDepth): ManualDriveMsg and ModeMsg. A
    // message that does not decode is counted and evented (605) by the pipe.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    bool driving() const { return driving_; }
    std::uint32_t drivesStarted() const { return started_; }
    std::uint32_t drivesEnded() const { return ended_; }
    std::uint32_t malformed() const { return input_.malformed(); }

private:
    void takeRequest(const msg::ManualDriveMsg& request);
    void takeMode(const msg::ModeMsg& mode);
    void start(const msg::ManualDriveMsg& request);
    void stop(const char* why);

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::InputPipe input_;
    bool manualMode_ = false;
    bool driving_ = false;
    core::TimeNs endTime_ = 0;
    std::uint32_t started_ = 0;
    std::uint32_t ended_ = 0;
};

}  // namespace rse::reflexive
