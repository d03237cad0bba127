#include "ground/telemetry_limits.hpp"

#include <cmath>
#include <cstring>
#include <limits>

#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

constexpr double kNoLimit = std::numeric_limits<double>::quiet_NaN();

// A misspelt packet or field name in an RSE_LIMIT fails the build here: the
// generated struct must have the member (the unit test checks the rest).
#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text)
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_NO_LIMIT kNoLimit
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)          \
    static_assert(sizeof(cmdtlm::PACKET##_Tlm::field) > 0, "RSE_LIMIT " #PACKET "." #field \
                                                           ": no such telemetry field");
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why) \
    {#PACKET, #field, warn_low, warn_high, alarm_low, alarm_high, why},
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
constexpr TelemetryLimit kLimits[] = {
#include "fsw/cmdtlm/dictionary.def"
};
#undef RSE_CMD
#undef RSE_ARG
#undef RSE_BLOB
#undef RSE_CMD_END
#undef RSE_TLM
#undef RSE_FIELD
#undef RSE_TLM_END
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END
#undef RSE_NO_LIMIT

constexpr std::size_t kLimitCount = sizeof kLimits / sizeof kLimits[0];

const cmdtlm::FieldDesc* findField(const cmdtlm::TelemetryDesc& packet, const char* name) {
    for (std::size_t i = 0; i < packet.fieldCount; ++i) {
        if (std::strcmp(packet.fields[i].name, name) == 0) {
            return &packet.fields[i];
        }
    }
    return nullptr;
}

}  // namespace

const TelemetryLimit* telemetryLimits(std::size_t* count) {
    *count = kLimitCount;
    return kLimits;
}

const TelemetryLimit* findTelemetryLimit(const char* packet, const char* field) {
    if (packet == nullptr || field == nullptr) {
        return nullptr;
    }
    for (const TelemetryLimit& l : kLimits) {
        if (std::strcmp(l.packet, packet) == 0 && std::strcmp(l.field, field) == 0) {
            return &l;
        }
    }
    return nullptr;
}

bool hasBound(double bound) { return !std::isnan(bound); }

LimitLevel limitLevel(const TelemetryLimit& limit, double value) {
    if ((hasBound(limit.alarmLow) && value < limit.alarmLow) || (hasBound(limit.alarmHigh) && value > limit.alarmHigh)) {
        return LimitLevel::kAlarm;
    }
    if ((hasBound(limit.warnLow) && value < limit.warnLow) || (hasBound(limit.warnHigh) && value > limit.warnHigh)) {
        return LimitLevel::kWarn;
    }
    return LimitLevel::kNominal;
}

std::string checkTelemetryLimit(const TelemetryLimit& limit) {
    const std::string name = std::string(limit.packet != nullptr ? limit.packet : "?") + "." +
                             (limit.field != nullptr ? limit.field : "?");
    const cmdtlm::TelemetryDesc* packet = cmdtlm::findTelemetry(limit.packet);
    if (packet == nullptr) {
        return name + ": no telemetry packet " + (limit.packet != nullptr ? limit.packet : "(null)");
    }
    const cmdtlm::FieldDesc* field = limit.field != nullptr ? findField(*packet, limit.field) : nullptr;
    if (field == nullptr) {
        return name + ": packet " + packet->name + " has no field " + (limit.field != nullptr ? limit.field : "(null)");
    }
    if (field->type == cmdtlm::FieldType::chr) {
        return name + ": a text field has no limits";
    }
    struct Bound {
        const char* what;
        double value;
    };
    const Bound lows[] = {{"warn_low", limit.warnLow}, {"alarm_low", limit.alarmLow}};
    const Bound highs[] = {{"warn_high", limit.warnHigh}, {"alarm_high", limit.alarmHigh}};
    bool any = false;
    for (const Bound* side : {lows, highs}) {
        for (std::size_t i = 0; i < 2; ++i) {
            if (hasBound(side[i].value) && !std::isfinite(side[i].value)) {
                return name + ": " + side[i].what + " is not finite";
            }
            any = any || hasBound(side[i].value);
        }
    }
    if (!any) {
        return name + ": no bound at all";
    }
    if (hasBound(limit.warnLow) && hasBound(limit.alarmLow) && !(limit.alarmLow < limit.warnLow)) {
        return name + ": warn_low " + formatNumber(limit.warnLow) + " is not inside (above) alarm_low " +
               formatNumber(limit.alarmLow);
    }
    if (hasBound(limit.warnHigh) && hasBound(limit.alarmHigh) && !(limit.warnHigh < limit.alarmHigh)) {
        return name + ": warn_high " + formatNumber(limit.warnHigh) + " is not inside (below) alarm_high " +
               formatNumber(limit.alarmHigh);
    }
    for (const Bound& low : lows) {
        for (const Bound& high : highs) {
            if (hasBound(low.value) && hasBound(high.value) && !(low.value < high.value)) {
                return name + ": " + low.what + " " + formatNumber(low.value) + " is not below " + high.what + " " +
                       formatNumber(high.value);
            }
        }
    }
    return "";
}

}  // namespace rse::ground
