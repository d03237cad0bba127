// RecordStore on a POSIX file system (hal/nvm/record_store.hpp): the record is
// the whole file PATH. A write goes to PATH.tmp (created 0600), is fsync'ed,
// renamed over PATH (rename is atomic) and the directory is fsync'ed, so after
// a crash or power cut PATH holds the old record or the new one, whole. A
// missing PATH reads as kNotFound; other errors as kUnavailable with the errno
// kept in lastErrno(). No events here: the caller (the command service) raises
// them and counts.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "hal/nvm/record_store.hpp"

namespace rse::hal {

class FileRecordStore final : public RecordStore {
public:
    static constexpr std::size_t kMaxPath = 240;

    // kInvalidArgument for an empty path or one longer than kMaxPath. Touches nothing on disk.
    core::Status open(const char* path);
    const char* path() const { return path_; }

    core::Status read(std::uint8_t* buffer, std::size_t capacity, std::size_t* length) override;
    core::Status write(const std::uint8_t* data, std::size_t length) override;

    int lastErrno() const { return lastErrno_; }
    std::uint32_t writes() const { return writes_; }
    std::uint32_t failures() const { return failures_; }

private:
    core::Status fail(int error);

    char path_[kMaxPath + 1] = {};
    char tmpPath_[kMaxPath + 5] = {};
    char dirPath_[kMaxPath + 1] = {};
    bool open_ = false;
    int lastErrno_ = 0;
    std::uint32_t writes_ = 0;
    std::uint32_t failures_ = 0;
};

// 8 bytes from the kernel's random source (getrandom(2)), for start-up nonces.
// kUnavailable (errno in *error) when the kernel cannot supply them.
core::Status readRandom64(std::uint64_t* value, int* error);

}  // namespace rse::hal
