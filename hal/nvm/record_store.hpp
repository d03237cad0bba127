// A small persistent record (hal/nvm): one block of bytes that survives a
// restart and a power cycle, replaced whole and atomically. The command service
// keeps its anti-replay reservations in one (fsw/cmdtlm/anti_replay_state.hpp).
//
//   read():  kOk with the bytes; kNotFound when no record was ever written (or it
//            was removed); kTooLarge when the record exceeds the caller's buffer;
//            kUnavailable when the medium could not be read.
//   write(): returns only once the new record is durable; kOk means a restart,
//            even a power cut right after the call, reads exactly these bytes. On
//            any failure the previous record is either still there whole or
//            replaced whole - never a mix.
//
// Blocking: a write is a blocking call (a file: write, fsync, rename, fsync of the
// directory). Callers bound how often they write.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

#include "fsw/core/status.hpp"

namespace rse::hal {

class RecordStore {
public:
    virtual ~RecordStore() = default;
    virtual core::Status read(std::uint8_t* buffer, std::size_t capacity, std::size_t* length) = 0;
    virtual core::Status write(const std::uint8_t* data, std::size_t length) = 0;
};

// In memory, for tests and the lockstep rig: a "restart" is a new reader of the
// same object. Faults can be injected: writes refused, the record removed or
// replaced by arbitrary bytes.
class MemoryRecordStore final : public RecordStore {
public:
    static constexpr std::size_t kCapacity = 256;

    core::Status read(std::uint8_t* buffer, std::size_t capacity, std::size_t* length) override {
        ++reads_;
        if (!present_) {
            return core::Status::kNotFound;
        }
        if (length_ > capacity) {
            return core::Status::kTooLarge;
        }
        std::memcpy(buffer, bytes_, length_);
        *length = length_;
        return core::Status::kOk;
    }
    core::Status write(const std::uint8_t* data, std::size_t length) override {
        if (failWrites_ || length > kCapacity) {
            ++failedWrites_;
            return core::Status::kUnavailable;
        }
        std::memcpy(bytes_, data, length);
        length_ = length;
        present_ = true;
        ++writes_;
        return core::Status::kOk;
    }

    // Fault injection and inspection.
    void setFailWrites(bool fail) { failWrites_ = fail; }
    void erase() { present_ = false; length_ = 0; }
    void replace(const std::uint8_t* data, std::size_t length) {
        length_ = length < kCapacity ? length : kCapacity;
        std::memcpy(bytes_, data, length_);
        present_ = true;
    }
    bool present() const { return present_; }
    const std::uint8_t* bytes() const { return bytes_; }
    std::size_t length() const { return length_; }
    std::uint32_t writes() const { return writes_; }
    std::uint32_t failedWrites() const { return failedWrites_; }
    std::uint32_t reads() const { return reads_; }

private:
    std::uint8_t bytes_[kCapacity] = {};
    std::size_t length_ = 0;
    bool present_ = false;
    bool failWrites_ = false;
    std::uint32_t writes_ = 0;
    std::uint32_t failedWrites_ = 0;
    std::uint32_t reads_ = 0;
};

}  // namespace rse::hal
