// Event ids raised by hal/can (range 300-349). Documented in docs/icd.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kCanStateChanged = 301;  // error-active/warning/passive/bus-off/down
constexpr core::EventId kCanRxOverrun = 302;     // frames lost before they were read
constexpr core::EventId kCanTxRefused = 303;     // send refused: queue full, link down, bus-off
constexpr core::EventId kCanTxInvalid = 304;     // send of a malformed frame refused
constexpr core::EventId kCanOpenFailed = 305;    // a SocketCAN interface could not be opened

}  // namespace rse::hal::events
