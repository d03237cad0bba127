#include "fsw/cmdtlm/key_loader.hpp"

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <sys/stat.h>

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

const char* toString(KeyLoadError error) {
    switch (error) {
        case KeyLoadError::kNone: return "loaded";
        case KeyLoadError::kCannotOpen: return "cannot be read";
        case KeyLoadError::kNotRegularFile: return "not a regular file";
        case KeyLoadError::kOpenToOthers: return "group or others may read or write it (chmod 600, or --allow-readable-key)";
        case KeyLoadError::kBadLine: return "not a key line (want ID:64-hex-digits)";
        case KeyLoadError::kDuplicateKeyId: return "key id given twice";
        case KeyLoadError::kTooManyKeys: return "more keys than the key store holds";
        case KeyLoadError::kNoKeyInFile: return "holds no key";
        case KeyLoadError::kLabKeyRefused: return "the public lab key (give --lab-key to use it in the lab)";
        case KeyLoadError::kWeakKeyRefused: return "weak key (or --allow-weak-key)";
    }
    return "?";
}

namespace {

constexpr mode_t kOpenToOthersBits = S_IRGRP | S_IWGRP | S_IROTH | S_IWOTH;

KeyLoadResult refuse(KeyLoadResult result, KeyLoadError error, core::Status status, const char* path,
                     KeyStore& keys, core::EventLog& eventLog) {
    keys.clear();
    result.status = status;
    result.error = error;
    result.keysLoaded = 0;
    if (result.line > 0) {
        eventLog.report(events::kKeyFileRefused, core::Severity::kCritical, "cmd: key file %s:%u refused: %s (key %u)",
                      path, result.line, toString(error), static_cast<unsigned>(result.keyId));
    } else {
        eventLog.report(events::kKeyFileRefused, core::Severity::kCritical, "cmd: key file %s refused: %s", path,
                      toString(error));
    }
    return result;
}

}  // namespace

KeyLoadResult loadKeyFile(const char* path, const KeyLoadOptions& options, KeyStore& keys,
                          core::EventLog& eventLog) {
    KeyLoadResult result;
    keys.clear();
    if (path == nullptr) {
        return refuse(result, KeyLoadError::kCannotOpen, core::Status::kInvalidArgument, "(none)", keys, eventLog);
    }
    std::FILE* file = std::fopen(path, "r");
    if (file == nullptr) {
        result.osError = errno;
        return refuse(result, KeyLoadError::kCannotOpen, core::Status::kNotFound, path, keys, eventLog);
    }
    // The checks look at the file that was opened, not at the path again.
    struct stat info {};
    if (fstat(fileno(file), &info) != 0) {
        result.osError = errno;
        std::fclose(file);
        return refuse(result, KeyLoadError::kCannotOpen, core::Status::kUnavailable, path, keys, eventLog);
    }
    if (!S_ISREG(info.st_mode)) {
        std::fclose(file);
        return refuse(result, KeyLoadError::kNotRegularFile, core::Status::kInvalidArgument, path, keys, eventLog);
    }
    if ((info.st_mode & kOpenToOthersBits) != 0) {
        if (!options.readableFileAllowed) {
            std::fclose(file);
            return refuse(result, KeyLoadError::kOpenToOthers, core::Status::kInvalidArgument, path, keys, eventLog);
        }
        result.openFileAccepted = true;
    }

    char line[256];
    unsigned lineNumber = 0;
    KeyLoadError error = KeyLoadError::kNone;
    core::Status status = core::Status::kOk;
    while (error == KeyLoadError::kNone && std::fgets(line, sizeof line, file) != nullptr) {
        ++lineNumber;
        result.line = lineNumber;
        if (std::strchr(line, '\n') == nullptr && std::feof(file) == 0) {
            error = KeyLoadError::kBadLine;  // longer than the buffer
            status = core::Status::kTooLarge;
            break;
        }
        std::uint16_t id = kNoKey;
        std::uint8_t key[kKeySize] = {};
        bool isKey = false;
        if (!core::isOk(parseKeyLine(line, &id, key, &isKey))) {
            error = KeyLoadError::kBadLine;
            status = core::Status::kInvalidArgument;
            break;
        }
        if (!isKey) {
            continue;
        }
        result.keyId = id;
        const KeyWeakness weakness = keyWeakness(key);
        if (keys.find(id) != nullptr) {
            error = KeyLoadError::kDuplicateKeyId;
            status = core::Status::kAlreadyExists;
        } else if (isLabKey(key) && !options.labKeyAllowed) {
            error = KeyLoadError::kLabKeyRefused;
            status = core::Status::kInvalidArgument;
        } else if (weakness != KeyWeakness::kNone && !options.weakKeyAllowed) {
            result.weakness = weakness;
            error = KeyLoadError::kWeakKeyRefused;
            status = core::Status::kInvalidArgument;
        } else if (!core::isOk(keys.add(id, key))) {
            error = KeyLoadError::kTooManyKeys;
            status = core::Status::kFull;
        } else if (weakness != KeyWeakness::kNone) {
            ++result.weakKeysAccepted;
            eventLog.report(events::kWeakKeyAccepted, core::Severity::kWarning,
                          "cmd: weak key %u loaded (%s) because --allow-weak-key said so: not for flight",
                          static_cast<unsigned>(id), toString(weakness));
        }
        std::memset(key, 0, sizeof key);
    }
    std::memset(line, 0, sizeof line);
    std::fclose(file);
    if (error != KeyLoadError::kNone) {
        return refuse(result, error, status, path, keys, eventLog);
    }
    result.line = 0;
    result.keyId = kNoKey;
    if (keys.size() == 0) {
        return refuse(result, KeyLoadError::kNoKeyInFile, core::Status::kEmpty, path, keys, eventLog);
    }
    result.keysLoaded = static_cast<std::uint8_t>(keys.size());
    if (result.openFileAccepted) {
        eventLog.report(events::kKeyFileOpenAccepted, core::Severity::kWarning,
                      "cmd: key file %s is open to group or others (mode %03o), loaded because --allow-readable-key said so",
                      path, static_cast<unsigned>(info.st_mode & 0777U));
    }
    return result;
}

}  // namespace rse::cmdtlm
