// Event ids raised by fsw/app (range 200-299). Documented in docs/architecture.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::app::events {

constexpr core::EventId kAppInitFailed = 201;   // a start-up step failed; rse-fsw exits
constexpr core::EventId kAppStarted = 202;
constexpr core::EventId kAppShutdown = 203;     // stop requested (signal or duration reached)
constexpr core::EventId kWheelCommandRejected = 204;  // malformed, non-finite or out-of-range wheel command

}  // namespace rse::app::events
