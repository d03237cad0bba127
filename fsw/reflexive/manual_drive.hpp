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
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::reflexive {

struct WheelSpeeds {
    double radS[msg::kWheelCount];
    bool limited;  // scaled down to the table's limits
};
// The kinematics alone, for tests and the habitual layer.
WheelSpeeds skidSteerWheelSpeeds(double speedMS, double turnRateRadS, const tables::RoverGeometryTable& g);

class ManualDrive final : public core::Task {
public:
    ManualDrive(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                const tables::TableService& tables)
        : clock_(clock), bus_(bus), events_(events), tables_(tables) {}

    core::Status init();
    void run(const core::FrameContext& frame) override;

    bool driving() const { return driving_; }
    std::uint32_t drivesStarted() const { return started_; }
    std::uint32_t drivesEnded() const { return ended_; }
    std::uint32_t malformed() const { return malformed_; }

private:
    void start(const msg::ManualDriveMsg& request);
    void stop(const char* why);

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::PipeId pipe_ = 0;
    core::Message inbox_{};
    bool manualMode_ = false;
    bool driving_ = false;
    core::TimeNs endTime_ = 0;
    std::uint32_t started_ = 0;
    std::uint32_t ended_ = 0;
    std::uint32_t malformed_ = 0;
};

}  // namespace rse::reflexive
