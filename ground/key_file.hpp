// The ground's command keys: a key file in the rse-fsw --key-file format (one
// "ID:64-hex-digits" a line, '#' comments; cmdtlm::parseKeyLine), or the
// built-in lab key (id 1), which every copy of this repository has.
#pragma once

#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>

#include "ground/command_encoder.hpp"

namespace rse::ground {

class KeyFileError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The key to sign with. keyFile empty: the lab key (keyId must be empty or 1).
// With a file: the key of keyId, or the file's first key. Throws KeyFileError
// naming the file and line of a bad line, or the missing id.
PacketAuth loadPacketAuth(const std::string& keyFile, std::optional<std::uint16_t> keyId);

// True when the file can be read or written by group or others (a warning).
bool keyFileTooOpen(const std::string& keyFile);

}  // namespace rse::ground
