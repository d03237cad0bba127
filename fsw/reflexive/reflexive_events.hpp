// Event ids raised by fsw/reflexive (range 600-699). Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::reflexive::events {

constexpr core::EventId kInterlockTripped = 601;  // a drive is unhealthy: all wheels held at zero
constexpr core::EventId kInterlockReset = 602;
constexpr core::EventId kManualDriveStarted = 603;  // DRIVE accepted: speeds, duration, whether limited
constexpr core::EventId kManualDriveEnded = 604;    // duration over, mode left, or e-stop
constexpr core::EventId kManualDriveMalformed = 605;  // a bus message that does not decode (throttled)

}  // namespace rse::reflexive::events
