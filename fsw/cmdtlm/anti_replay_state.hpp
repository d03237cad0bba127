// The anti-replay state that outlives a restart (docs/icd.md, "Anti-replay").
//
// In RAM, per key, the KeyStore keeps the sliding window (highest number
// accepted, which of the 64 below it were seen). This class makes it hold across
// restarts and power cycles with a persisted reservation per key, the design of
// Thread/Zigbee frame counters and of SDLS's non-volatile ARSN:
//
//   - The store (hal::RecordStore, a file by default) holds, per key, a
//     reservation R: no number above R has ever been accepted.
//   - Start-up: every number up to R is refused for that key (the window's floor
//     becomes R, all 64 below it taken as seen).
//   - A number s is accepted only when s <= R on the medium. For s > R the
//     reservation R = s + kReserveBlock is written first (atomic replace), and
//     only once it is durable is s recorded and the command acted on. A crash at
//     any point can only skip numbers, never reopen one: the stored R is always
//     >= every number accepted. A failed write refuses the command
//     (sequence_store_failed).
//   - Writes never block the command task (hal/nvm/record_writer.hpp): the
//     record is posted to a writer and reserve() answers kBusy until it is
//     durable; the command waits at the head of its queue meanwhile (a frame or
//     two with the file store). So that this wait is rare, a number within
//     kRenewMargin of R posts the next reservation (s + kReserveBlock) ahead of
//     need, without waiting. Writes: at most about one per kReserveBlock -
//     kRenewMargin numbers per key (bounded write rate), one at a time.
//   - Numbers above kMaxUsableSequence are refused (sequence_exhausted): the
//     reservation s + kReserveBlock must fit in 32 bits. The key must be changed
//     before its numbers run out.
//   - A store that is missing, unreadable or corrupt (magic, version, length,
//     CRC-32), or that has no entry for a loaded key, fails safe: that key's
//     commands are refused (sequence_unsynchronised, detail why) until the ground
//     re-synchronises it with AUTH_RESYNC.
//   - AUTH_RESYNC is freshness by challenge, not by number: the rover draws a
//     64-bit nonce at start-up (kernel random source), shows it in HK
//     (auth_challenge_high/low) and accepts AUTH_RESYNC only when its arguments
//     (covered by the MAC) carry that nonce. A captured AUTH_RESYNC carries an
//     old nonce and is refused; after each accepted one the nonce changes. The
//     key's floor becomes the AUTH_RESYNC's own sequence number (never lower
//     than the floor already in force): the ground signs it with a number above
//     every number it has used, so every captured command is below the floor.
//
// Without a store attached (unit tests that never restart) the state is
// volatile: the window lives in RAM only, as before. rse-fsw always attaches a
// file (--auth-store), the lockstep rig a MemoryRecordStore.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/core/status.hpp"
#include "hal/nvm/record_store.hpp"
#include "hal/nvm/record_writer.hpp"

namespace rse::cmdtlm {

constexpr std::uint32_t kReserveBlock = 1024;                            // numbers reserved per store write
constexpr std::uint32_t kRenewMargin = kReserveBlock / 2;                // renew when this close to R
constexpr std::uint32_t kMaxUsableSequence = 0xFFFFFFFFu - kReserveBlock;  // highest number accepted
constexpr std::size_t kMaxStoredKeys = 8;                                // entries in the store
constexpr std::uint32_t kAuthStoreMagic = 0x52534541;                    // "RSEA"
constexpr std::uint16_t kAuthStoreVersion = 1;
// magic 4, version 2, count 2, count x (key id 2, reservation 4), CRC-32 4
constexpr std::size_t kAuthStoreHeaderBytes = 8;
constexpr std::size_t kAuthStoreEntryBytes = 6;
constexpr std::size_t kAuthStoreMaxBytes = kAuthStoreHeaderBytes + kMaxStoredKeys * kAuthStoreEntryBytes + 4;

// HK.auth_store_state.
enum class AuthStoreState : std::uint8_t {
    kVolatile = 0,    // no store attached: RAM only (tests, lockstep)
    kOk = 1,          // read (or created) and valid
    kMissing = 2,     // no record: every key refused until AUTH_RESYNC
    kCorrupt = 3,     // bad magic, version, length or CRC: every key refused until AUTH_RESYNC
    kUnreadable = 4,  // the medium could not be read: every key refused until AUTH_RESYNC
};
const char* toString(AuthStoreState state);

// CMD_ACK.detail of sequence_unsynchronised: why the key is refused.
enum class Unsynced : std::int16_t {
    kSynced = 0,
    kStoreMissing = 1,
    kStoreCorrupt = 2,
    kKeyNotStored = 3,       // the store is valid but has no entry for this key
    kChallengeMismatch = 4,  // AUTH_RESYNC with a nonce that is not the current one
    kStoreUnreadable = 5,
    kNoChallenge = 6,        // AUTH_RESYNC, but no nonce could be drawn at start-up
};

struct AuthStoreEntry {
    std::uint16_t keyId = kNoKey;
    std::uint32_t reserved = 0;
};

// The record: big-endian, CRC-32 (core::crc32) over everything before it.
std::size_t encodeAuthStore(const AuthStoreEntry* entries, std::size_t count, std::uint8_t* out,
                            std::size_t capacity);
// kProtocolError for a bad magic, version, length or CRC; kTooLarge for more than kMaxStoredKeys.
core::Status decodeAuthStore(const std::uint8_t* data, std::size_t length, AuthStoreEntry* entries,
                             std::size_t* count);

class AntiReplayState {
public:
    // Before load(). store nullptr: volatile. The store is read (and, when
    // provisioning, written) in load(); every later write goes through `writer`,
    // which must write to the same store. writer nullptr: an ImmediateRecordWriter
    // on the store (writes inside the command task: tests, the lockstep rig).
    void attach(hal::RecordStore* store, hal::RecordWriter* writer = nullptr);
    bool persistent() const { return store_ != nullptr; }

    // Start-up, after the keys are loaded: reads the store and sets each synced
    // key's floor in `keys`. provision: a missing store is created, and a valid
    // store gets an entry for each loaded key it lacks, at reservation 0 (the
    // explicit first-boot step, rse-fsw --auth-store-create). A corrupt or
    // unreadable store is never overwritten here.
    void load(KeyStore& keys, bool provision);
    AuthStoreState state() const { return state_; }

    // kSynced, or why commands of this key are refused.
    Unsynced unsynced(std::uint16_t keyId) const;
    // The reservation stored for the key (0 if none).
    std::uint32_t reserved(std::uint16_t keyId) const;

    // Takes the result of a finished write (durable: the reservations it carried
    // are in force; failed: counted). Called every frame by the command task and
    // by reserve() and resync().
    void service();
    bool writeInFlight() const { return inFlight_; }

    // Before accepting `sequence` (fresh, <= kMaxUsableSequence). kOk: the
    // durable reservation covers it (and the next one is posted when it is within
    // kRenewMargin). kBusy: a write that will cover it is posted or waits for the
    // one in flight; ask again next frame. Anything else: the write failed
    // (counted), the command must be refused.
    core::Status reserve(std::uint16_t keyId, std::uint32_t sequence);
    // AUTH_RESYNC: the key's floor becomes `newFloor` (the reservation becomes
    // newFloor + kReserveBlock, never lower than the one in force). Same answers
    // as reserve(): act on the command only after kOk.
    core::Status resync(std::uint16_t keyId, std::uint32_t newFloor);

    // The AUTH_RESYNC nonce. Without a seed there is none and AUTH_RESYNC is refused.
    void setChallengeSeed(std::uint64_t seed) { challenge_ = seed; challengeReady_ = true; }
    bool challengeReady() const { return challengeReady_; }
    std::uint64_t challenge() const { return challengeReady_ ? challenge_ : 0; }
    void nextChallenge() { ++challenge_; }  // a nonce: never repeats, need not be secret

    std::uint32_t writes() const { return writes_; }
    std::uint32_t writeFailures() const { return writeFailures_; }
    core::Status lastWriteStatus() const { return lastWriteStatus_; }

private:
    AuthStoreEntry* entry(std::uint16_t keyId);
    const AuthStoreEntry* entry(std::uint16_t keyId) const;
    // Posts entries_ with `keyId` set to `reserved` (added when absent);
    // entries_ change only once that write is durable (service()).
    core::Status postWith(std::uint16_t keyId, std::uint32_t reserved);
    // Until entry(keyId) covers `reserved`: posts the write (or waits for the one
    // in flight) and answers kBusy, or reports the failure of the write posted for it.
    core::Status reach(std::uint16_t keyId, std::uint32_t reserved);

    hal::RecordStore* store_ = nullptr;
    hal::RecordWriter* writer_ = nullptr;
    hal::ImmediateRecordWriter immediate_;
    // The write in flight: the whole table it carries.
    bool inFlight_ = false;
    AuthStoreEntry posted_[kMaxStoredKeys] = {};
    std::size_t postedCount_ = 0;
    std::uint16_t postedKey_ = kNoKey;  // the key it was posted for
    bool postedForCommand_ = false;    // a command waits for it (not a renewal)
    // The key whose command's write failed, until that command is refused for it.
    std::uint16_t failedKey_ = kNoKey;
    AuthStoreState state_ = AuthStoreState::kVolatile;
    AuthStoreEntry entries_[kMaxStoredKeys] = {};
    std::size_t count_ = 0;
    std::uint64_t challenge_ = 0;
    bool challengeReady_ = false;
    std::uint32_t writes_ = 0;
    std::uint32_t writeFailures_ = 0;
    core::Status lastWriteStatus_ = core::Status::kOk;
};

}  // namespace rse::cmdtlm
