// Event ids raised by fsw/app, the composition root (range 200-299).
// Documented in docs/architecture.md. The rest of the range went with the code
// that raises it and keeps its numbers: 204, 209, 211-214, 216-219, 222-223 to
// fsw/io (io_events.hpp); 205-207, 211, 215, 220-221, 224-225 to fsw/cmdtlm
// (cmdtlm_events.hpp); 208 to fsw/plan_executive (the goal commands;
// plan_executive_events.hpp, kGoalsCommanded).
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::app::events {

constexpr core::EventId kAppInitFailed = 201;   // a start-up step failed; rse-fsw exits
constexpr core::EventId kAppStarted = 202;
constexpr core::EventId kAppShutdown = 203;     // stop requested (signal or duration reached)
constexpr core::EventId kGroundLinkOpened = 210; // start-up: which ground links carry commands and telemetry
constexpr core::EventId kTimeScaled = 226;         // start-up (rse-fsw --time-scale N > 1, lab only): the timeline runs N times slower than real time

}  // namespace rse::app::events
