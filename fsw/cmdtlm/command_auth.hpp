// Command authentication in the spirit of CCSDS SDLS (355.0-B): each command
// names a key (key id, SDLS's SPI), carries a 32-bit anti-replay sequence
// number and ends in HMAC-SHA-256 truncated to 128 bits. The MAC covers the
// whole packet before it with the checksum byte taken as zero (so the checksum,
// computed last, can cover the MAC). Crypto is Debian's mbedTLS, not ours.
#pragma once

#include <cstddef>
#include <cstdint>

#include <mbedtls/md.h>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/core/status.hpp"

namespace rse::cmdtlm {

constexpr std::size_t kKeySize = 32;        // HMAC-SHA-256 keys are 256 bits here
constexpr std::size_t kMaxKeys = 4;         // key slots in the key store
constexpr std::uint32_t kReplayWindow = 64; // sequence numbers accepted out of order

constexpr std::size_t kHmacSha256Size = 32; // untruncated HMAC-SHA-256

// The lab key (key id 1 when rse-fsw --lab-key loads it). Anyone with this
// repository has it: it exists so a fresh checkout can command a lab rover. It is
// used only when asked for explicitly (rse-fsw --lab-key, FswApp::useLabKey);
// its bytes are recognised under any key id (isLabKey), and rse-fsw warns at
// start-up and HK.lab_key_in_use says so while it is loaded.
constexpr std::uint16_t kLabKeyId = 1;
extern const std::uint8_t kLabKey[kKeySize];
bool isLabKey(const std::uint8_t key[kKeySize]);

// A key too regular to be secret (docs/icd.md §5.3, "Keys"): all bytes zero, all
// bytes equal, or fewer than kMinDistinctKeyBytes distinct byte values among its
// 32 (a random key has about 30; fewer than 8 means a pattern or a typo).
constexpr std::size_t kMinDistinctKeyBytes = 8;
enum class KeyWeakness : std::uint8_t { kNone, kAllZero, kAllEqual, kFewDistinct };
KeyWeakness keyWeakness(const std::uint8_t key[kKeySize]);
const char* toString(KeyWeakness weakness);

// One HMAC-SHA-256 engine, used by flight and ground alike. init() allocates
// mbedTLS's context once, at start-up; computing a MAC afterwards allocates
// nothing. Every MAC, packetMac included, goes through compute(), the code the
// RFC 4231 known-answer tests check (unit_test/fsw/cmdtlm/test_hmac_sha256.cpp).
class HmacSha256 {
public:
    HmacSha256();
    ~HmacSha256();
    HmacSha256(const HmacSha256&) = delete;
    HmacSha256& operator=(const HmacSha256&) = delete;

    // Bytes fed to the MAC one after the other.
    struct Part {
        const std::uint8_t* data;
        std::size_t length;
    };

    core::Status init();
    // HMAC-SHA-256 (RFC 2104) with a key of any length over the concatenation of
    // parts. kNotInitialized before init(); kInvalidArgument for a null key, out
    // or parts, or a part with null data and a length; kProtocolError if mbedTLS fails.
    core::Status compute(const std::uint8_t* key, std::size_t keyLength, const Part* parts, std::size_t partCount,
                         std::uint8_t out[kHmacSha256Size]);
    core::Status compute(const std::uint8_t* key, std::size_t keyLength, const std::uint8_t* data,
                         std::size_t length, std::uint8_t out[kHmacSha256Size]);
    // The 128-bit MAC of packet[0..length) with the checksum byte taken as zero.
    core::Status packetMac(const std::uint8_t key[kKeySize], const std::uint8_t* packet, std::size_t length,
                           std::uint8_t mac[kMacSize]);

private:
    mbedtls_md_context_t context_;
    bool ready_ = false;
};

// Compares in time independent of where the first difference is.
bool macEqual(const std::uint8_t a[kMacSize], const std::uint8_t b[kMacSize]);

class KeyStore {
public:
    // kInvalidArgument for key id 0; kFull when every slot is taken; a known id is replaced.
    core::Status add(std::uint16_t keyId, const std::uint8_t key[kKeySize]);
    const std::uint8_t* find(std::uint16_t keyId) const;  // nullptr: unknown key
    std::size_t size() const { return count_; }
    std::uint16_t idAt(std::size_t index) const { return index < count_ ? slots_[index].id : kNoKey; }
    // The lab key's bytes are loaded, under whatever id (kNoKey: they are not).
    std::uint16_t labKeyId() const;
    bool labKeyInUse() const { return labKeyId() != kNoKey; }
    void clear();

    // Per-key anti-replay state, kept with the key.
    enum class Freshness : std::uint8_t { kFresh, kReplayed, kStale };
    Freshness check(std::uint16_t keyId, std::uint32_t sequence) const;
    void commit(std::uint16_t keyId, std::uint32_t sequence);  // after the MAC verified
    std::uint32_t lastSequence(std::uint16_t keyId) const;
    // Every number up to `floorSequence` is refused from now on (as replayed or stale):
    // the floor persisted across a restart, or set by AUTH_RESYNC.
    void setFloor(std::uint16_t keyId, std::uint32_t floorSequence);

private:
    struct Slot {
        std::uint16_t id = kNoKey;
        std::uint8_t key[kKeySize] = {};
        bool anySeen = false;
        std::uint32_t highest = 0;  // highest sequence accepted
        std::uint64_t seenMask = 0; // bit i: highest - i was accepted
    };
    const Slot* slot(std::uint16_t keyId) const;
    Slot* slot(std::uint16_t keyId);

    Slot slots_[kMaxKeys];
    std::size_t count_ = 0;
};

// Parses "ID:64-hex-digits" lines ('#' comments, blank lines allowed): the key
// file format of rse-fsw --key-file and rse-ground --key-file. Returns the line
// number of the first bad line in *badLine (0 if none) and kInvalidArgument.
core::Status parseKeyLine(const char* line, std::uint16_t* keyId, std::uint8_t key[kKeySize], bool* isKey);

}  // namespace rse::cmdtlm
