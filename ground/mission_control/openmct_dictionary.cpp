#include "ground/mission_control/openmct_dictionary.hpp"

#include <cstddef>
#include <string>

#include "ground/telemetry_limits.hpp"

namespace rse::ground::mission_control {
namespace {

Json limitsJson(const FieldLimits& limits) {
    Json out = Json::object();
    if (limits.warnLow) {
        out["warn_low"] = *limits.warnLow;
    }
    if (limits.warnHigh) {
        out["warn_high"] = *limits.warnHigh;
    }
    if (limits.alarmLow) {
        out["alarm_low"] = *limits.alarmLow;
    }
    if (limits.alarmHigh) {
        out["alarm_high"] = *limits.alarmHigh;
    }
    return out;
}

}  // namespace

std::optional<FieldLimits> dictionaryLimits(const cmdtlm::TelemetryDesc& packet, const cmdtlm::FieldDesc& field) {
    const TelemetryLimit* limit = findTelemetryLimit(packet.name, field.name);
    if (limit == nullptr) {
        return std::nullopt;
    }
    const auto bound = [](double b) { return hasBound(b) ? std::optional<double>(b) : std::nullopt; };
    return FieldLimits{bound(limit->warnLow), bound(limit->warnHigh), bound(limit->alarmLow), bound(limit->alarmHigh)};
}

Json displayDictionary(const LimitsLookup& limits) {
    Json packets = Json::array();
    std::size_t count = 0;
    const cmdtlm::TelemetryDesc* descs = cmdtlm::telemetryDescs(&count);
    for (std::size_t p = 0; p < count; ++p) {
        const cmdtlm::TelemetryDesc& packet = descs[p];
        Json fields = Json::array();
        for (std::size_t f = 0; f < packet.fieldCount; ++f) {
            const cmdtlm::FieldDesc& field = packet.fields[f];
            const std::optional<FieldLimits> fieldLimits = limits ? limits(packet, field) : std::nullopt;
            for (std::size_t e = 0; e < datumKeyCount(field); ++e) {
                const std::string key = datumKey(field, e);
                Json entry = {{"key", key},
                              {"name", key},
                              {"type", cmdtlm::toString(field.type)},
                              {"units", field.units},
                              {"description", field.description}};
                if (fieldLimits) {
                    entry["limits"] = limitsJson(*fieldLimits);
                }
                fields.push_back(std::move(entry));
            }
        }
        packets.push_back({{"name", packet.name},
                           {"apid", packet.apid},
                           {"description", packet.description},
                           {"fields", std::move(fields)}});
    }
    return {{"name", "RSE rover"}, {"packets", std::move(packets)}};
}

}  // namespace rse::ground::mission_control
