#include "ground/sequence_store.hpp"

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

namespace rse::ground {
namespace {

std::string errnoText() { return std::strerror(errno); }

// Holds an exclusive flock on DIR/.lock while it lives.
class DirectoryLock {
public:
    explicit DirectoryLock(const std::string& directory) {
        const std::string path = directory + "/.lock";
        fd_ = ::open(path.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0600);
        if (fd_ < 0) {
            throw StateError("cannot open " + path + ": " + errnoText());
        }
        while (::flock(fd_, LOCK_EX) != 0) {
            if (errno != EINTR) {
                const std::string why = errnoText();
                ::close(fd_);
                throw StateError("cannot lock " + path + ": " + why);
            }
        }
    }
    ~DirectoryLock() { ::close(fd_); }
    DirectoryLock(const DirectoryLock&) = delete;
    DirectoryLock& operator=(const DirectoryLock&) = delete;

private:
    int fd_ = -1;
};

}  // namespace

SequenceStore::SequenceStore(std::string directory) : directory_(std::move(directory)) {
    if (directory_.empty()) {
        throw StateError("the state directory name is empty");
    }
    while (directory_.size() > 1 && directory_.back() == '/') {
        directory_.pop_back();
    }
    struct stat info {};
    if (::stat(directory_.c_str(), &info) == 0) {
        if (!S_ISDIR(info.st_mode)) {
            throw StateError("state directory " + directory_ + " is not a directory");
        }
    } else if (::mkdir(directory_.c_str(), 0700) != 0 && errno != EEXIST) {
        throw StateError("cannot create state directory " + directory_ + ": " + errnoText());
    }
}

std::string SequenceStore::pathFor(std::uint16_t keyId) const {
    return directory_ + "/auth_seq_key" + std::to_string(keyId);
}

std::string SequenceStore::defaultDirectory() {
    if (const char* state = std::getenv("RSE_GROUND_STATE"); state != nullptr && state[0] != '\0') {
        return state;
    }
    if (const char* home = std::getenv("HOME"); home != nullptr && home[0] != '\0') {
        return std::string(home) + "/.rse-ground";
    }
    return ".rse-ground";
}

std::uint32_t SequenceStore::readLocked(std::uint16_t keyId) const {
    const std::string path = pathFor(keyId);
    std::ifstream in(path);
    if (!in) {
        return 0;  // no number handed out yet
    }
    std::string text;
    std::getline(in, text);
    while (!text.empty() && (text.back() == '\n' || text.back() == '\r' || text.back() == ' ')) {
        text.pop_back();
    }
    if (text.empty() || text.size() > 10 || text.find_first_not_of("0123456789") != std::string::npos ||
        std::stoull(text) > 0xFFFFFFFFULL) {
        throw StateError(path + " does not hold a sequence number (got '" + text +
                         "'); fix or delete it (deleting restarts at 1, which the rover may reject as stale)");
    }
    return static_cast<std::uint32_t>(std::stoull(text));
}

void SequenceStore::writeLocked(std::uint16_t keyId, std::uint32_t value) {
    const std::string path = pathFor(keyId);
    const std::string temporary = path + ".tmp";
    const int fd = ::open(temporary.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0600);
    if (fd < 0) {
        throw StateError("cannot write " + temporary + ": " + errnoText());
    }
    const std::string text = std::to_string(value) + "\n";
    const ssize_t n = ::write(fd, text.data(), text.size());
    const bool written = n == static_cast<ssize_t>(text.size()) && ::fsync(fd) == 0;
    const std::string why = errnoText();
    ::close(fd);
    if (!written || ::rename(temporary.c_str(), path.c_str()) != 0) {
        throw StateError("cannot persist the sequence number in " + path + ": " + (written ? errnoText() : why));
    }
    // The rename itself must reach the disk before the number is used.
    const int dir = ::open(directory_.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
    if (dir >= 0) {
        (void)::fsync(dir);
        ::close(dir);
    }
}

std::uint32_t SequenceStore::next(std::uint16_t keyId) {
    DirectoryLock lock(directory_);
    const std::uint32_t last = readLocked(keyId);
    if (last == 0xFFFFFFFFU) {
        throw StateError("sequence numbers of key " + std::to_string(keyId) +
                         " are exhausted (" + pathFor(keyId) + "): load a new key on the rover");
    }
    const std::uint32_t value = last + 1;
    writeLocked(keyId, value);
    return value;
}

void SequenceStore::noteUsed(std::uint16_t keyId, std::uint32_t sequence) {
    DirectoryLock lock(directory_);
    if (sequence > readLocked(keyId)) {
        writeLocked(keyId, sequence);
    }
}

std::uint32_t SequenceStore::last(std::uint16_t keyId) const {
    DirectoryLock lock(directory_);
    return readLocked(keyId);
}

}  // namespace rse::ground
