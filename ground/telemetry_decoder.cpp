#include "ground/telemetry_decoder.hpp"

#include <cstdio>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/cmdtlm/task_command_refusal.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/telemetry_limits.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

using cmdtlm::FieldType;

std::string hex3(unsigned value) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "0x%03X", value);
    return buffer;
}

bool isSigned(FieldType type) {
    return type == FieldType::i16 || type == FieldType::i32 || type == FieldType::i64;
}

std::string renderElement(const DecodedField& f, std::size_t i) {
    const FieldType type = f.desc->type;
    if (type == FieldType::f32) {
        return formatFloat(static_cast<float>(f.values[i]));
    }
    if (type == FieldType::f64) {
        return formatNumber(f.values[i]);
    }
    if (isSigned(type)) {
        const std::size_t bits = 8 * cmdtlm::wireSize(type);
        std::uint64_t raw = f.raw[i];
        if (bits < 64 && (raw >> (bits - 1)) != 0) {
            raw |= ~0ULL << bits;  // sign-extend
        }
        return std::to_string(static_cast<long long>(raw));
    }
    return std::to_string(static_cast<unsigned long long>(f.raw[i]));
}

// Printable ASCII as is, the rest as \xNN.
std::string escapeText(const std::string& text) {
    std::string out;
    for (const char c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u >= 0x20 && u < 0x7F && c != '\\') {
            out += c;
        } else {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\x%02X", u);
            out += buffer;
        }
    }
    return out;
}

// An element outside the field's display limits (telemetry_limits.hpp) is
// marked: "23.5!ALARM", "2.6!WARN".
std::string renderLimited(const DecodedField& f, std::size_t i, const TelemetryLimit* limit) {
    std::string text = renderElement(f, i);
    if (limit != nullptr) {
        switch (limitLevel(*limit, f.values[i])) {
            case LimitLevel::kAlarm: text += "!ALARM"; break;
            case LimitLevel::kWarn: text += "!WARN"; break;
            case LimitLevel::kNominal: break;
        }
    }
    return text;
}

std::string renderField(const DecodedField& f, const char* packetName) {
    std::string out = std::string(f.desc->name) + "=";
    const std::size_t count = f.raw.size();
    if (f.desc->type == FieldType::chr) {
        return out + "\"" + escapeText(f.text) + "\"";
    }
    const TelemetryLimit* limit = findTelemetryLimit(packetName, f.desc->name);
    if (count == 1) {
        return out + renderLimited(f, 0, limit);
    }
    if (f.desc->type == FieldType::u8 && count > 16) {
        std::string hex;
        for (std::size_t i = 0; i < count; ++i) {
            char buffer[4];
            std::snprintf(buffer, sizeof buffer, "%02x", static_cast<unsigned>(f.raw[i]));
            hex += buffer;
        }
        return out + hex;
    }
    out += "[";
    for (std::size_t i = 0; i < count; ++i) {
        out += (i > 0 ? "," : "") + renderLimited(f, i, limit);
    }
    return out + "]";
}

// HAZARDS: the revision, then only the hazards in use (count of them), each as
// its detector id, centre and radius: " revision=4 count=2 hazards=[#7 (12.5,-1.25) r=0.5; #9 (3,4) r=0.25]".
std::string renderHazards(const DecodedPacket& p) {
    const DecodedField* x = p.field("x");
    const std::size_t slots = x != nullptr ? x->values.size() : 0;
    const auto count = static_cast<std::size_t>(p.value("count").value_or(0));
    std::string line = " revision=" + formatNumber(p.value("revision").value_or(0)) +
                       " count=" + std::to_string(count) + " hazards=[";
    for (std::size_t i = 0; i < count && i < slots; ++i) {
        line += (i > 0 ? "; #" : "#") + formatNumber(p.value("obstacle_id", i).value_or(0)) + " (" +
                formatFloat(static_cast<float>(p.value("x", i).value_or(0))) + "," +
                formatFloat(static_cast<float>(p.value("y", i).value_or(0))) +
                ") r=" + formatFloat(static_cast<float>(p.value("radius", i).value_or(0)));
    }
    return line + "]" + (count > slots ? " (count beyond the " + std::to_string(slots) + " entries)" : "");
}

std::string padName(const std::string& name) {
    return name.size() < 12 ? name + std::string(12 - name.size(), ' ') : name;
}

std::string rawSummary(const DecodedPacket& p) {
    const std::size_t shown = p.bytes.size() < 32 ? p.bytes.size() : 32;
    return hexBytes(p.bytes.data(), shown) + (shown < p.bytes.size() ? " ..." : "");
}

}  // namespace

const DecodedField* DecodedPacket::field(const std::string& fieldName) const {
    for (const DecodedField& f : fields) {
        if (fieldName == f.desc->name) {
            return &f;
        }
    }
    const std::string lower = toLower(fieldName);
    for (const DecodedField& f : fields) {
        if (lower == f.desc->name) {
            return &f;
        }
    }
    return nullptr;
}

std::optional<double> DecodedPacket::value(const std::string& fieldName, std::size_t index) const {
    const DecodedField* f = field(fieldName);
    if (f == nullptr || index >= f->values.size()) {
        return std::nullopt;
    }
    return f->values[index];
}

DecodedPacket decodeTelemetry(const std::uint8_t* data, std::size_t length) {
    DecodedPacket p;
    p.length = length;
    if (data != nullptr && length > 0) {
        p.bytes.assign(data, data + length);
    }
    if (data == nullptr || length < cmdtlm::kTelemetryHeaderSize) {
        p.error = "length " + std::to_string(length) + " is shorter than the " +
                  std::to_string(cmdtlm::kTelemetryHeaderSize) + "-byte telemetry header";
        return p;
    }
    const cmdtlm::PrimaryHeader h = cmdtlm::decodePrimaryHeader(data);
    p.apid = h.apid;
    p.sequenceCount = h.sequenceCount;
    core::BeReader time(data + cmdtlm::kPrimaryHeaderSize, cmdtlm::kTelemetrySecondaryHeaderSize);
    cmdtlm::MetTime met;
    met.seconds = time.u32();
    met.subseconds = time.u16();
    p.met = cmdtlm::metSeconds(met);
    if (h.version != 0 || h.type != cmdtlm::PacketType::kTelemetry || !h.secondaryHeader ||
        h.sequenceFlags != cmdtlm::kUnsegmented) {
        p.error = "bad primary header (version " + std::to_string(h.version) + ", type " +
                  (h.type == cmdtlm::PacketType::kCommand ? "command" : "telemetry") + ", secondary header " +
                  (h.secondaryHeader ? "yes" : "no") + ", sequence flags " + std::to_string(h.sequenceFlags) +
                  ")";
        return p;
    }
    if (static_cast<std::size_t>(h.dataLength) + 7 != length) {
        p.error = "length field says " + std::to_string(static_cast<std::size_t>(h.dataLength) + 7) +
                  " bytes, packet has " + std::to_string(length);
        return p;
    }
    p.desc = cmdtlm::findTelemetry(h.apid);
    if (p.desc == nullptr) {
        p.error = "unknown APID " + hex3(h.apid);
        return p;
    }
    const std::size_t payload = length - cmdtlm::kTelemetryHeaderSize;
    if (payload != p.desc->payloadSize) {
        p.error = std::string(p.desc->name) + " payload is " + std::to_string(payload) +
                  " bytes, the dictionary says " + std::to_string(p.desc->payloadSize);
        return p;
    }
    core::BeReader r(data + cmdtlm::kTelemetryHeaderSize, payload);
    p.fields.reserve(p.desc->fieldCount);
    for (std::size_t i = 0; i < p.desc->fieldCount; ++i) {
        DecodedField f;
        f.desc = &p.desc->fields[i];
        const std::size_t width = cmdtlm::wireSize(f.desc->type);
        for (std::size_t e = 0; e < f.desc->count; ++e) {
            const std::uint8_t* at = data + cmdtlm::kTelemetryHeaderSize + r.position();
            std::uint64_t raw = 0;
            for (std::size_t b = 0; b < width && r.remaining() >= width; ++b) {
                raw = (raw << 8) | at[b];
            }
            f.raw.push_back(raw);
            f.values.push_back(cmdtlm::readAsDouble(r, f.desc->type));
        }
        if (f.desc->type == FieldType::chr) {
            for (const std::uint64_t c : f.raw) {
                if (c == 0) {
                    break;
                }
                f.text += static_cast<char>(c);
            }
        }
        p.fields.push_back(std::move(f));
    }
    if (!r.ok()) {
        p.error = "payload shorter than its fields";  // cannot happen after the size check
        p.fields.clear();
        return p;
    }
    p.ok = true;
    return p;
}

std::string severityName(unsigned severity) {
    static const char* const kNames[] = {"DEBUG", "INFO", "WARN", "ERROR", "CRIT"};
    return severity < 5 ? kNames[severity] : "SEV" + std::to_string(severity);
}

std::string rejectReasonName(unsigned reason) {
    if (reason < cmdtlm::kRejectReasonCount) {
        return cmdtlm::toString(static_cast<cmdtlm::CommandReject>(reason));
    }
    return "reason_" + std::to_string(reason);
}

int rejectReasonCode(const std::string& name) {
    const std::string lower = toLower(name);
    for (std::size_t i = 0; i < cmdtlm::kRejectReasonCount; ++i) {
        if (lower == cmdtlm::toString(static_cast<cmdtlm::CommandReject>(i))) {
            return static_cast<int>(i);
        }
    }
    return -1;
}

std::string describeAck(const DecodedPacket& ack) {
    const auto apid = static_cast<std::uint16_t>(ack.value("apid").value_or(0));
    const auto fc = static_cast<std::uint8_t>(ack.value("function_code").value_or(0));
    const auto reason = static_cast<unsigned>(ack.value("reason").value_or(0));
    const auto detail = static_cast<int>(ack.value("detail").value_or(-1));
    const cmdtlm::CommandDesc* command = cmdtlm::findCommand(apid, fc);
    std::string text = std::string(command != nullptr ? command->name : "command") + " (" + hex3(apid) + "/" +
                       std::to_string(fc) + ", auth seq " +
                       formatNumber(ack.value("auth_sequence").value_or(0)) + ")";
    if (reason == 0) {
        return text + " accepted";
    }
    text += " rejected: " + rejectReasonName(reason);
    if (detail >= 0) {
        text += " (detail " + std::to_string(detail);
        if (reason == static_cast<unsigned>(cmdtlm::CommandReject::kArgumentOutOfRange) && command != nullptr &&
            static_cast<std::size_t>(detail) < command->argCount) {
            text += std::string(": argument ") + command->args[detail].name;
        } else if (reason == static_cast<unsigned>(cmdtlm::CommandReject::kExecutionFailed) && command != nullptr &&
                   std::string(command->name).rfind("TABLE_", 0) == 0 &&
                   static_cast<std::size_t>(detail) < tables::kTableRejectCount) {
            text += std::string(": table ") + tables::toString(static_cast<tables::TableReject>(detail));
        } else if (reason == static_cast<unsigned>(cmdtlm::CommandReject::kExecutionFailed) && command != nullptr &&
                   command->code == cmdtlm::CommandCode::EXEC_SET_TASK && detail < cmdtlm::kTaskCommandRefusalCount) {
            text += std::string(": ") + cmdtlm::toString(static_cast<cmdtlm::TaskCommandRefusal>(detail));
        } else if (reason == static_cast<unsigned>(cmdtlm::CommandReject::kWrongMode) &&
                   static_cast<std::size_t>(detail) < cmdtlm::kModeCount) {
            text += std::string(": rover in ") + cmdtlm::toString(static_cast<cmdtlm::Mode>(detail));
        }
        text += ")";
    }
    return text;
}

// EVENT_DATA: the event's numbers by the dictionary's names for that event id.
std::string renderEventData(const DecodedPacket& p) {
    const auto id = static_cast<core::EventId>(p.value("event_id").value_or(0));
    const std::size_t count = static_cast<std::size_t>(p.value("value_count").value_or(0));
    const cmdtlm::EventDataDesc* layout = cmdtlm::findEventData(id);
    std::string line =
        " event " + std::to_string(id) + " " + (layout != nullptr ? layout->name : "(no event data known)");
    for (std::size_t i = 0; i < count && i < core::kEventDataValues; ++i) {
        const bool named = layout != nullptr && i < layout->valueCount;
        line += " " + (named ? std::string(layout->values[i].name) : "value[" + std::to_string(i) + "]") + "=" +
                formatNumber(p.value("value", i).value_or(0));
    }
    return line + "  [event_sequence=" + formatNumber(p.value("event_sequence").value_or(0)) +
           " data_withheld=" + formatNumber(p.value("data_withheld").value_or(0)) + "]";
}

std::string renderPacket(const DecodedPacket& p) {
    if (!p.ok) {
        if (p.desc == nullptr && p.error.rfind("unknown APID", 0) == 0) {
            return padName("UNKNOWN") + " apid=" + hex3(p.apid) + " seq=" + std::to_string(p.sequenceCount) +
                   " length " + std::to_string(p.length) + ": " + rawSummary(p);
        }
        return padName("MALFORMED") + " " + p.error + ": " + rawSummary(p);
    }
    char met[32];
    std::snprintf(met, sizeof met, "%.3f", p.met);
    std::string line = padName(p.name()) + " apid=" + hex3(p.apid) + " seq=" + std::to_string(p.sequenceCount) +
                       " met=" + met;
    if (p.desc->apid == cmdtlm::EVENT_Tlm::kApid) {
        const DecodedField* text = p.field("text");
        line += " EVT " + formatNumber(p.value("event_id").value_or(0)) + " " +
                severityName(static_cast<unsigned>(p.value("severity").value_or(0))) + " " +
                (text != nullptr ? escapeText(text->text) : std::string()) +
                "  [event_sequence=" + formatNumber(p.value("event_sequence").value_or(0)) + "]";
        return line;
    }
    if (p.desc->apid == cmdtlm::HAZARDS_Tlm::kApid) {
        return line + renderHazards(p);
    }
    if (p.desc->apid == cmdtlm::EVENT_DATA_Tlm::kApid) {
        return line + renderEventData(p);
    }
    for (const DecodedField& f : p.fields) {
        line += " " + renderField(f, p.desc->name);
    }
    if (p.desc->apid == cmdtlm::CMD_ACK_Tlm::kApid) {
        line += "  => " + describeAck(p);
    }
    return line;
}

}  // namespace rse::ground
