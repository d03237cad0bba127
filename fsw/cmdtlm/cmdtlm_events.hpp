// Event ids raised by fsw/cmdtlm (range 500-559, and the ids kept from fsw/app
// below). Documented in docs/architecture.md
// and docs/icd.md ("Ground link").
#pragma once

#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/core/event_log.hpp"

namespace rse::cmdtlm::events {

// The command and telemetry service's parts that came from fsw/app (the mode
// owner, the executive's commands, the telemetry and console tasks, the
// onboard-request pipe) keep their ids of fsw/app's range, and their text
// starts "app:" as before, so ground tools and logs read them unchanged.
constexpr core::EventId kModeChanged = 205;         // SET_MODE or a call home: the mode before and after
constexpr core::EventId kEstopSet = 206;            // software e-stop: every drive commanded to zero and held
constexpr core::EventId kEstopCleared = 207;
// A bus message that does not decode as its id's type (the telemetry, console
// and onboard-request pipes; core::InputPipe's text). fsw/io raises the same
// id for its own pipes.
constexpr core::EventId kBusMessageMalformed = 211;
constexpr core::EventId kSafedOnRequest = 215;      // an onboard layer called home: mode -> SAFE (who, why)
constexpr core::EventId kTaskRestarted = 220;       // fault protection asked: a stalled rate-group row runs again
constexpr core::EventId kTaskRestartRefused = 221;  // a task restart naming no row of the table (row)
constexpr core::EventId kTaskSetByGround = 224;     // EXEC_SET_TASK: a row disabled (WARN) or enabled (INFO) by ground
constexpr core::EventId kTaskSetRefused = 225;      // EXEC_SET_TASK refused: no such row, or a row whose loss could not be undone

constexpr core::EventId kNoop = 500;                 // NOOP executed (proves the link)
constexpr core::EventId kCountersReset = 501;        // RESET_COUNTERS executed
constexpr core::EventId kCommandExecuted = 502;      // any other command accepted and executed (debug)
constexpr core::EventId kRejectEventsSuppressed = 503;  // more than kRejectEventsPerSecond rejections in a second
constexpr core::EventId kLabKeyInUse = 504;          // start-up: the public lab key is loaded (warning)
constexpr core::EventId kAuthDisabled = 505;         // start-up: the lab setting accepts unauthenticated commands
constexpr core::EventId kCmdInitFailed = 506;        // a command service start-up step failed
constexpr core::EventId kTelemetryDropped = 507;     // a link refused a telemetry packet (throttled 1,2,4,8..)
constexpr core::EventId kTelemetryTooLarge = 508;    // a telemetry packet did not fit (a dictionary bug)
constexpr core::EventId kAppRegistrationRefused = 509;  // start-up: an APID owned twice, a table full (command router, telemetry task)
constexpr core::EventId kCommandWithoutOwner = 510;  // an accepted command whose APID no application owns (execution_failed)
constexpr core::EventId kEventDataWithheld = 511;    // an event's EVENT_DATA withheld to keep the frame's EVENTs' place (throttled 1,2,4,8..)
// Start-up key loading (fsw/cmdtlm/key_loader.hpp).
constexpr core::EventId kKeyFileRefused = 515;       // the key file was refused (why in the text); rse-fsw exits
constexpr core::EventId kWeakKeyAccepted = 516;      // a weak key loaded because --allow-weak-key said so (warning)
constexpr core::EventId kKeyFileOpenAccepted = 517;  // a key file others may read loaded because --allow-readable-key said so (warning)
// The persisted anti-replay state (fsw/cmdtlm/anti_replay_state.hpp), 540-546.
constexpr core::EventId kAuthStoreLoaded = 540;      // start-up: store read (or created), keys and floors (INFO)
constexpr core::EventId kAuthStoreUnusable = 541;    // start-up: store missing, corrupt or unreadable: keys refused until AUTH_RESYNC (CRIT)
constexpr core::EventId kAuthStoreVolatile = 542;    // start-up: no store attached, the window lives in RAM only (WARN)
constexpr core::EventId kAuthKeyUnsynced = 543;      // start-up: a loaded key without a stored reservation: refused until AUTH_RESYNC (ERROR)
constexpr core::EventId kAuthResynced = 544;         // AUTH_RESYNC accepted: the key's floor moved (WARN)
constexpr core::EventId kAuthStoreWriteFailed = 545; // a reservation write failed (ERROR, 1st, 2nd, 4th ... time)
constexpr core::EventId kAuthNoChallenge = 546;      // start-up: no AUTH_RESYNC nonce (no random source) (WARN)
// A second of flood on the ground links (at most one a second): rejection acks
// suppressed, ingest stopped at its per-frame limit, or packets dropped by the OS.
constexpr core::EventId kIngestFlood = 518;
// One event per reject reason: kRejectBase + CommandReject value (521 bad length ... 537 sequence store failed).
constexpr core::EventId kRejectBase = 520;
constexpr core::EventId rejectEvent(CommandReject reason) {
    return static_cast<core::EventId>(kRejectBase + static_cast<unsigned>(reason));
}

}  // namespace rse::cmdtlm::events
