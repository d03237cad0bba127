// The telemetry archive of `rse-ground serve`: every packet received, kept in
// one SQLite file across restarts (docs/mission_control.md, "Archive").
//
//   CREATE TABLE telemetry (utc INTEGER NOT NULL,   -- ms since 1970, ground receive time
//                           packet TEXT NOT NULL,   -- dictionary name; UNDECODED when not decoded
//                           datum TEXT,             -- the datum JSON as served (NULL when not decoded)
//                           bytes BLOB NOT NULL);   -- the packet as received
//   CREATE INDEX telemetry_packet_utc ON telemetry (packet, utc);
//
// The file is marked as an RSE archive (PRAGMA application_id, user_version)
// and opened in WAL mode (synchronous NORMAL: a commit is not synced, a crash
// loses at most the last packets, never the file), so readers (the history
// queries, or sqlite3 on the same file) never wait for the writer. Opening
// checks the file (quick_check): a file that is not an RSE archive, of another
// version, or damaged is refused with ArchiveError saying which, and left as is.
//
// Thread-safe: the link reader appends while the HTTP server queries.
#pragma once

#include <cstddef>
#include <cstdint>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

struct sqlite3;
struct sqlite3_stmt;

namespace rse::ground::mission_control {

class ArchiveError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// The packet name under which packets that did not decode are kept (their
// bytes say why: rse-ground's decoder, or a later dictionary, reads them).
constexpr const char* kUndecodedPacket = "UNDECODED";

struct HistoryResult {
    std::vector<std::string> datums;  // datum JSON texts, oldest first
    bool truncated = false;           // more datums matched than the limit: these are the newest
};

class TelemetryArchive {
public:
    // Opens (creating it, and its folder, when missing) the archive at path.
    // Throws ArchiveError naming the file and what is wrong with it.
    explicit TelemetryArchive(const std::string& path);
    ~TelemetryArchive();
    TelemetryArchive(const TelemetryArchive&) = delete;
    TelemetryArchive& operator=(const TelemetryArchive&) = delete;

    // Appends one packet; datum is absent for a packet that did not decode.
    // Throws ArchiveError when SQLite cannot write it (disk full ...).
    void append(std::int64_t utcMs, const std::string& packet, const std::optional<std::string>& datum,
                const std::vector<std::uint8_t>& bytes);

    // The datums of `packet` with startMs <= utc <= endMs, oldest first; at
    // most `limit`, the newest of them when more match. Throws ArchiveError.
    HistoryResult history(const std::string& packet, std::int64_t startMs, std::int64_t endMs,
                          std::size_t limit) const;

    // Rows in the archive (every packet ever archived in this file).
    std::uint64_t rows() const;
    const std::string& path() const { return path_; }

private:
    void execute(const std::string& sql) const;
    [[noreturn]] void fail(const std::string& what) const;

    std::string path_;
    sqlite3* db_ = nullptr;
    sqlite3_stmt* insert_ = nullptr;
    sqlite3_stmt* history_ = nullptr;
    mutable std::mutex mutex_;
};

}  // namespace rse::ground::mission_control
