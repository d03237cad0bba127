#include "ground/command_encoder.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <iterator>
#include <limits>
#include <sstream>

#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/table_types.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

using cmdtlm::ArgDesc;
using cmdtlm::CommandDesc;
using cmdtlm::FieldType;

bool isFloat(FieldType type) { return type == FieldType::f32 || type == FieldType::f64; }

[[noreturn]] void fail(const CommandDesc& command, const std::string& what) {
    throw CommandError(std::string(command.name) + ": " + what + "\nusage: " + commandUsage(command));
}

// Symbolic values some arguments take besides numbers.
bool symbolicValue(const ArgDesc& arg, const std::string& text, double* value) {
    const std::string name = arg.name;
    const std::string upper = toUpper(text);
    if (name == "mode") {
        for (std::size_t m = 0; m < cmdtlm::kModeCount; ++m) {
            if (upper == cmdtlm::toString(static_cast<cmdtlm::Mode>(m))) {
                *value = static_cast<double>(m);
                return true;
            }
        }
    }
    if (name == "table_id") {
        if (const tables::TableDesc* table = tables::findTable(upper.c_str())) {
            *value = static_cast<double>(static_cast<unsigned>(table->id));
            return true;
        }
    }
    return false;
}

double parseScalar(const CommandDesc& command, const ArgDesc& arg, const std::string& text) {
    const std::string shown = std::string(arg.name) + "=" + text;
    const std::string expected = " (expected " + argumentUsage(arg) + ")";
    double value = 0.0;
    if (symbolicValue(arg, text, &value)) {
        return value;
    }
    if (isFloat(arg.type)) {
        if (!parseDouble(text, &value)) {
            fail(command, shown + " is not a number" + expected);
        }
        if (!std::isfinite(value)) {
            fail(command, shown + " is not finite" + expected);
        }
        if (arg.type == FieldType::f32) {
            // Flight checks the value as stored: the float.
            if (std::fabs(value) > static_cast<double>(std::numeric_limits<float>::max())) {
                fail(command, shown + " does not fit a 32-bit float" + expected);
            }
            value = static_cast<double>(static_cast<float>(value));
        }
    } else {
        long long integer = 0;
        if (parseInteger(text, &integer)) {
            value = static_cast<double>(integer);
        } else if (parseDouble(text, &value) && std::isfinite(value)) {
            // "1e3" is an integer too; "1.5" is not.
            if (value != std::floor(value)) {
                fail(command, shown + " is not an integer" + expected);
            }
        } else {
            fail(command, shown + " is not a number" + expected);
        }
    }
    if (value < arg.min || value > arg.max) {
        fail(command, shown + " is out of range " + formatNumber(arg.min) + ".." + formatNumber(arg.max) +
                          (arg.units[0] != '\0' ? std::string(" ") + arg.units : std::string()) + expected);
    }
    return value;
}

void writeScalar(core::BeWriter& w, FieldType type, double value) {
    switch (type) {
        case FieldType::u8: case FieldType::chr: case FieldType::blob:
            w.u8(static_cast<std::uint8_t>(value));
            break;
        case FieldType::u16: w.u16(static_cast<std::uint16_t>(value)); break;
        case FieldType::u32: w.u32(static_cast<std::uint32_t>(value)); break;
        case FieldType::u64: w.u64(static_cast<std::uint64_t>(value)); break;
        case FieldType::i16: w.i16(static_cast<std::int16_t>(value)); break;
        case FieldType::i32: w.i32(static_cast<std::int32_t>(value)); break;
        case FieldType::i64: w.i64(static_cast<std::int64_t>(value)); break;
        case FieldType::f32: w.f32(static_cast<float>(value)); break;
        case FieldType::f64: w.f64(value); break;
    }
}

std::vector<std::uint8_t> parseBlob(const CommandDesc& command, const ArgDesc& arg, const std::string& text) {
    const std::string shown = std::string(arg.name) + "=";
    std::vector<std::uint8_t> bytes;
    if (!text.empty() && text[0] == '@') {
        const std::string path = text.substr(1);
        std::ifstream in(path, std::ios::binary);
        if (!in) {
            fail(command, shown + text + ": cannot read file '" + path + "'");
        }
        bytes.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    } else {
        std::size_t i = 0;
        if (text.size() >= 2 && text[0] == '0' && (text[1] == 'x' || text[1] == 'X')) {
            i = 2;
        }
        int high = -1;
        for (; i < text.size(); ++i) {
            const char c = text[i];
            if ((c == ':' || c == '-' || c == '_') && high < 0) {
                continue;
            }
            const int d = hexDigit(c);
            if (d < 0) {
                fail(command, shown + text + " is not hex bytes (expected " + argumentUsage(arg) + ")");
            }
            if (high < 0) {
                high = d;
            } else {
                bytes.push_back(static_cast<std::uint8_t>((high << 4) | d));
                high = -1;
            }
        }
        if (high >= 0) {
            fail(command, shown + text + " has an odd number of hex digits (expected " + argumentUsage(arg) + ")");
        }
    }
    if (bytes.empty() || bytes.size() > arg.maxBytes) {
        fail(command, shown + (text.size() > 40 ? text.substr(0, 40) + "..." : text) + " is " +
                          std::to_string(bytes.size()) + " bytes, must be 1.." + std::to_string(arg.maxBytes));
    }
    return bytes;
}

}  // namespace

const cmdtlm::CommandDesc* lookupCommand(const std::string& name) {
    return cmdtlm::findCommand(toUpper(name).c_str());
}

std::string argumentUsage(const cmdtlm::ArgDesc& arg) {
    if (arg.type == FieldType::blob) {
        return "<hex or @file, 1.." + std::to_string(arg.maxBytes) + " bytes>";
    }
    std::string text = std::string("<") + cmdtlm::toString(arg.type);
    if (arg.units != nullptr && arg.units[0] != '\0') {
        text += std::string(" ") + arg.units;
    }
    text += ", " + formatNumber(arg.min) + ".." + formatNumber(arg.max) + ">";
    return text;
}

std::string commandUsage(const cmdtlm::CommandDesc& command) {
    std::string text = command.name;
    for (std::size_t i = 0; i < command.argCount; ++i) {
        text += std::string(" ") + command.args[i].name + "=" + argumentUsage(command.args[i]);
    }
    return text;
}

std::vector<std::uint8_t> encodeArguments(const cmdtlm::CommandDesc& command,
                                          const std::vector<std::string>& assignments) {
    std::vector<std::string> values(command.argCount);
    std::vector<bool> given(command.argCount, false);
    for (const std::string& item : assignments) {
        const std::size_t eq = item.find('=');
        if (eq == std::string::npos || eq == 0) {
            fail(command, "'" + item + "' is not name=value");
        }
        const std::string name = toLower(item.substr(0, eq));
        std::size_t index = command.argCount;
        for (std::size_t i = 0; i < command.argCount; ++i) {
            if (name == command.args[i].name) {
                index = i;
            }
        }
        if (index == command.argCount) {
            fail(command, command.argCount == 0 ? "takes no arguments (got '" + item + "')"
                                                : "has no argument '" + name + "'");
        }
        if (given[index]) {
            fail(command, "argument '" + name + "' given twice");
        }
        given[index] = true;
        values[index] = item.substr(eq + 1);
    }
    for (std::size_t i = 0; i < command.argCount; ++i) {
        if (!given[i]) {
            fail(command, std::string("missing argument '") + command.args[i].name + "' " +
                              argumentUsage(command.args[i]));
        }
    }
    std::vector<std::uint8_t> bytes(static_cast<std::size_t>(command.fixedArgBytes) + command.maxBlobBytes);
    core::BeWriter w(bytes.data(), bytes.size());
    for (std::size_t i = 0; i < command.argCount; ++i) {
        const ArgDesc& arg = command.args[i];
        if (arg.type == FieldType::blob) {
            const std::vector<std::uint8_t> blob = parseBlob(command, arg, values[i]);
            w.bytes(blob.data(), blob.size());
        } else {
            writeScalar(w, arg.type, parseScalar(command, arg, values[i]));
        }
    }
    if (!w.ok()) {
        fail(command, "arguments do not fit the command");
    }
    bytes.resize(w.size());
    return bytes;
}

std::vector<std::uint8_t> buildCommandPacket(const cmdtlm::CommandDesc& command,
                                             const std::vector<std::uint8_t>& args, const PacketAuth& auth,
                                             std::uint32_t authSequence) {
    const bool authenticated = auth.keyId != cmdtlm::kNoKey;
    if (authenticated && auth.key.size() != cmdtlm::kKeySize) {
        throw CommandError("key " + std::to_string(auth.keyId) + " has no 32-byte key");
    }
    cmdtlm::HmacSha256 hmac;
    if (authenticated && !core::isOk(hmac.init())) {
        throw CommandError("cannot initialise HMAC-SHA-256 (mbedTLS)");
    }
    cmdtlm::CommandFields fields;
    fields.apid = command.apid;
    fields.functionCode = command.functionCode;
    fields.sequenceCount = static_cast<std::uint16_t>(authSequence & cmdtlm::kSequenceCountMask);
    fields.keyId = auth.keyId;
    fields.authSequence = authSequence;
    std::vector<std::uint8_t> packet(cmdtlm::kMaxCommandPacket);
    const std::size_t length =
        cmdtlm::encodeCommandPacket(fields, args.data(), args.size(), authenticated ? auth.key.data() : nullptr,
                                    hmac, packet.data(), packet.size());
    if (length == 0) {
        throw CommandError(std::string(command.name) + ": the packet cannot be built (" +
                           std::to_string(args.size()) + " argument bytes; at most " +
                           std::to_string(cmdtlm::kMaxCommandPacket) + " bytes a packet)");
    }
    packet.resize(length);
    return packet;
}

std::vector<std::uint8_t> encodeCommand(const std::string& name, const std::vector<std::string>& assignments,
                                        const PacketAuth& auth, std::uint32_t authSequence) {
    const cmdtlm::CommandDesc* command = lookupCommand(name);
    if (command == nullptr) {
        throw CommandError("unknown command '" + name + "' (rse-ground dict --markdown lists them)");
    }
    return buildCommandPacket(*command, encodeArguments(*command, assignments), auth, authSequence);
}

PacketAuth labKeyAuth() {
    PacketAuth auth;
    auth.keyId = cmdtlm::kLabKeyId;
    auth.key.assign(cmdtlm::kLabKey, cmdtlm::kLabKey + cmdtlm::kKeySize);
    return auth;
}

}  // namespace rse::ground
