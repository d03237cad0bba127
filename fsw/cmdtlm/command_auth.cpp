#include "fsw/cmdtlm/command_auth.hpp"

#include <cctype>
#include <cstring>

namespace rse::cmdtlm {

// 32 bytes, "RSE lab key - not for flight use" in ASCII: recognisable in a dump.
const std::uint8_t kLabKey[kKeySize] = {'R', 'S', 'E', ' ', 'l', 'a', 'b', ' ', 'k', 'e', 'y',
                                        ' ', '-', ' ', 'n', 'o', 't', ' ', 'f', 'o', 'r', ' ',
                                        'f', 'l', 'i', 'g', 'h', 't', ' ', 'u', 's', 'e'};

bool isLabKey(const std::uint8_t key[kKeySize]) {
    return key != nullptr && std::memcmp(key, kLabKey, kKeySize) == 0;
}

KeyWeakness keyWeakness(const std::uint8_t key[kKeySize]) {
    bool seen[256] = {};
    std::size_t distinct = 0;
    bool allZero = true;
    for (std::size_t i = 0; i < kKeySize; ++i) {
        allZero = allZero && key[i] == 0;
        if (!seen[key[i]]) {
            seen[key[i]] = true;
            ++distinct;
        }
    }
    if (allZero) {
        return KeyWeakness::kAllZero;
    }
    if (distinct == 1) {
        return KeyWeakness::kAllEqual;
    }
    return distinct < kMinDistinctKeyBytes ? KeyWeakness::kFewDistinct : KeyWeakness::kNone;
}

const char* toString(KeyWeakness weakness) {
    switch (weakness) {
        case KeyWeakness::kNone: return "none";
        case KeyWeakness::kAllZero: return "all bytes zero";
        case KeyWeakness::kAllEqual: return "all bytes equal";
        case KeyWeakness::kFewDistinct: return "fewer than 8 distinct byte values";
    }
    return "?";
}

HmacSha256::HmacSha256() { mbedtls_md_init(&context_); }

HmacSha256::~HmacSha256() { mbedtls_md_free(&context_); }

core::Status HmacSha256::init() {
    if (ready_) {
        return core::Status::kOk;
    }
    const mbedtls_md_info_t* info = mbedtls_md_info_from_type(MBEDTLS_MD_SHA256);
    if (info == nullptr || mbedtls_md_setup(&context_, info, 1) != 0) {
        return core::Status::kUnavailable;
    }
    ready_ = true;
    return core::Status::kOk;
}

core::Status HmacSha256::compute(const std::uint8_t* key, std::size_t keyLength, const Part* parts,
                                 std::size_t partCount, std::uint8_t out[kHmacSha256Size]) {
    if (!ready_) {
        return core::Status::kNotInitialized;
    }
    if (key == nullptr || out == nullptr || (parts == nullptr && partCount > 0)) {
        return core::Status::kInvalidArgument;
    }
    for (std::size_t i = 0; i < partCount; ++i) {
        if (parts[i].data == nullptr && parts[i].length > 0) {
            return core::Status::kInvalidArgument;
        }
    }
    if (mbedtls_md_hmac_starts(&context_, key, keyLength) != 0) {
        return core::Status::kProtocolError;
    }
    for (std::size_t i = 0; i < partCount; ++i) {
        if (parts[i].length > 0 && mbedtls_md_hmac_update(&context_, parts[i].data, parts[i].length) != 0) {
            return core::Status::kProtocolError;
        }
    }
    return mbedtls_md_hmac_finish(&context_, out) == 0 ? core::Status::kOk : core::Status::kProtocolError;
}

core::Status HmacSha256::compute(const std::uint8_t* key, std::size_t keyLength, const std::uint8_t* data,
                                 std::size_t length, std::uint8_t out[kHmacSha256Size]) {
    const Part part{data, length};
    return compute(key, keyLength, &part, 1, out);
}

core::Status HmacSha256::packetMac(const std::uint8_t key[kKeySize], const std::uint8_t* packet,
                                   std::size_t length, std::uint8_t mac[kMacSize]) {
    if (!ready_) {
        return core::Status::kNotInitialized;
    }
    if (packet == nullptr || mac == nullptr || length <= kChecksumOffset) {
        return core::Status::kInvalidArgument;
    }
    const std::uint8_t zero = 0;
    const Part parts[] = {{packet, kChecksumOffset},
                          {&zero, 1},
                          {packet + kChecksumOffset + 1, length - kChecksumOffset - 1}};
    std::uint8_t full[kHmacSha256Size];
    const core::Status status = compute(key, kKeySize, parts, sizeof parts / sizeof parts[0], full);
    if (core::isOk(status)) {
        std::memcpy(mac, full, kMacSize);
    }
    return status;
}

bool macEqual(const std::uint8_t a[kMacSize], const std::uint8_t b[kMacSize]) {
    std::uint8_t difference = 0;
    for (std::size_t i = 0; i < kMacSize; ++i) {
        difference = static_cast<std::uint8_t>(difference | (a[i] ^ b[i]));
    }
    return difference == 0;
}

core::Status KeyStore::add(std::uint16_t keyId, const std::uint8_t key[kKeySize]) {
    if (keyId == kNoKey || key == nullptr) {
        return core::Status::kInvalidArgument;
    }
    Slot* s = slot(keyId);
    if (s == nullptr) {
        if (count_ >= kMaxKeys) {
            return core::Status::kFull;
        }
        s = &slots_[count_++];
    }
    *s = Slot{};
    s->id = keyId;
    std::memcpy(s->key, key, kKeySize);
    return core::Status::kOk;
}

void KeyStore::clear() {
    for (Slot& s : slots_) {
        s = Slot{};
    }
    count_ = 0;
}

std::uint16_t KeyStore::labKeyId() const {
    for (std::size_t i = 0; i < count_; ++i) {
        if (isLabKey(slots_[i].key)) {
            return slots_[i].id;
        }
    }
    return kNoKey;
}

const KeyStore::Slot* KeyStore::slot(std::uint16_t keyId) const {
    for (std::size_t i = 0; i < count_; ++i) {
        if (slots_[i].id == keyId) {
            return &slots_[i];
        }
    }
    return nullptr;
}

KeyStore::Slot* KeyStore::slot(std::uint16_t keyId) {
    return const_cast<Slot*>(static_cast<const KeyStore*>(this)->slot(keyId));
}

const std::uint8_t* KeyStore::find(std::uint16_t keyId) const {
    const Slot* s = keyId == kNoKey ? nullptr : slot(keyId);
    return s == nullptr ? nullptr : s->key;
}

// A sliding window as in IPsec/SDLS anti-replay: a number above the highest is
// fresh; one within the window below it is fresh once; older ones are stale.
KeyStore::Freshness KeyStore::check(std::uint16_t keyId, std::uint32_t sequence) const {
    const Slot* s = slot(keyId);
    if (s == nullptr || !s->anySeen || sequence > s->highest) {
        return Freshness::kFresh;
    }
    const std::uint32_t behind = s->highest - sequence;
    if (behind >= kReplayWindow) {
        return Freshness::kStale;
    }
    return (s->seenMask >> behind) & 1U ? Freshness::kReplayed : Freshness::kFresh;
}

void KeyStore::commit(std::uint16_t keyId, std::uint32_t sequence) {
    Slot* s = slot(keyId);
    if (s == nullptr) {
        return;
    }
    if (!s->anySeen) {
        s->anySeen = true;
        s->highest = sequence;
        s->seenMask = 1;
        return;
    }
    if (sequence > s->highest) {
        const std::uint32_t ahead = sequence - s->highest;
        s->seenMask = ahead >= kReplayWindow ? 0 : s->seenMask << ahead;
        s->seenMask |= 1U;
        s->highest = sequence;
        return;
    }
    const std::uint32_t behind = s->highest - sequence;
    if (behind < kReplayWindow) {
        s->seenMask |= std::uint64_t{1} << behind;
    }
}

void KeyStore::setFloor(std::uint16_t keyId, std::uint32_t floorSequence) {
    Slot* s = slot(keyId);
    if (s == nullptr) {
        return;
    }
    s->anySeen = true;
    s->highest = floorSequence;
    s->seenMask = ~std::uint64_t{0};  // nothing below the floor is fresh
}

std::uint32_t KeyStore::lastSequence(std::uint16_t keyId) const {
    const Slot* s = slot(keyId);
    return s == nullptr ? 0 : s->highest;
}

core::Status parseKeyLine(const char* line, std::uint16_t* keyId, std::uint8_t key[kKeySize], bool* isKey) {
    *isKey = false;
    const char* p = line;
    while (*p == ' ' || *p == '\t') {
        ++p;
    }
    if (*p == '\0' || *p == '\n' || *p == '\r' || *p == '#') {
        return core::Status::kOk;
    }
    unsigned long id = 0;
    std::size_t digits = 0;
    while (std::isdigit(static_cast<unsigned char>(*p)) != 0 && digits < 6) {
        id = id * 10 + static_cast<unsigned long>(*p - '0');
        ++p;
        ++digits;
    }
    if (digits == 0 || id == 0 || id > 0xFFFF || *p != ':') {
        return core::Status::kInvalidArgument;
    }
    ++p;
    for (std::size_t i = 0; i < kKeySize; ++i) {
        unsigned value = 0;
        for (int half = 0; half < 2; ++half, ++p) {
            const int c = std::tolower(static_cast<unsigned char>(*p));
            unsigned nibble = 0;
            if (c >= '0' && c <= '9') {
                nibble = static_cast<unsigned>(c - '0');
            } else if (c >= 'a' && c <= 'f') {
                nibble = static_cast<unsigned>(c - 'a' + 10);
            } else {
                return core::Status::kInvalidArgument;
            }
            value = (value << 4) | nibble;
        }
        key[i] = static_cast<std::uint8_t>(value);
    }
    while (*p == ' ' || *p == '\t' || *p == '\r' || *p == '\n') {
        ++p;
    }
    if (*p != '\0' && *p != '#') {
        return core::Status::kInvalidArgument;
    }
    *keyId = static_cast<std::uint16_t>(id);
    *isKey = true;
    return core::Status::kOk;
}

}  // namespace rse::cmdtlm
