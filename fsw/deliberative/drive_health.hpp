// The deliberative layer's view of the drives (docs/deliberative.md, "A failed
// drive" and "Mobility"), from two inputs: the drive mode estimator's
// DriveModesMsg (each drive's power factor and declared mode) and the
// reflexive layer's DriveStatusMsg (each drive's health and the interlock).
//
// It answers what the layer decides with:
// - which drives a plan takes as failed: declared failed, or unknown (nothing
//   says an unknown drive works); the plans' motion noise waits until a
//   declaration has lasted PLANNER.failed_drive_confirm_s without a break (a
//   resettable drive fault reads as failed for an update or two after its
//   reset: the estimator's window held the fault report);
// - the drives' mean power factor the legs' bounds are made at (a failed drive
//   at HABITUAL.failed_drive_power_factor);
// - whether mobility is lost. Only a latched interlock stops every wheel. A
//   drive declared failed while its wheels are free (a locked wheel dragged,
//   or a fault fault protection has already reset) is planned with its power
//   factor: the legs' bounds grow, and a leg that cannot meet them fails up as
//   any other. An interlock latched only on drives the estimator declares
//   failed (fault protection gave them up) is the layer's to decide: it plans
//   with them failed. A drive that trips it and is not declared failed (or
//   only unknown: nothing says its wheel has stopped), or an interlock with no
//   failed drive at all, is mobility lost.
//
// Pure: no bus, no events; the table figures come as arguments.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"

namespace rse::deliberative {

class DriveHealthView {
public:
    void takeDriveStatus(const msg::DriveStatusMsg& drives);
    // now: the task's run time (when the declarations were seen).
    void takeDriveModes(const msg::DriveModesMsg& modes, core::TimeNs now);

    bool interlockTripped() const { return interlockTripped_; }
    // Wheels the drive mode estimator declares failed (and unknown, withUnknown): bit per wheel.
    std::uint8_t failedDrives(bool withUnknown) const;
    // Drives declared failed or unknown for confirmS (PLANNER.failed_drive_confirm_s) or more.
    std::uint8_t confirmedFailedDrives(core::TimeNs now, double confirmS) const;
    bool mobilityLost() const;
    // The drives' mean power factor, a failed drive at failedDriveFactor
    // (HABITUAL.failed_drive_power_factor); 1 before any DriveModesMsg.
    double meanPowerFactor(double failedDriveFactor) const;

private:
    msg::DriveModesMsg modes_{};
    bool modesSeen_ = false;
    bool interlockTripped_ = false;
    msg::DriveHealth health_[msg::kWheelCount] = {};      // DriveStatusMsg last seen
    core::TimeNs failedSinceNs_[msg::kWheelCount] = {};  // declared failed or unknown since (0: not)
};

// "FL ML": the names of the wheels in mask, space separated, cut to size.
void wheelNames(std::uint8_t mask, char* out, std::size_t size);

}  // namespace rse::deliberative
