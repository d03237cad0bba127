#include "ground/dictionary_export.hpp"

#include <cstdio>
#include <sstream>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "ground/command_encoder.hpp"
#include "ground/telemetry_limits.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

using cmdtlm::ArgDesc;
using cmdtlm::CommandDesc;
using cmdtlm::FieldDesc;
using cmdtlm::FieldType;
using cmdtlm::TelemetryDesc;

// Indexed by cmdtlm::CommandReject; the order of checks is command_validator.hpp's.
constexpr const char* kReasonDescriptions[] = {
    "accepted (and executed)",
    "the command queue was full: the command was dropped unread",
    "packet length wrong: shorter than the headers, longer than 256 bytes, not equal to the length field, "
    "no room for the MAC, or argument bytes not the dictionary's size (detail: fixed argument bytes)",
    "primary or secondary header wrong: version, packet type, secondary header flag, sequence flags or the "
    "function code's reserved bit",
    "the cFS checksum does not check",
    "no command has this APID",
    "the APID has no command with this function code",
    "unauthenticated (key id 0) while the rover requires authentication",
    "the key id names no key loaded on the rover: counted in HK.cmd_rejected_by_reason[8] only; never in a "
    "CMD_ACK, which says bad_mac so an unauthenticated sender cannot tell which key ids exist",
    "the MAC does not verify with the key, or the key id names no key loaded on the rover (the CMD_ACK does "
    "not tell the two apart; HK.cmd_rejected_by_reason does)",
    "the anti-replay sequence number was already accepted",
    "the anti-replay sequence number is older than the replay window (64 below the highest accepted)",
    "an argument is outside its [min, max] or not finite (detail: argument index, from 0)",
    "the current mode does not allow the command (detail: the rover's mode)",
    "the command was valid but failed when executed (detail: the handler's code, e.g. the table reject code)",
    "the key's anti-replay state is not known (detail: 1 store missing, 2 store corrupt, 3 key not in the store, "
    "5 store unreadable; for AUTH_RESYNC 4 wrong nonce, 6 no nonce): refused until AUTH_RESYNC",
    "the anti-replay sequence number is above 4294966271 (0xFFFFFFFF - 1024): the key's numbers are used up; "
    "change the key",
    "the anti-replay reservation could not be written to the store (detail -1), or was not durable within 1 s (detail 1): refused, not acted on (HK.auth_store_write_failures, auth_store_wait_frames)",
};
static_assert(sizeof kReasonDescriptions / sizeof kReasonDescriptions[0] == cmdtlm::kRejectReasonCount,
              "one description per CMD_ACK reason code");

std::string hex3(unsigned value) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "0x%03X", value);
    return buffer;
}

std::string modeNames(std::uint8_t modes, const char* separator) {
    if (modes == cmdtlm::mode_mask::kAnyMode) {
        return "any";
    }
    std::string text;
    for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
        if (cmdtlm::modeAllows(modes, static_cast<cmdtlm::Mode>(m))) {
            text += (text.empty() ? "" : separator);
            text += cmdtlm::toString(static_cast<cmdtlm::Mode>(m));
        }
    }
    return text;
}

// "any mode", "mode MANUAL", "modes STANDBY, AUTONOMOUS"
std::string modeList(std::uint8_t modes) {
    if (modes == cmdtlm::mode_mask::kAnyMode) {
        return "any mode";
    }
    const std::string names = modeNames(modes, ", ");
    return (names.find(',') == std::string::npos ? "mode " : "modes ") + names;
}

std::string md(const char* text) {
    std::string out;
    for (const char* p = text; p != nullptr && *p != '\0'; ++p) {
        if (*p == '|') {
            out += "\\|";
        } else {
            out += *p;
        }
    }
    return out;
}

std::string json(const char* text) {
    std::string out = "\"";
    for (const char* p = text; p != nullptr && *p != '\0'; ++p) {
        const auto c = static_cast<unsigned char>(*p);
        if (c == '"' || c == '\\') {
            out += '\\';
            out += *p;
        } else if (c < 0x20) {
            char buffer[8];
            std::snprintf(buffer, sizeof buffer, "\\u%04X", c);
            out += buffer;
        } else {
            out += *p;
        }
    }
    return out + "\"";
}

std::size_t fieldSize(const FieldDesc& f) { return cmdtlm::wireSize(f.type) * f.count; }

const CommandDesc* commands(std::size_t* count) { return cmdtlm::commandDescs(count); }
const TelemetryDesc* telemetry(std::size_t* count) { return cmdtlm::telemetryDescs(count); }

std::string anchor(const char* name) { return toLower(name); }

// A bound for the Markdown table: the number, or "-" for no bound.
std::string mdBound(double bound) { return hasBound(bound) ? formatNumber(bound) : "-"; }

// The field's limits as a JSON object (only the sides that have a bound, then why).
std::string jsonLimits(const TelemetryLimit& limit) {
    std::string out = "{";
    const struct {
        const char* key;
        double value;
    } bounds[] = {{"warn_low", limit.warnLow},
                  {"warn_high", limit.warnHigh},
                  {"alarm_low", limit.alarmLow},
                  {"alarm_high", limit.alarmHigh}};
    for (const auto& b : bounds) {
        if (hasBound(b.value)) {
            out += "\"" + std::string(b.key) + "\": " + formatNumber(b.value) + ", ";
        }
    }
    return out + "\"why\": " + json(limit.why) + "}";
}

}  // namespace

const char* rejectReasonDescription(unsigned reason) {
    return reason < cmdtlm::kRejectReasonCount ? kReasonDescriptions[reason] : "";
}

namespace {

// The Markdown export, section by section (exportDictionaryMarkdown's order).
void mdPreamble(std::ostream& o) {
    o << "# RSE command and telemetry dictionary\n\n"
      << "<!-- Generated from fsw/cmdtlm/dictionary.def by `rse-ground dict --markdown`. Do not edit:\n"
      << "     change the .def and regenerate (a unit test fails while this file is stale). -->\n\n"
      << "Every command the rover accepts and every telemetry packet it sends. Packets are CCSDS\n"
      << "space packets, every field big-endian (docs/icd.md, \"Ground link\"). A machine-readable\n"
      << "copy of the same content is [dictionary.json](dictionary.json); `rse-ground` (docs/ground.md)\n"
      << "encodes and decodes by the same descriptors.\n\n"
      << "- Command packet: primary header (6) + function code (1) + checksum (1) + key id (2) +\n"
      << "  anti-replay sequence (4) + arguments, in the order listed + HMAC-SHA-256/128 MAC (16,\n"
      << "  when the key id is not 0). At most " << cmdtlm::kMaxCommandPacket << " bytes.\n"
      << "- Telemetry packet: primary header (6) + mission elapsed time, seconds (4) and 1/65536 s (2) +\n"
      << "  payload, the fields listed. At most " << cmdtlm::kMaxTelemetryPacket << " bytes.\n"
      << "- A command is refused whole if any argument is outside [min, max] or, for floats, not\n"
      << "  finite. Types: u8/u16/u32/u64 unsigned, i16/i32/i64 signed, f32/f64 IEEE 754, chr N: text of\n"
      << "  N bytes padded with NUL, blob: the remaining bytes of the packet (last argument only).\n"
      << "- Display limits: some telemetry fields have them (a table under the packet's fields; in the\n"
      << "  JSON, `limits` on the field). A value below warn_low or above warn_high is outside its\n"
      << "  normal range (warn), below alarm_low or above alarm_high past its limit (alarm); a value\n"
      << "  equal to a bound is inside it, \"-\" is no bound, and an array field's limits hold for every\n"
      << "  element. `why` says where each bound comes from: most mirror the default value of the table\n"
      << "  field named (a unit test holds them to it). They colour the display only: the rover's faults\n"
      << "  use the tables in force.\n"
      << "- Event data: the numbers some events carry beside their text (section Event data below),\n"
      << "  sent in an EVENT_DATA packet right after the event's EVENT packet (same event_sequence).\n"
      << "  Decide on these; the event text is for people and may be reworded.\n\n";
}

void mdModes(std::ostream& o) {
    o << "## Modes\n\n| Value | Mode |\n|---:|---|\n";
    for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
        o << "| " << m << " | " << cmdtlm::toString(static_cast<cmdtlm::Mode>(m)) << " |\n";
    }
}

void mdCommandIndex(std::ostream& o, const CommandDesc* cmds, std::size_t commandCount) {
    o << "\n## Commands\n\n| Command | APID | FC | Modes | Arguments | Description |\n"
      << "|---|---|---:|---|---|---|\n";
    for (std::size_t i = 0; i < commandCount; ++i) {
        const CommandDesc& c = cmds[i];
        std::string args;
        for (std::size_t a = 0; a < c.argCount; ++a) {
            args += std::string(a > 0 ? ", " : "") + c.args[a].name;
        }
        o << "| [" << c.name << "](#" << anchor(c.name) << ") | " << hex3(c.apid) << " | "
          << static_cast<unsigned>(c.functionCode) << " | " << modeNames(c.modes, ", ") << " | "
          << (args.empty() ? "-" : args) << " | " << md(c.description) << " |\n";
    }
}

void mdCommandSection(std::ostream& o, const CommandDesc& c) {
    o << "\n### " << c.name << "\n\n"
      << md(c.description) << ".\n\n"
      << "APID " << hex3(c.apid) << ", function code " << static_cast<unsigned>(c.functionCode)
      << ", accepted in " << modeList(c.modes) << ". ";
    if (c.argCount == 0) {
        o << "No arguments.\n";
    } else {
        o << "Argument bytes: " << c.fixedArgBytes;
        if (c.maxBlobBytes > 0) {
            o << " + 1.." << c.maxBlobBytes;
        }
        o << ".\n\n| Argument | Type | Units | Min | Max | Description |\n|---|---|---|---:|---:|---|\n";
        for (std::size_t a = 0; a < c.argCount; ++a) {
            const ArgDesc& arg = c.args[a];
            if (arg.type == FieldType::blob) {
                o << "| " << arg.name << " | blob | bytes | 1 | " << arg.maxBytes << " | " << md(arg.description)
                  << " |\n";
            } else {
                o << "| " << arg.name << " | " << cmdtlm::toString(arg.type) << " | " << md(arg.units) << " | "
                  << formatNumber(arg.min) << " | " << formatNumber(arg.max) << " | " << md(arg.description)
                  << " |\n";
            }
        }
    }
    o << "\n`rse-ground send " << commandUsage(c) << "`\n";
}

void mdReasonCodes(std::ostream& o) {
    o << "\n## CMD_ACK reason codes\n\n"
      << "Every command received is answered by one CMD_ACK packet; `reason` is 0 when the command\n"
      << "was accepted, otherwise the first check it failed, in this order (HK.cmd_rejected_by_reason\n"
      << "counts them by code).\n\n| Code | Name | Meaning |\n|---:|---|---|\n";
    for (unsigned r = 0; r < cmdtlm::kRejectReasonCount; ++r) {
        o << "| " << r << " | " << cmdtlm::toString(static_cast<cmdtlm::CommandReject>(r)) << " | "
          << md(kReasonDescriptions[r]) << " |\n";
    }
}

void mdTelemetryIndex(std::ostream& o, const TelemetryDesc* tlm, std::size_t telemetryCount) {
    o << "\n## Telemetry\n\n| Packet | APID | Payload bytes | Packet bytes | Description |\n"
      << "|---|---|---:|---:|---|\n";
    for (std::size_t i = 0; i < telemetryCount; ++i) {
        const TelemetryDesc& t = tlm[i];
        // A packet named like a command (TABLE_DUMP) gets the second heading's anchor.
        const bool clash = cmdtlm::findCommand(t.name) != nullptr;
        o << "| [" << t.name << "](#" << anchor(t.name) << (clash ? "-1" : "") << ") | " << hex3(t.apid) << " | " << t.payloadSize << " | "
          << t.payloadSize + cmdtlm::kTelemetryHeaderSize << " | " << md(t.description) << " |\n";
    }
}

// The packet's display limits table, when any of its fields has limits.
void mdTelemetryLimits(std::ostream& o, const TelemetryDesc& t) {
    bool heading = false;
    for (std::size_t f = 0; f < t.fieldCount; ++f) {
        const TelemetryLimit* limit = findTelemetryLimit(t.name, t.fields[f].name);
        if (limit == nullptr) {
            continue;
        }
        if (!heading) {
            o << "\nDisplay limits:\n\n| Field | Warn low | Warn high | Alarm low | Alarm high | Why |\n"
              << "|---|---:|---:|---:|---:|---|\n";
            heading = true;
        }
        o << "| " << limit->field << " | " << mdBound(limit->warnLow) << " | " << mdBound(limit->warnHigh)
          << " | " << mdBound(limit->alarmLow) << " | " << mdBound(limit->alarmHigh) << " | " << md(limit->why)
          << " |\n";
    }
}

void mdTelemetrySection(std::ostream& o, const TelemetryDesc& t) {
    o << "\n### " << t.name << "\n\n"
      << md(t.description) << ". APID " << hex3(t.apid) << ", payload " << t.payloadSize << " bytes (packet "
      << t.payloadSize + cmdtlm::kTelemetryHeaderSize << ").\n\n"
      << "| Offset | Field | Type | Count | Units | Description |\n|---:|---|---|---:|---|---|\n";
    std::size_t offset = 0;
    for (std::size_t f = 0; f < t.fieldCount; ++f) {
        const FieldDesc& field = t.fields[f];
        o << "| " << offset << " | " << field.name << " | " << cmdtlm::toString(field.type) << " | " << field.count
          << " | " << md(field.units) << " | " << md(field.description) << " |\n";
        offset += fieldSize(field);
    }
    mdTelemetryLimits(o, t);
}

// "905", or "760..763" for a layout shared by a range of event ids.
std::string eventIds(const cmdtlm::EventDataDesc& d) {
    return d.firstId == d.lastId ? std::to_string(d.firstId)
                                 : std::to_string(d.firstId) + ".." + std::to_string(d.lastId);
}

void mdEventData(std::ostream& o) {
    std::size_t count = 0;
    const cmdtlm::EventDataDesc* layouts = cmdtlm::eventDataDescs(&count);
    o << "\n## Event data\n\n"
      << "The numbers an event carries (F'-style event arguments), in this order in EVENT_DATA.value\n"
      << "(value_count of them; f64, integers exact). Every report of an event listed carries all its\n"
      << "values; an event not listed carries none. Codes are the numbers of the enumeration named.\n\n"
      << "| Event data | Events | Values | Description |\n|---|---|---|---|\n";
    for (std::size_t i = 0; i < count; ++i) {
        std::string names;
        for (std::size_t v = 0; v < layouts[i].valueCount; ++v) {
            names += std::string(v > 0 ? ", " : "") + layouts[i].values[v].name;
        }
        o << "| [" << layouts[i].name << "](#" << anchor(layouts[i].name) << ") | " << eventIds(layouts[i]) << " | "
          << names << " | " << md(layouts[i].description) << " |\n";
    }
    for (std::size_t i = 0; i < count; ++i) {
        const cmdtlm::EventDataDesc& d = layouts[i];
        o << "\n### " << d.name << "\n\n"
          << md(d.description) << ". Event" << (d.firstId == d.lastId ? " " : "s ") << eventIds(d) << ", "
          << static_cast<unsigned>(d.valueCount) << " values.\n\n"
          << "| Value | Name | Units | Description |\n|---:|---|---|---|\n";
        for (std::size_t v = 0; v < d.valueCount; ++v) {
            o << "| " << v << " | " << d.values[v].name << " | " << md(d.values[v].units) << " | "
              << md(d.values[v].description) << " |\n";
        }
    }
}

void jsonEventData(std::ostream& o) {
    std::size_t count = 0;
    const cmdtlm::EventDataDesc* layouts = cmdtlm::eventDataDescs(&count);
    o << "  \"event_data\": [\n";
    for (std::size_t i = 0; i < count; ++i) {
        const cmdtlm::EventDataDesc& d = layouts[i];
        o << "    {\n"
          << "      \"name\": " << json(d.name) << ",\n"
          << "      \"first_event_id\": " << d.firstId << ",\n"
          << "      \"last_event_id\": " << d.lastId << ",\n"
          << "      \"description\": " << json(d.description) << ",\n"
          << "      \"values\": [";
        for (std::size_t v = 0; v < d.valueCount; ++v) {
            o << (v > 0 ? "," : "") << "\n        {\"index\": " << v << ", \"name\": " << json(d.values[v].name)
              << ", \"units\": " << json(d.values[v].units) << ", \"description\": " << json(d.values[v].description)
              << "}";
        }
        o << "\n      ]\n    }" << (i + 1 < count ? "," : "") << "\n";
    }
    o << "  ]\n";
}

void jsonTelemetry(std::ostream& o, const TelemetryDesc* tlm, std::size_t telemetryCount) {
    o << "  \"telemetry\": [\n";
    for (std::size_t i = 0; i < telemetryCount; ++i) {
        const TelemetryDesc& t = tlm[i];
        o << "    {\n"
          << "      \"name\": " << json(t.name) << ",\n"
          << "      \"apid\": " << t.apid << ",\n"
          << "      \"description\": " << json(t.description) << ",\n"
          << "      \"payload_bytes\": " << t.payloadSize << ",\n"
          << "      \"packet_bytes\": " << t.payloadSize + cmdtlm::kTelemetryHeaderSize << ",\n"
          << "      \"fields\": [";
        std::size_t offset = 0;
        for (std::size_t f = 0; f < t.fieldCount; ++f) {
            const FieldDesc& field = t.fields[f];
            o << (f > 0 ? "," : "") << "\n        {\"name\": " << json(field.name) << ", \"type\": "
              << json(cmdtlm::toString(field.type)) << ", \"count\": " << field.count << ", \"offset\": " << offset
              << ", \"units\": " << json(field.units) << ", \"description\": " << json(field.description);
            if (const TelemetryLimit* limit = findTelemetryLimit(t.name, field.name)) {
                o << ", \"limits\": " << jsonLimits(*limit);
            }
            o << "}";
            offset += fieldSize(field);
        }
        o << "\n      ]\n    }" << (i + 1 < telemetryCount ? "," : "") << "\n";
    }
}

}  // namespace

std::string exportDictionaryMarkdown() {
    std::ostringstream o;
    std::size_t commandCount = 0;
    std::size_t telemetryCount = 0;
    const CommandDesc* cmds = commands(&commandCount);
    const TelemetryDesc* tlm = telemetry(&telemetryCount);
    mdPreamble(o);
    mdModes(o);
    mdCommandIndex(o, cmds, commandCount);
    for (std::size_t i = 0; i < commandCount; ++i) {
        mdCommandSection(o, cmds[i]);
    }
    mdReasonCodes(o);
    mdTelemetryIndex(o, tlm, telemetryCount);
    for (std::size_t i = 0; i < telemetryCount; ++i) {
        mdTelemetrySection(o, tlm[i]);
    }
    mdEventData(o);
    return o.str();
}

std::string exportDictionaryJson() {
    std::ostringstream o;
    std::size_t commandCount = 0;
    std::size_t telemetryCount = 0;
    const CommandDesc* cmds = commands(&commandCount);
    const TelemetryDesc* tlm = telemetry(&telemetryCount);

    o << "{\n"
      << "  \"format\": \"rse-dictionary\",\n"
      << "  \"format_version\": 1,\n"
      << "  \"generated_from\": \"fsw/cmdtlm/dictionary.def\",\n"
      << "  \"generated_by\": \"rse-ground dict --json\",\n"
      << "  \"byte_order\": \"big-endian\",\n"
      << "  \"command_packet\": {\"header_bytes\": " << cmdtlm::kCommandHeaderSize
      << ", \"mac_bytes\": " << cmdtlm::kMacSize << ", \"max_bytes\": " << cmdtlm::kMaxCommandPacket << "},\n"
      << "  \"telemetry_packet\": {\"header_bytes\": " << cmdtlm::kTelemetryHeaderSize
      << ", \"max_bytes\": " << cmdtlm::kMaxTelemetryPacket << "},\n";

    o << "  \"modes\": [\n";
    for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
        o << "    {\"value\": " << m << ", \"name\": " << json(cmdtlm::toString(static_cast<cmdtlm::Mode>(m))) << "}"
          << (m + 1 < cmdtlm::kModeCount ? "," : "") << "\n";
    }
    o << "  ],\n";

    o << "  \"cmd_ack_reasons\": [\n";
    for (unsigned r = 0; r < cmdtlm::kRejectReasonCount; ++r) {
        o << "    {\"code\": " << r << ", \"name\": " << json(cmdtlm::toString(static_cast<cmdtlm::CommandReject>(r)))
          << ", \"description\": " << json(kReasonDescriptions[r]) << "}" << (r + 1 < cmdtlm::kRejectReasonCount ? "," : "")
          << "\n";
    }
    o << "  ],\n";

    o << "  \"commands\": [\n";
    for (std::size_t i = 0; i < commandCount; ++i) {
        const CommandDesc& c = cmds[i];
        o << "    {\n"
          << "      \"name\": " << json(c.name) << ",\n"
          << "      \"apid\": " << c.apid << ",\n"
          << "      \"function_code\": " << static_cast<unsigned>(c.functionCode) << ",\n"
          << "      \"modes\": [";
        bool first = true;
        for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
            if (cmdtlm::modeAllows(c.modes, static_cast<cmdtlm::Mode>(m))) {
                o << (first ? "" : ", ") << json(cmdtlm::toString(static_cast<cmdtlm::Mode>(m)));
                first = false;
            }
        }
        o << "],\n"
          << "      \"description\": " << json(c.description) << ",\n"
          << "      \"fixed_argument_bytes\": " << c.fixedArgBytes << ",\n"
          << "      \"max_blob_bytes\": " << c.maxBlobBytes << ",\n"
          << "      \"arguments\": [";
        for (std::size_t a = 0; a < c.argCount; ++a) {
            const ArgDesc& arg = c.args[a];
            o << (a > 0 ? "," : "") << "\n        {\"name\": " << json(arg.name) << ", \"type\": "
              << json(cmdtlm::toString(arg.type));
            if (arg.type == FieldType::blob) {
                o << ", \"units\": \"bytes\", \"min_bytes\": 1, \"max_bytes\": " << arg.maxBytes;
            } else {
                o << ", \"units\": " << json(arg.units) << ", \"min\": " << formatNumber(arg.min)
                  << ", \"max\": " << formatNumber(arg.max);
            }
            o << ", \"description\": " << json(arg.description) << "}";
        }
        o << (c.argCount > 0 ? "\n      ]\n" : "]\n") << "    }" << (i + 1 < commandCount ? "," : "") << "\n";
    }
    o << "  ],\n";

    jsonTelemetry(o, tlm, telemetryCount);
    o << "  ],\n";
    jsonEventData(o);
    o << "}\n";
    return o.str();
}

}  // namespace rse::ground
