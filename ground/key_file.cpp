#include "ground/key_file.hpp"

#include <fstream>
#include <sys/stat.h>

#include "fsw/cmdtlm/command_auth.hpp"

namespace rse::ground {

PacketAuth loadPacketAuth(const std::string& keyFile, std::optional<std::uint16_t> keyId) {
    if (keyFile.empty()) {
        if (keyId && *keyId != cmdtlm::kLabKeyId) {
            throw KeyFileError("key id " + std::to_string(*keyId) +
                               ": only the lab key (id 1) is built in; give --key-file FILE for other keys");
        }
        return labKeyAuth();
    }
    std::ifstream in(keyFile);
    if (!in) {
        throw KeyFileError("cannot read key file '" + keyFile + "'");
    }
    std::string line;
    int number = 0;
    std::optional<PacketAuth> chosen;
    std::string ids;
    while (std::getline(in, line)) {
        ++number;
        std::uint16_t id = 0;
        std::uint8_t key[cmdtlm::kKeySize] = {};
        bool isKey = false;
        if (!core::isOk(cmdtlm::parseKeyLine(line.c_str(), &id, key, &isKey))) {
            throw KeyFileError(keyFile + ":" + std::to_string(number) +
                               ": not a key line (expected ID:64 hex digits, ID 1..65535, or a # comment)");
        }
        if (!isKey) {
            continue;
        }
        ids += (ids.empty() ? "" : ", ") + std::to_string(id);
        if (!chosen && (!keyId || *keyId == id)) {
            PacketAuth auth;
            auth.keyId = id;
            auth.key.assign(key, key + cmdtlm::kKeySize);
            chosen = std::move(auth);
        }
    }
    if (!chosen) {
        throw KeyFileError(keyFile + ": " +
                           (ids.empty() ? std::string("no key in the file")
                                        : "no key " + std::to_string(keyId ? *keyId : 0) + " (the file has " + ids + ")"));
    }
    return *chosen;
}

bool keyFileTooOpen(const std::string& keyFile) {
    struct stat info {};
    return ::stat(keyFile.c_str(), &info) == 0 && (info.st_mode & (S_IRWXG | S_IRWXO)) != 0;
}

}  // namespace rse::ground
