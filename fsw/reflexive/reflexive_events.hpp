// Event ids raised by fsw/reflexive (range 600-699). Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::reflexive::events {

// 601, 602 and 606: the drive interlock's (fsw/io/io_events.hpp: it runs in the CAN I/O task).
constexpr core::EventId kManualDriveStarted = 603;  // DRIVE accepted: speeds, duration, whether limited
constexpr core::EventId kManualDriveEnded = 604;    // duration over, mode left, or e-stop
constexpr core::EventId kManualDriveMalformed = 605;  // a bus message that does not decode (throttled)

// The trajectory follower (trajectory_task.hpp), 610-629.
constexpr core::EventId kTrajectoryAccepted = 610;   // a trajectory to follow: id, leg, points, length, speed
constexpr core::EventId kStopAccepted = 611;         // a stop trajectory (count 0): decelerating from v, w
constexpr core::EventId kTrajectoryRefused = 612;    // refused whole (why); the previous one stays in force (throttled)
constexpr core::EventId kTrajectoryReached = 613;    // within the arrival tolerance of the last point
constexpr core::EventId kFollowerGaveUp = 614;       // cannot follow (reason, figures): wheels to zero at once
constexpr core::EventId kFollowerStopped = 615;      // a stop ended: body speed and turn rate at zero, idle
constexpr core::EventId kFollowerInputMalformed = 616;  // pose, mode or drive status that does not decode or is not usable, a wheel reading not finite (throttled)
constexpr core::EventId kFollowerHalted = 617;       // not following, but still moving, when the drives were held or AUTONOMOUS left: zero at once
constexpr core::EventId kContactSeen = 618;          // a contact (wheels pushing, current, where): wheels to zero at once, backing off
constexpr core::EventId kBackedOff = 619;            // the back-off after a contact ended (how far, why): cannot follow (contact)

}  // namespace rse::reflexive::events
