// Start-up: rse-fsw --key-file FILE into the command key store, with the checks
// a flight key file must pass (docs/icd.md §5.3, "Keys"). Any refusal leaves the
// store empty: a half-loaded key set is worse than none.
//
//   - the file must open, and be a regular file that neither group nor others
//     may read or write (kOpenToOthers), unless allowReadableFile (then event 517);
//   - every line is a key line "ID:64-hex-digits", a '#' comment or blank (kBadLine),
//     at most 255 characters (kBadLine);
//   - each key id once (kDuplicateKeyId), at most kMaxKeys keys (kTooManyKeys), at
//     least one (kNoKeyInFile);
//   - the public lab key's bytes, under any id, only with labKeyAllowed (kLabKeyRefused);
//   - no weak key (keyWeakness: all zero, all equal, < 8 distinct bytes) unless
//     weakKeyAllowed (then event 516); else kWeakKeyRefused.
// A refusal raises event 515 and returns its reason; the caller exits.
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/status.hpp"

namespace rse::cmdtlm {

struct KeyLoadOptions {
    bool labKeyAllowed = false;      // rse-fsw --lab-key
    bool weakKeyAllowed = false;     // rse-fsw --allow-weak-key
    bool readableFileAllowed = false;  // rse-fsw --allow-readable-key
};

enum class KeyLoadError : std::uint8_t {
    kNone,
    kCannotOpen,       // fopen/fstat failed (osError)
    kNotRegularFile,
    kOpenToOthers,     // group or others may read or write it
    kBadLine,          // line: not a key line, or too long
    kDuplicateKeyId,   // line, keyId
    kTooManyKeys,      // line, keyId
    kNoKeyInFile,
    kLabKeyRefused,    // line, keyId
    kWeakKeyRefused,   // line, keyId, weakness
};
const char* toString(KeyLoadError error);

struct KeyLoadResult {
    core::Status status = core::Status::kOk;
    KeyLoadError error = KeyLoadError::kNone;
    unsigned line = 0;               // the line refused, 1-based
    std::uint16_t keyId = kNoKey;    // the key refused
    KeyWeakness weakness = KeyWeakness::kNone;
    int osError = 0;                 // errno for kCannotOpen
    std::uint8_t keysLoaded = 0;
    std::uint8_t weakKeysAccepted = 0;  // loaded under weakKeyAllowed
    bool openFileAccepted = false;      // loaded under readableFileAllowed
};

// Replaces the store's keys with the file's (path must name the file).
KeyLoadResult loadKeyFile(const char* path, const KeyLoadOptions& options, KeyStore& keys, core::EventLog& eventLog);

}  // namespace rse::cmdtlm
