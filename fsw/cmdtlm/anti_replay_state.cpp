#include "fsw/cmdtlm/anti_replay_state.hpp"

#include "fsw/core/byte_codec.hpp"
#include "fsw/core/crc32.hpp"

namespace rse::cmdtlm {

const char* toString(AuthStoreState state) {
    switch (state) {
        case AuthStoreState::kVolatile: return "volatile";
        case AuthStoreState::kOk: return "ok";
        case AuthStoreState::kMissing: return "missing";
        case AuthStoreState::kCorrupt: return "corrupt";
        case AuthStoreState::kUnreadable: return "unreadable";
    }
    return "?";
}

std::size_t encodeAuthStore(const AuthStoreEntry* entries, std::size_t count, std::uint8_t* out,
                            std::size_t capacity) {
    if (count > kMaxStoredKeys) {
        return 0;
    }
    core::BeWriter w(out, capacity);
    w.u32(kAuthStoreMagic);
    w.u16(kAuthStoreVersion);
    w.u16(static_cast<std::uint16_t>(count));
    for (std::size_t i = 0; i < count; ++i) {
        w.u16(entries[i].keyId);
        w.u32(entries[i].reserved);
    }
    if (!w.ok()) {
        return 0;
    }
    const std::uint32_t crc = core::crc32(out, w.size());
    w.u32(crc);
    return w.ok() ? w.size() : 0;
}

core::Status decodeAuthStore(const std::uint8_t* data, std::size_t length, AuthStoreEntry* entries,
                             std::size_t* count) {
    if (data == nullptr || length < kAuthStoreHeaderBytes + 4) {
        return core::Status::kProtocolError;
    }
    core::BeReader r(data, length);
    const std::uint32_t magic = r.u32();
    const std::uint16_t version = r.u16();
    const std::uint16_t n = r.u16();
    if (magic != kAuthStoreMagic || version != kAuthStoreVersion) {
        return core::Status::kProtocolError;
    }
    if (n > kMaxStoredKeys) {
        return core::Status::kTooLarge;
    }
    if (length != kAuthStoreHeaderBytes + static_cast<std::size_t>(n) * kAuthStoreEntryBytes + 4) {
        return core::Status::kProtocolError;
    }
    AuthStoreEntry read[kMaxStoredKeys];
    for (std::size_t i = 0; i < n; ++i) {
        read[i].keyId = r.u16();
        read[i].reserved = r.u32();
        if (read[i].keyId == kNoKey) {
            return core::Status::kProtocolError;
        }
        for (std::size_t j = 0; j < i; ++j) {
            if (read[j].keyId == read[i].keyId) {
                return core::Status::kProtocolError;  // one entry per key
            }
        }
    }
    const std::size_t covered = r.position();
    const std::uint32_t crc = r.u32();
    if (!r.ok() || crc != core::crc32(data, covered)) {
        return core::Status::kProtocolError;
    }
    for (std::size_t i = 0; i < n; ++i) {
        entries[i] = read[i];
    }
    *count = n;
    return core::Status::kOk;
}

AuthStoreEntry* AntiReplayState::entry(std::uint16_t keyId) {
    return const_cast<AuthStoreEntry*>(static_cast<const AntiReplayState*>(this)->entry(keyId));
}

const AuthStoreEntry* AntiReplayState::entry(std::uint16_t keyId) const {
    for (std::size_t i = 0; i < count_; ++i) {
        if (entries_[i].keyId == keyId) {
            return &entries_[i];
        }
    }
    return nullptr;
}

void AntiReplayState::load(KeyStore& keys, bool provision) {
    count_ = 0;
    if (store_ == nullptr) {
        state_ = AuthStoreState::kVolatile;
        return;
    }
    std::uint8_t buffer[kAuthStoreMaxBytes];
    std::size_t length = 0;
    const core::Status read = store_->read(buffer, sizeof buffer, &length);
    if (read == core::Status::kNotFound) {
        state_ = AuthStoreState::kMissing;
    } else if (read == core::Status::kTooLarge) {
        state_ = AuthStoreState::kCorrupt;
    } else if (!core::isOk(read)) {
        state_ = AuthStoreState::kUnreadable;
    } else if (!core::isOk(decodeAuthStore(buffer, length, entries_, &count_))) {
        count_ = 0;
        state_ = AuthStoreState::kCorrupt;
    } else {
        state_ = AuthStoreState::kOk;
    }
    // Provisioning adds what is missing and never touches what exists: entries
    // already stored keep their reservation, a corrupt store stays as it is.
    if (provision && (state_ == AuthStoreState::kOk || state_ == AuthStoreState::kMissing)) {
        AuthStoreEntry next[kMaxStoredKeys];
        std::size_t n = count_;
        for (std::size_t i = 0; i < count_; ++i) {
            next[i] = entries_[i];
        }
        for (std::size_t k = 0; k < keys.size(); ++k) {
            const std::uint16_t id = keys.idAt(k);
            if (entry(id) == nullptr && n < kMaxStoredKeys) {
                next[n].keyId = id;
                next[n].reserved = 0;
                ++n;
            }
        }
        if (n != count_ || state_ == AuthStoreState::kMissing) {
            std::uint8_t out[kAuthStoreMaxBytes];
            const std::size_t bytes = encodeAuthStore(next, n, out, sizeof out);
            lastWriteStatus_ = bytes == 0 ? core::Status::kTooLarge : store_->write(out, bytes);
            if (core::isOk(lastWriteStatus_)) {
                ++writes_;
                for (std::size_t i = 0; i < n; ++i) {
                    entries_[i] = next[i];
                }
                count_ = n;
                state_ = AuthStoreState::kOk;
            } else {
                ++writeFailures_;
            }
        }
    }
    for (std::size_t k = 0; k < keys.size(); ++k) {
        const AuthStoreEntry* e = entry(keys.idAt(k));
        if (e != nullptr) {
            keys.setFloor(e->keyId, e->reserved);
        }
    }
}

Unsynced AntiReplayState::unsynced(std::uint16_t keyId) const {
    if (store_ == nullptr || entry(keyId) != nullptr) {
        return Unsynced::kSynced;
    }
    switch (state_) {
        case AuthStoreState::kMissing: return Unsynced::kStoreMissing;
        case AuthStoreState::kCorrupt: return Unsynced::kStoreCorrupt;
        case AuthStoreState::kUnreadable: return Unsynced::kStoreUnreadable;
        case AuthStoreState::kVolatile:
        case AuthStoreState::kOk: break;
    }
    return Unsynced::kKeyNotStored;
}

std::uint32_t AntiReplayState::reserved(std::uint16_t keyId) const {
    const AuthStoreEntry* e = entry(keyId);
    return e == nullptr ? 0 : e->reserved;
}

void AntiReplayState::attach(hal::RecordStore* store, hal::RecordWriter* writer) {
    store_ = store;
    immediate_.bind(store);
    writer_ = writer != nullptr ? writer : &immediate_;
}

core::Status AntiReplayState::postWith(std::uint16_t keyId, std::uint32_t reserved) {
    AuthStoreEntry next[kMaxStoredKeys];
    std::size_t n = count_;
    bool found = false;
    for (std::size_t i = 0; i < count_; ++i) {
        next[i] = entries_[i];
        if (next[i].keyId == keyId) {
            next[i].reserved = reserved;
            found = true;
        }
    }
    core::Status status = core::Status::kOk;
    if (!found) {
        if (n >= kMaxStoredKeys) {
            status = core::Status::kNoCapacity;
        } else {
            next[n].keyId = keyId;
            next[n].reserved = reserved;
            ++n;
        }
    }
    std::uint8_t out[kAuthStoreMaxBytes];
    if (core::isOk(status)) {
        const std::size_t bytes = encodeAuthStore(next, n, out, sizeof out);
        status = bytes == 0 ? core::Status::kTooLarge : writer_->post(out, bytes);
    }
    if (status == core::Status::kBusy) {
        return status;
    }
    if (!core::isOk(status)) {
        lastWriteStatus_ = status;
        ++writeFailures_;
        return status;
    }
    for (std::size_t i = 0; i < n; ++i) {
        posted_[i] = next[i];
    }
    postedCount_ = n;
    postedKey_ = keyId;
    inFlight_ = true;
    return core::Status::kOk;
}

void AntiReplayState::service() {
    core::Status result = core::Status::kOk;
    if (!inFlight_ || !writer_->takeResult(&result)) {
        return;
    }
    inFlight_ = false;
    lastWriteStatus_ = result;
    const bool forCommand = postedForCommand_;
    postedForCommand_ = false;
    if (!core::isOk(result)) {
        ++writeFailures_;
        // A command waits for this write: it is refused. A failed renewal refuses
        // nothing (the durable reservation still covers what it covered).
        failedKey_ = forCommand ? postedKey_ : kNoKey;
        return;
    }
    ++writes_;
    for (std::size_t i = 0; i < postedCount_; ++i) {
        entries_[i] = posted_[i];
    }
    count_ = postedCount_;
    state_ = AuthStoreState::kOk;  // the record on the medium is valid (again)
    failedKey_ = kNoKey;
}

core::Status AntiReplayState::reach(std::uint16_t keyId, std::uint32_t reserved) {
    service();
    const AuthStoreEntry* e = entry(keyId);
    if (e != nullptr && e->reserved >= reserved) {
        return core::Status::kOk;
    }
    if (inFlight_) {
        return core::Status::kBusy;  // it may cover this one: asked again next frame
    }
    if (failedKey_ == keyId) {
        failedKey_ = kNoKey;  // the write posted for this command failed: refused, the next one tries again
        return lastWriteStatus_;
    }
    const core::Status posted = postWith(keyId, reserved);
    if (!core::isOk(posted)) {
        return posted;  // kBusy only if the writer is still busy with a write we no longer track
    }
    postedForCommand_ = true;
    service();  // an immediate writer has finished already
    e = entry(keyId);
    if (e != nullptr && e->reserved >= reserved) {
        return core::Status::kOk;
    }
    if (failedKey_ == keyId) {
        failedKey_ = kNoKey;
        return lastWriteStatus_;
    }
    return core::Status::kBusy;
}

core::Status AntiReplayState::reserve(std::uint16_t keyId, std::uint32_t sequence) {
    if (store_ == nullptr) {
        return core::Status::kOk;
    }
    if (sequence > kMaxUsableSequence) {
        return core::Status::kInvalidArgument;
    }
    service();
    const AuthStoreEntry* e = entry(keyId);
    if (e == nullptr) {
        return core::Status::kNotFound;  // an unsynchronised key: refused before this
    }
    if (sequence <= e->reserved) {
        // Covered. Near the end of the block, the next reservation goes out now,
        // so the command that needs it finds it durable.
        if (e->reserved - sequence < kRenewMargin && !inFlight_) {
            (void)postWith(keyId, sequence + kReserveBlock);  // a failure is counted; the command is covered
        }
        return core::Status::kOk;
    }
    return reach(keyId, sequence + kReserveBlock);
}

core::Status AntiReplayState::resync(std::uint16_t keyId, std::uint32_t newFloor) {
    if (store_ == nullptr) {
        return core::Status::kOk;
    }
    if (newFloor > kMaxUsableSequence) {
        return core::Status::kInvalidArgument;
    }
    return reach(keyId, newFloor + kReserveBlock);
}

}  // namespace rse::cmdtlm
