// Event ids raised by fsw/cmdtlm (range 500-559). Documented in docs/architecture.md
// and docs/icd.md ("Ground link").
#pragma once

#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/core/event_log.hpp"

namespace rse::cmdtlm::events {

constexpr core::EventId kNoop = 500;                 // NOOP executed (proves the link)
constexpr core::EventId kCountersReset = 501;        // RESET_COUNTERS executed
constexpr core::EventId kCommandExecuted = 502;      // any other command accepted and executed (debug)
constexpr core::EventId kRejectEventsSuppressed = 503;  // more than kRejectEventsPerSecond rejections in a second
constexpr core::EventId kLabKeyInUse = 504;          // start-up: the public lab key is loaded (warning)
constexpr core::EventId kAuthDisabled = 505;         // start-up: the lab setting accepts unauthenticated commands
constexpr core::EventId kCmdInitFailed = 506;        // a command service start-up step failed
constexpr core::EventId kTelemetryDropped = 507;     // a link refused a telemetry packet (throttled 1,2,4,8..)
constexpr core::EventId kTelemetryTooLarge = 508;    // a telemetry packet did not fit (a dictionary bug)
// A second of flood on the ground links (at most one a second): rejection acks
// suppressed, ingest stopped at its per-frame limit, or packets dropped by the OS.
constexpr core::EventId kIngestFlood = 515;
// One event per reject reason: kRejectBase + CommandReject value (521 bad length ... 534 execution failed).
constexpr core::EventId kRejectBase = 520;
constexpr core::EventId rejectEvent(CommandReject reason) {
    return static_cast<core::EventId>(kRejectBase + static_cast<unsigned>(reason));
}

}  // namespace rse::cmdtlm::events
