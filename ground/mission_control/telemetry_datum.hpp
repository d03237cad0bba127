// A datum: one decoded telemetry packet as the mission control display reads
// it (docs/mission_control.md): a flat JSON object
//   {"utc": ms since 1970 (ground receive time), "met": rover time s,
//    "<field>": value, "<array field>.<i>": value, ...}
// Integer fields are exact JSON integers (u64 and i64 too), floats JSON
// numbers (null when not finite: JSON has no NaN; an f32 as its shortest
// decimal, 0.1 rather than 0.10000000149011612), a chr field its text up to
// the first NUL (bytes that are not UTF-8 replaced by U+FFFD).
//
// The packet is decoded by ground/telemetry_decoder.hpp, by the flight
// dictionary's descriptors: nothing here knows a packet's layout.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include <nlohmann/json.hpp>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground::mission_control {

// JSON with its keys in insertion order: a datum lists its fields in the
// dictionary's order, as the display dictionary does.
using Json = nlohmann::ordered_json;

// The two keys every datum has besides its fields.
constexpr const char* kUtcKey = "utc";
constexpr const char* kMetKey = "met";

// The datum key of element `element` of a field: its name for a field of count
// 1 (and for chr, one text), "name.element" for an array field.
std::string datumKey(const cmdtlm::FieldDesc& field, std::size_t element);
// How many datum keys a field has: 1 for a scalar or a chr text, count otherwise.
std::size_t datumKeyCount(const cmdtlm::FieldDesc& field);

// The datum of a decoded packet (packet.ok must be true).
Json datumFromPacket(const DecodedPacket& packet, std::int64_t utcMs);

// The double whose shortest text is the float's shortest text (0.1f -> 0.1):
// the value a person reads for an f32, printed short in JSON.
double shortestFloat(float value);

// JSON text for the wire and the archive: compact, invalid UTF-8 replaced.
std::string jsonText(const Json& value);

}  // namespace rse::ground::mission_control
