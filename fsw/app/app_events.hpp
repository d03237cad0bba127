// Event ids raised by fsw/app (range 200-299). Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::app::events {

constexpr core::EventId kAppInitFailed = 201;   // a start-up step failed; rse-fsw exits
constexpr core::EventId kAppStarted = 202;
constexpr core::EventId kAppShutdown = 203;     // stop requested (signal or duration reached)
constexpr core::EventId kWheelCommandRejected = 204;  // malformed, non-finite or out-of-range wheel command
constexpr core::EventId kModeChanged = 205;     // SET_MODE: the mode before and after
constexpr core::EventId kEstopSet = 206;        // software e-stop: every drive commanded to zero and held
constexpr core::EventId kEstopCleared = 207;
constexpr core::EventId kGoalsChanged = 208;    // GOTO, ADD_TARGET, CLEAR_GOALS, SET_RISK_BOUND
constexpr core::EventId kWheelCommandHeld = 209; // wheel commands ignored while the e-stop holds (throttled)
constexpr core::EventId kGroundLinkOpened = 210; // start-up: which ground links carry commands and telemetry
constexpr core::EventId kBusMessageMalformed = 211; // a bus message that does not decode as its id's type, or an
                                                    // InstrumentCommandMsg naming no instrument (throttled)
constexpr core::EventId kWheelsStoppedOnModeChange = 212; // the rover mode changed while a wheel was commanded: all to zero
constexpr core::EventId kEstopWheelsStopped = 213; // e-stop: every drive reports stopped, and how long it took
constexpr core::EventId kEstopStopOverrun = 214;   // e-stop: a wheel still turns after FAULT_RESPONSE.estop_stop_time_ms
constexpr core::EventId kSafedOnRequest = 215;     // an onboard layer called home: mode -> SAFE (who, why)
constexpr core::EventId kDriveRecoveryRefused = 216; // DriveRecoveryMsg malformed, unknown action, wheel out of range or nothing to reset (throttled)
constexpr core::EventId kDriveRecoveryTaken = 217;   // DriveRecoveryMsg acted on: fault reset, NMT reset node or interlock reset
constexpr core::EventId kHoldEstopChanged = 218;     // fault protection's MissionHoldMsg e-stop set or released
constexpr core::EventId kNodeMapRefused = 219;       // start-up: a node id of the CAN node map could not be used; rse-fsw exits
constexpr core::EventId kTaskRestarted = 220;      // fault protection asked: a stalled rate-group row runs again
constexpr core::EventId kTaskRestartRefused = 221; // a task restart naming no row of the table (row)
constexpr core::EventId kWatchdogWithheld = 222;   // the watchdog is no longer fed: a task stalled or health silent (CRIT)
constexpr core::EventId kWatchdogFeeding = 223;    // the watchdog is fed again
constexpr core::EventId kTaskSetByGround = 224;    // EXEC_SET_TASK: a rate-group row disabled (WARN) or enabled (INFO) by ground
constexpr core::EventId kTaskSetRefused = 225;     // EXEC_SET_TASK refused: no such row, or a row whose loss could not be undone (why)
constexpr core::EventId kTimeScaled = 226;         // start-up (rse-fsw --time-scale N > 1, lab only): the timeline runs N times slower than real time

}  // namespace rse::app::events
