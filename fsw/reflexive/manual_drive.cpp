#include "fsw/reflexive/manual_drive.hpp"

#include <cmath>

#include "fsw/reflexive/reflexive_events.hpp"

namespace rse::reflexive {

WheelSpeeds skidSteerWheelSpeeds(double speedMS, double turnRateRadS, const tables::RoverGeometryTable& g) {
    WheelSpeeds out{};
    const double radius = static_cast<double>(g.wheel_radius_m);
    const double halfTrack = 0.5 * static_cast<double>(g.track_width_m);
    double v = speedMS;
    double w = turnRateRadS;
    // Body limits first, then the wheels': each scales v and w together so the
    // path's curvature is what the operator asked for.
    double scale = 1.0;
    const double maxV = static_cast<double>(g.max_body_speed_m_s);
    const double maxW = static_cast<double>(g.max_body_rate_rad_s);
    if (std::fabs(v) > maxV) {
        scale = std::fmin(scale, maxV / std::fabs(v));
    }
    if (std::fabs(w) > maxW) {
        scale = std::fmin(scale, maxW / std::fabs(w));
    }
    v *= scale;
    w *= scale;
    double left = (v - w * halfTrack) / radius;
    double right = (v + w * halfTrack) / radius;
    const double maxWheel = static_cast<double>(g.max_wheel_speed_rad_s);
    const double largest = std::fmax(std::fabs(left), std::fabs(right));
    if (largest > maxWheel) {
        left *= maxWheel / largest;
        right *= maxWheel / largest;
        scale = 0.0;  // marks limited
    }
    out.limited = scale < 1.0;
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        out.radS[i] = i < msg::kWheelCount / 2 ? left : right;  // 0-2 left side, 3-5 right (icd §1.1)
    }
    return out;
}

ManualDrive::ManualDrive(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                         const tables::TableService& tables)
    : clock_(clock),
      bus_(bus),
      events_(events),
      tables_(tables),
      input_(bus, events,
             core::InputPipeConfig{"manual_drive", kManualDrivePipeDepth, events::kManualDriveMalformed, "manual"}) {}

core::Status ManualDrive::init() {
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&ManualDrive::takeRequest>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&ManualDrive::takeMode>(this);
    }
    return status;
}

void ManualDrive::run(const core::FrameContext&) {
    input_.drain();
    if (driving_ && clock_.now() >= endTime_) {
        stop("duration over");
    }
}

void ManualDrive::takeMode(const msg::ModeMsg& mode) {
    manualMode_ = mode.mode == msg::mode::kManual && mode.estop == 0;
    if (driving_ && !manualMode_) {
        stop(mode.estop != 0 ? "software e-stop" : "left MANUAL mode");
    }
}

void ManualDrive::takeRequest(const msg::ManualDriveMsg& request) {
    if (manualMode_) {
        start(request);
        return;
    }
    // The handler checked the mode; this only happens when the mode or the
    // e-stop changed in between. Said, not silently dropped.
    events_.report(events::kManualDriveEnded, core::Severity::kWarning,
                   "manual: drive request ignored (not in MANUAL mode, or e-stop set)");
}

void ManualDrive::start(const msg::ManualDriveMsg& request) {
    const tables::RoverGeometryTable& geometry = tables_.roverGeometry();
    const WheelSpeeds speeds = skidSteerWheelSpeeds(request.speedMS, request.turnRateRadS, geometry);
    const double duration = std::fmin(request.durationS, static_cast<double>(geometry.max_manual_drive_s));
    msg::WheelCommandMsg command{};
    command.timeNs = clock_.now();
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        command.velocityRadS[i] = speeds.radS[i];
    }
    (void)bus_.publish(command);
    driving_ = true;
    endTime_ = command.timeNs + static_cast<core::TimeNs>(duration * static_cast<double>(core::kNsPerSec));
    ++started_;
    events_.report(events::kManualDriveStarted, core::Severity::kInfo,
                   "manual: drive v=%.2f m/s w=%.2f rad/s for %.1f s: wheels L %.2f R %.2f rad/s%s",
                   request.speedMS, request.turnRateRadS, duration, speeds.radS[0], speeds.radS[3],
                   speeds.limited ? " (limited by the geometry table)" : "");
}

void ManualDrive::stop(const char* why) {
    msg::WheelCommandMsg command{};
    command.timeNs = clock_.now();
    (void)bus_.publish(command);
    driving_ = false;
    ++ended_;
    events_.report(events::kManualDriveEnded, core::Severity::kInfo, "manual: drive ended (%s)", why);
}

}  // namespace rse::reflexive
