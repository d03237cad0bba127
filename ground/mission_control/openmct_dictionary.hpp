// The display dictionary that `rse-ground serve` answers GET /api/dictionary
// with (docs/mission_control.md): every telemetry packet of the flight
// dictionary (fsw/cmdtlm/dictionary.def) with every field, array fields
// expanded to one entry per element under its datum key ("current.0" ...):
//
//   {"name": "RSE rover", "packets": [{"name": "ROVER_STATE", "apid": 16, "description": "...",
//     "fields": [{"key": "x", "name": "x", "type": "f64", "units": "m", "description": "...",
//                 "limits": {"warn_low": .., "warn_high": .., "alarm_low": .., "alarm_high": ..}}, ...]}, ...]}
//
// Generated from the flight dictionary's descriptor tables at run time, so a
// packet or field added there is on the display without a change here.
#pragma once

#include <functional>
#include <optional>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/mission_control/telemetry_datum.hpp"

namespace rse::ground::mission_control {

// A field's display limits; each bound is optional (a field may have only
// high ones). "limits" lists the bounds given.
struct FieldLimits {
    std::optional<double> warnLow;
    std::optional<double> warnHigh;
    std::optional<double> alarmLow;
    std::optional<double> alarmHigh;
};

// The limits of a field of a packet (the same for every element of an array
// field), or none.
using LimitsLookup =
    std::function<std::optional<FieldLimits>(const cmdtlm::TelemetryDesc& packet, const cmdtlm::FieldDesc& field)>;

// The flight dictionary's limits: its RSE_LIMIT lines (fsw/cmdtlm/dictionary.def,
// read through ground/telemetry_limits.hpp), each side only where bounded.
std::optional<FieldLimits> dictionaryLimits(const cmdtlm::TelemetryDesc& packet, const cmdtlm::FieldDesc& field);

// The display dictionary, with limits from `limits`.
Json displayDictionary(const LimitsLookup& limits = dictionaryLimits);

}  // namespace rse::ground::mission_control
