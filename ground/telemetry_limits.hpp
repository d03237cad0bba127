// The display limits of telemetry fields: the RSE_LIMIT lines of
// fsw/cmdtlm/dictionary.def (format and rules in its header comment), expanded
// for the ground alone. The dictionary export (docs/dictionary.md, .json) and
// the mission control display colour a value by them; the flight never reads
// them (its faults use the tables).
#pragma once

#include <cstddef>
#include <string>

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::ground {

struct TelemetryLimit {
    const char* packet;  // "POWER"
    const char* field;   // "battery_voltage"
    // NaN: no bound on that side (RSE_NO_LIMIT in the .def).
    double warnLow;
    double warnHigh;
    double alarmLow;
    double alarmHigh;
    const char* why;  // where the bounds come from
};

// Every RSE_LIMIT, in .def order.
const TelemetryLimit* telemetryLimits(std::size_t* count);
// The limits of one field; nullptr when it has none.
const TelemetryLimit* findTelemetryLimit(const char* packet, const char* field);

// False for NaN: the side has no bound.
bool hasBound(double bound);

// The level of a value against a field's limits, as the display colours it.
// Strict comparisons: a value equal to a bound is inside it.
enum class LimitLevel { kNominal, kWarn, kAlarm };
LimitLevel limitLevel(const TelemetryLimit& limit, double value);

// Why a limit breaks the .def's rules ("" when it keeps them): it names a
// packet and a numeric field of the dictionary; at least one bound; every bound
// given finite; warn inside alarm on each side; every low bound below every
// high bound. The unit test runs it on every RSE_LIMIT (and on broken ones).
std::string checkTelemetryLimit(const TelemetryLimit& limit);

}  // namespace rse::ground
