// Event ids raised by fsw/io, the tasks that drive the rover's hardware through
// hal/ (CAN I/O, the watchdog). They keep the numbers they had in fsw/app's range
// (200-299) when these tasks moved here, so ground tools and logs read them as
// before; their text still starts "app:" for the same reason. Documented in
// docs/architecture.md ("Events").
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::io::events {

constexpr core::EventId kWheelCommandRejected = 204;  // non-finite or out-of-range wheel command, unusable hold
constexpr core::EventId kWheelCommandHeld = 209;      // wheel commands ignored while an e-stop holds (throttled)
// A bus message that does not decode as its id's type (the CAN I/O and watchdog
// pipes, core::InputPipe's text), or an InstrumentCommandMsg naming no
// instrument (throttled). fsw/cmdtlm raises the same id for its own pipes.
constexpr core::EventId kBusMessageMalformed = 211;
constexpr core::EventId kWheelsStoppedOnModeChange = 212;  // the rover mode changed while a wheel was commanded
constexpr core::EventId kEstopWheelsStopped = 213;  // e-stop: every drive reports stopped, and how long it took
constexpr core::EventId kEstopStopOverrun = 214;    // e-stop: a wheel still turns after FAULT_RESPONSE.estop_stop_time_ms
constexpr core::EventId kDriveRecoveryRefused = 216;  // unknown action, wheel out of range or nothing to reset (throttled)
constexpr core::EventId kDriveRecoveryTaken = 217;    // fault reset, NMT reset node or interlock reset
constexpr core::EventId kHoldEstopChanged = 218;      // fault protection's MissionHoldMsg e-stop set or released
constexpr core::EventId kNodeMapRefused = 219;        // start-up: a node id of the CAN node map could not be used
constexpr core::EventId kWatchdogWithheld = 222;      // the watchdog is no longer fed: a task stalled or health silent
constexpr core::EventId kWatchdogFeeding = 223;       // the watchdog is fed again

// The drive interlock (drive_interlock.hpp): the reflexive layer's numbers
// (600-699), kept when it moved here beside the task that applies it.
constexpr core::EventId kInterlockTripped = 601;       // a drive is unhealthy: all wheels held at zero
constexpr core::EventId kInterlockReset = 602;         // RESET_INTERLOCK: every drive healthy, the hold released
constexpr core::EventId kInterlockResetRefused = 606;  // RESET_INTERLOCK while a drive is still unhealthy: the hold stays

}  // namespace rse::io::events
