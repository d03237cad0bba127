// Event ids raised by hal/watchdog (390-399). Documented in docs/fault_protection.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kWatchdogOpened = 390;      // device open and armed: its timeout
constexpr core::EventId kWatchdogOpenFailed = 391;  // open or timeout setting failed (errno)
constexpr core::EventId kWatchdogFeedFailed = 392;  // a feed write failed (errno, throttled)
constexpr core::EventId kWatchdogDisarmed = 393;    // clean stop: magic close written, device closed

}  // namespace rse::hal::events
