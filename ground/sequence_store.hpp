// The ground's anti-replay sequence numbers, one counter per key id, kept in a
// state directory so they keep increasing across invocations (the rover rejects
// a number it has seen, or one more than 64 below the highest it has seen).
//
// One file per key: DIR/auth_seq_key<ID>, holding the last number handed out, in
// decimal. next() reads it, adds one, writes the file (write to a temporary,
// fsync, rename) and only then returns the number, so a crash after sending can
// never reuse it. An exclusive flock on DIR/.lock serialises concurrent rse-ground
// processes. Default directory: $RSE_GROUND_STATE, else ~/.rse-ground.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace rse::ground {

class StateError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

class SequenceStore {
public:
    // Creates the directory (mode 0700) if missing. Throws StateError.
    explicit SequenceStore(std::string directory);

    // The next number for this key, persisted before it is returned. Throws StateError.
    std::uint32_t next(std::uint16_t keyId);
    // Records a number used out of turn (--auth-seq): later next() calls return
    // larger numbers. Throws StateError.
    void noteUsed(std::uint16_t keyId, std::uint32_t sequence);
    // The last number handed out or noted (0: none yet). Throws StateError.
    std::uint32_t last(std::uint16_t keyId) const;

    const std::string& directory() const { return directory_; }
    std::string pathFor(std::uint16_t keyId) const;

    // $RSE_GROUND_STATE, else $HOME/.rse-ground, else ./.rse-ground.
    static std::string defaultDirectory();

private:
    std::uint32_t readLocked(std::uint16_t keyId) const;
    void writeLocked(std::uint16_t keyId, std::uint32_t value);

    std::string directory_;
};

}  // namespace rse::ground
