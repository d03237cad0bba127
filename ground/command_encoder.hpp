// Ground command encoding: a dictionary name and "arg=value" strings become the
// argument bytes the flight's decodeArgs() reads, then a complete command packet
// (headers, MAC, checksum) through the flight's own encodeCommandPacket(), so the
// layout exists once. Every argument is checked here, before anything is sent,
// with the same rules as the flight validator (fsw/cmdtlm/command_validator.hpp):
// all given, none unknown, each parsed as its wire type, finite, within
// [min, max]; a blob 1..max bytes.
//
// Bad input throws CommandError, whose message names the command and the
// argument and shows the valid range or the usage line.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::ground {

class CommandError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The command of that dictionary name, case-insensitive; nullptr if none.
const cmdtlm::CommandDesc* lookupCommand(const std::string& name);

// "GOTO x=<f64 m, -10000..10000> y=<...> risk=<f64, 1e-09..0.5>"
std::string commandUsage(const cmdtlm::CommandDesc& command);
// "<f64 m, -10000..10000>" for one argument.
std::string argumentUsage(const cmdtlm::ArgDesc& arg);

// Argument bytes (big-endian, dictionary order) from "name=value" strings.
// Values: integers in decimal, 0x hex or any number form with an integral value
// ("1e3"); floats in any strtod form except nan/inf (f32: the value as stored,
// the float, is what is range-checked, as flight does); blobs as hex digits (optionally 0x-prefixed, ':' or '-' separators
// allowed) or @FILE for a file's bytes. SET_MODE's mode also takes a mode name
// (SAFE ...), and a table_id a table name (ROVER_GEOMETRY ...).
// Throws CommandError.
std::vector<std::uint8_t> encodeArguments(const cmdtlm::CommandDesc& command,
                                          const std::vector<std::string>& assignments);

// How a packet is authenticated: keyId 0 / key empty = unauthenticated (no MAC).
struct PacketAuth {
    std::uint16_t keyId = cmdtlm::kNoKey;
    std::vector<std::uint8_t> key;  // kKeySize bytes when keyId != 0
};

// The complete packet for encoded arguments. The CCSDS sequence count is the
// low 14 bits of the anti-replay sequence (one number to follow in captures).
// Throws CommandError if the packet cannot be built (too long, MAC failure).
std::vector<std::uint8_t> buildCommandPacket(const cmdtlm::CommandDesc& command,
                                             const std::vector<std::uint8_t>& args, const PacketAuth& auth,
                                             std::uint32_t authSequence);

// Both steps at once: "GOTO", {"x=1", "y=2", "risk=1e-3"} -> packet bytes. For
// tools and fuzz seed corpora. Throws CommandError (unknown command, bad args).
std::vector<std::uint8_t> encodeCommand(const std::string& name, const std::vector<std::string>& assignments,
                                        const PacketAuth& auth, std::uint32_t authSequence);

// The built-in lab key as a PacketAuth (key id 1).
PacketAuth labKeyAuth();

// A command's argument bytes through the dictionary's own encoder.
template <typename Args>
std::vector<std::uint8_t> argumentBytes(const Args& args) {
    std::vector<std::uint8_t> bytes(sizeof(Args));
    core::BeWriter w(bytes.data(), bytes.size());
    cmdtlm::encodeArgs(w, args);
    bytes.resize(w.size());
    return bytes;
}

}  // namespace rse::ground
