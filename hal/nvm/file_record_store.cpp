#include "hal/nvm/file_record_store.hpp"

#include <fcntl.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>

namespace rse::hal {

core::Status FileRecordStore::open(const char* path) {
    if (path == nullptr || path[0] == '\0' || std::strlen(path) > kMaxPath) {
        return core::Status::kInvalidArgument;
    }
    std::snprintf(path_, sizeof path_, "%s", path);
    std::snprintf(tmpPath_, sizeof tmpPath_, "%s.tmp", path);
    // The directory to fsync after the rename: everything before the last '/'.
    const char* slash = std::strrchr(path_, '/');
    if (slash == nullptr) {
        std::snprintf(dirPath_, sizeof dirPath_, ".");
    } else if (slash == path_) {
        std::snprintf(dirPath_, sizeof dirPath_, "/");
    } else {
        std::snprintf(dirPath_, sizeof dirPath_, "%.*s", static_cast<int>(slash - path_), path_);
    }
    open_ = true;
    return core::Status::kOk;
}

core::Status FileRecordStore::fail(int error) {
    lastErrno_ = error;
    ++failures_;
    return core::Status::kUnavailable;
}

core::Status FileRecordStore::read(std::uint8_t* buffer, std::size_t capacity, std::size_t* length) {
    if (!open_) {
        return core::Status::kNotInitialized;
    }
    const int fd = ::open(path_, O_RDONLY | O_CLOEXEC);
    if (fd < 0) {
        if (errno == ENOENT) {
            lastErrno_ = ENOENT;
            return core::Status::kNotFound;
        }
        return fail(errno);
    }
    std::size_t total = 0;
    std::uint8_t extra = 0;
    core::Status status = core::Status::kOk;
    for (;;) {
        // One byte past the capacity tells "too large" from "exactly full".
        std::uint8_t* into = total < capacity ? buffer + total : &extra;
        const std::size_t want = total < capacity ? capacity - total : 1;
        const ssize_t n = ::read(fd, into, want);
        if (n < 0) {
            if (errno == EINTR) {
                continue;
            }
            status = fail(errno);
            break;
        }
        if (n == 0) {
            break;
        }
        if (total >= capacity) {
            status = core::Status::kTooLarge;
            break;
        }
        total += static_cast<std::size_t>(n);
    }
    ::close(fd);
    if (core::isOk(status)) {
        *length = total;
    }
    return status;
}

core::Status FileRecordStore::write(const std::uint8_t* data, std::size_t length) {
    if (!open_) {
        return core::Status::kNotInitialized;
    }
    const int fd = ::open(tmpPath_, O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) {
        return fail(errno);
    }
    std::size_t done = 0;
    while (done < length) {
        const ssize_t n = ::write(fd, data + done, length - done);
        if (n < 0 && errno == EINTR) {
            continue;
        }
        if (n <= 0) {
            const int error = n < 0 ? errno : EIO;
            ::close(fd);
            (void)::unlink(tmpPath_);
            return fail(error);
        }
        done += static_cast<std::size_t>(n);
    }
    if (::fsync(fd) != 0) {
        const int error = errno;
        ::close(fd);
        (void)::unlink(tmpPath_);
        return fail(error);
    }
    if (::close(fd) != 0) {
        const int error = errno;
        (void)::unlink(tmpPath_);
        return fail(error);
    }
    if (::rename(tmpPath_, path_) != 0) {
        const int error = errno;
        (void)::unlink(tmpPath_);
        return fail(error);
    }
    // The rename itself is durable only once the directory is.
    const int dir = ::open(dirPath_, O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir < 0) {
        return fail(errno);
    }
    const int synced = ::fsync(dir);
    const int error = errno;
    ::close(dir);
    if (synced != 0) {
        return fail(error);
    }
    ++writes_;
    return core::Status::kOk;
}

core::Status readRandom64(std::uint64_t* value, int* error) {
    std::uint8_t bytes[sizeof(std::uint64_t)];
    ssize_t n = -1;
    do {
        n = ::getrandom(bytes, sizeof bytes, 0);
    } while (n < 0 && errno == EINTR);
    if (n != static_cast<ssize_t>(sizeof bytes)) {
        *error = n < 0 ? errno : EIO;
        return core::Status::kUnavailable;
    }
    std::uint64_t v = 0;
    for (std::uint8_t b : bytes) {
        v = (v << 8) | b;
    }
    *value = v;
    return core::Status::kOk;
}

}  // namespace rse::hal
