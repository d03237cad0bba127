#include "ground/mission_control/telemetry_datum.hpp"

#include <cmath>
#include <cstdlib>

#include "ground/text_format.hpp"

namespace rse::ground::mission_control {
namespace {

using cmdtlm::FieldType;

bool isSigned(FieldType type) {
    return type == FieldType::i16 || type == FieldType::i32 || type == FieldType::i64;
}

bool isFloat(FieldType type) { return type == FieldType::f32 || type == FieldType::f64; }

// One element as JSON: integers from their wire bits (exact), floats from the
// decoded value.
Json elementValue(const DecodedField& field, std::size_t element) {
    const FieldType type = field.desc->type;
    if (isFloat(type)) {
        const double value = field.values[element];
        if (!std::isfinite(value)) {
            return Json(nullptr);
        }
        return type == FieldType::f32 ? Json(shortestFloat(static_cast<float>(value))) : Json(value);
    }
    const std::uint64_t raw = field.raw[element];
    if (isSigned(type)) {
        const std::size_t bits = 8 * cmdtlm::wireSize(type);
        std::uint64_t extended = raw;
        if (bits < 64 && (raw >> (bits - 1)) != 0) {
            extended |= ~0ULL << bits;
        }
        return Json(static_cast<std::int64_t>(extended));
    }
    return Json(raw);
}

}  // namespace

std::size_t datumKeyCount(const cmdtlm::FieldDesc& field) {
    return field.type == FieldType::chr || field.count <= 1 ? 1 : field.count;
}

std::string datumKey(const cmdtlm::FieldDesc& field, std::size_t element) {
    if (datumKeyCount(field) == 1) {
        return field.name;
    }
    return std::string(field.name) + "." + std::to_string(element);
}

Json datumFromPacket(const DecodedPacket& packet, std::int64_t utcMs) {
    Json datum = Json::object();
    datum[kUtcKey] = utcMs;
    datum[kMetKey] = packet.met;
    for (const DecodedField& field : packet.fields) {
        if (field.desc->type == FieldType::chr) {
            datum[field.desc->name] = field.text;
            continue;
        }
        const std::size_t keys = datumKeyCount(*field.desc);
        for (std::size_t i = 0; i < keys && i < field.raw.size(); ++i) {
            datum[datumKey(*field.desc, i)] = elementValue(field, i);
        }
    }
    return datum;
}

double shortestFloat(float value) { return std::strtod(formatFloat(value).c_str(), nullptr); }

std::string jsonText(const Json& value) {
    return value.dump(-1, ' ', false, Json::error_handler_t::replace);
}

}  // namespace rse::ground::mission_control
