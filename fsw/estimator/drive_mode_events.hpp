// Event ids raised by the drive mode estimator (fsw/estimator/drive_mode_task.hpp),
// range 760-779. Texts start with "drive_modes: ".
#pragma once

#include "fsw/core/event_log.hpp"
#include "fsw/msg/health_msgs.hpp"

namespace rse::estimator::events {

// A wheel's declared mode changed: "drive_modes: FL nominal -> degraded (p=0.97,
// power x1.48)". One id per declared mode (760 + DriveMode), so the ground can filter
// on it. Edges, not rate limited: the declare threshold keeps them rare.
constexpr core::EventId kDriveModeDeclaredNominal = 760;   // INFO: back to nominal
constexpr core::EventId kDriveModeDeclaredDegraded = 761;  // WARN
constexpr core::EventId kDriveModeDeclaredFailed = 762;    // ERROR
constexpr core::EventId kDriveModeDeclaredUnknown = 763;   // ERROR: evidence fits no modelled mode

constexpr core::EventId kDriveModeMalformedInput = 770;    // ERROR: drive status that does not decode, not finite or bad health (throttled)
constexpr core::EventId kDriveModeNoDriveStatus = 771;     // WARN: an update window without any drive status (throttled)
constexpr core::EventId kDriveModeInitFailed = 772;        // ERROR: pipe or subscription refused at start-up

constexpr core::EventId declaredModeEventId(msg::DriveMode mode) {
    return static_cast<core::EventId>(kDriveModeDeclaredNominal + static_cast<core::EventId>(mode));
}

}  // namespace rse::estimator::events
