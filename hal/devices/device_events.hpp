// Event ids raised by the RSE device clients in hal/devices (range 450-469).
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kDeviceBadFrame = 450;  // device frame with the wrong DLC or RTR
constexpr core::EventId kDeviceBadValue = 451;  // device frame with a field out of its range

// Science instruments (hal/devices/instrument.hpp, docs/icd.md §1.7).
constexpr core::EventId kInstrumentBadFrame = 452;       // report with the wrong DLC or RTR (throttled)
constexpr core::EventId kInstrumentBadValue = 453;       // report with a field out of range or its invariants broken (throttled)
constexpr core::EventId kInstrumentOnline = 454;         // a good report after start-up or after being offline
constexpr core::EventId kInstrumentOffline = 455;        // no good report for kInstrumentStatusTimeout, or never one since start
constexpr core::EventId kInstrumentAccepted = 456;       // a report names a new command: the instrument took it
constexpr core::EventId kInstrumentDone = 457;           // the command finished
constexpr core::EventId kInstrumentFailed = 458;         // the command failed (result) or the instrument reports a fault
constexpr core::EventId kInstrumentRefused = 459;        // the instrument refused a command (why; throttled)
constexpr core::EventId kInstrumentNotSent = 460;        // a command not sent: invalid, instrument offline, CAN refused (throttled)
constexpr core::EventId kInstrumentCancelled = 461;      // the command was cancelled
constexpr core::EventId kInstrumentFaultCleared = 462;   // the instrument's fault code went back to 0
constexpr core::EventId kInstrumentEventsDropped = 463;  // more state changes in a second than kInstrumentEventsPerSecond: the rest counted, not evented

}  // namespace rse::hal::events
