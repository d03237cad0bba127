// Event ids raised by hal/canopen and hal/devices (range 400-499). Documented in docs/icd.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kNodeBootUp = 401;         // a node announced boot-up (first start or restart)
constexpr core::EventId kNodeLost = 402;           // heartbeat timeout: node lost
constexpr core::EventId kNodeRecovered = 403;      // heartbeat back after a loss
constexpr core::EventId kNodeStateChanged = 404;   // NMT state in the heartbeat changed
constexpr core::EventId kBadHeartbeat = 405;       // heartbeat with wrong DLC or unknown state byte
constexpr core::EventId kEmcyReceived = 406;       // EMCY with its error code and register
constexpr core::EventId kNodeNeverBooted = 407;    // no boot-up or heartbeat within the node's boot timeout: lost
constexpr core::EventId kSdoAborted = 410;         // SDO transfer aborted (by the server or by us)
constexpr core::EventId kSdoTimeout = 411;         // SDO server did not answer in time
constexpr core::EventId kSdoProtocolError = 412;   // malformed or unexpected SDO response
constexpr core::EventId kUnknownCobId = 420;       // frame with a COB-ID nobody owns
constexpr core::EventId kBadPdo = 421;             // PDO with the wrong DLC
constexpr core::EventId kDriveConfigured = 430;    // drive passed every start-up check
constexpr core::EventId kDriveConfigFailed = 431;  // a configuration step failed after its retries
constexpr core::EventId kDriveEnabled = 432;       // CiA 402 operation enabled
constexpr core::EventId kDriveFault = 433;         // drive entered fault (EMCY code or statusword)
constexpr core::EventId kDriveFailed = 434;        // fault not cleared after its resets: drive out of service
constexpr core::EventId kDriveFaultCleared = 435;  // fault reset succeeded
constexpr core::EventId kDriveLost = 436;          // drive's heartbeat lost
constexpr core::EventId kDriveResetRequested = 437; // a fresh round of fault resets asked for from outside (fault protection)

}  // namespace rse::hal::events
