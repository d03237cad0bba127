#include "ground/mission_control/telemetry_archive.hpp"

#include <algorithm>
#include <filesystem>
#include <limits>

#include <sqlite3.h>

namespace rse::ground::mission_control {
namespace {

// "RSEA": this file is an RSE telemetry archive (PRAGMA application_id).
constexpr int kApplicationId = 0x52534541;
// The layout above; a file of another version is refused, not converted.
constexpr int kSchemaVersion = 1;

// A prepared statement, finalized on every path out.
class Statement {
public:
    Statement(sqlite3* db, const char* sql) {
        if (sqlite3_prepare_v2(db, sql, -1, &stmt_, nullptr) != SQLITE_OK) {
            stmt_ = nullptr;
        }
    }
    ~Statement() { sqlite3_finalize(stmt_); }
    Statement(const Statement&) = delete;
    Statement& operator=(const Statement&) = delete;
    sqlite3_stmt* get() const { return stmt_; }

private:
    sqlite3_stmt* stmt_ = nullptr;
};

}  // namespace

void TelemetryArchive::fail(const std::string& what) const {
    throw ArchiveError("archive " + path_ + ": " + what + (db_ != nullptr ? std::string(": ") + sqlite3_errmsg(db_) : ""));
}

void TelemetryArchive::execute(const std::string& sql) const {
    char* message = nullptr;
    if (sqlite3_exec(db_, sql.c_str(), nullptr, nullptr, &message) != SQLITE_OK) {
        const std::string text = message != nullptr ? message : "unknown error";
        sqlite3_free(message);
        throw ArchiveError("archive " + path_ + ": " + text + " (in: " + sql + ")");
    }
}

TelemetryArchive::TelemetryArchive(const std::string& path) : path_(path) {
    try {
        const std::filesystem::path parent = std::filesystem::path(path).parent_path();
        if (!parent.empty()) {
            std::filesystem::create_directories(parent);
        }
    } catch (const std::filesystem::filesystem_error& e) {
        throw ArchiveError("archive " + path + ": cannot create its folder: " + e.what());
    }
    if (sqlite3_open_v2(path.c_str(), &db_, SQLITE_OPEN_READWRITE | SQLITE_OPEN_CREATE, nullptr) != SQLITE_OK) {
        const std::string why = db_ != nullptr ? sqlite3_errmsg(db_) : "out of memory";
        sqlite3_close(db_);
        db_ = nullptr;
        throw ArchiveError("archive " + path + ": cannot open: " + why);
    }
    try {
        sqlite3_busy_timeout(db_, 5000);
        // The first read of the file: a file that is not SQLite fails here.
        auto pragmaInt = [this](const char* sql, const char* what) {
            Statement s(db_, sql);
            if (s.get() == nullptr || sqlite3_step(s.get()) != SQLITE_ROW) {
                fail(std::string("not an RSE telemetry archive (cannot read its ") + what + ")");
            }
            return sqlite3_column_int(s.get(), 0);
        };
        const int applicationId = pragmaInt("PRAGMA application_id", "header");
        const int objects = pragmaInt("SELECT count(*) FROM sqlite_master", "schema");
        if (applicationId == 0 && objects == 0) {
            // A new (or empty) file: make it an archive.
            execute("PRAGMA application_id = " + std::to_string(kApplicationId));
            execute("PRAGMA user_version = " + std::to_string(kSchemaVersion));
            execute("CREATE TABLE telemetry (utc INTEGER NOT NULL, packet TEXT NOT NULL, datum TEXT, "
                    "bytes BLOB NOT NULL)");
            execute("CREATE INDEX telemetry_packet_utc ON telemetry (packet, utc)");
        } else if (applicationId != kApplicationId) {
            throw ArchiveError("archive " + path_ +
                               ": an SQLite file, but not an RSE telemetry archive (application_id " +
                               std::to_string(applicationId) + "): give another --archive");
        } else {
            const int version = pragmaInt("PRAGMA user_version", "version");
            if (version != kSchemaVersion) {
                throw ArchiveError("archive " + path_ + ": archive version " + std::to_string(version) +
                                   ", this rse-ground reads version " + std::to_string(kSchemaVersion));
            }
        }
        {
            Statement check(db_, "PRAGMA quick_check");
            if (check.get() == nullptr || sqlite3_step(check.get()) != SQLITE_ROW) {
                fail("damaged (quick_check could not run)");
            }
            const auto* verdict = reinterpret_cast<const char*>(sqlite3_column_text(check.get(), 0));
            if (verdict == nullptr || std::string(verdict) != "ok") {
                throw ArchiveError("archive " + path_ + ": damaged (quick_check: " +
                                   (verdict != nullptr ? verdict : "no answer") +
                                   "): move it aside to keep it, and start with a new archive");
            }
        }
        Statement journal(db_, "PRAGMA journal_mode = WAL");
        if (journal.get() == nullptr || sqlite3_step(journal.get()) != SQLITE_ROW ||
            std::string(reinterpret_cast<const char*>(sqlite3_column_text(journal.get(), 0))) != "wal") {
            fail("cannot switch to WAL mode (a file system without shared memory?)");
        }
        execute("PRAGMA synchronous = NORMAL");
        if (sqlite3_prepare_v2(db_, "INSERT INTO telemetry (utc, packet, datum, bytes) VALUES (?1, ?2, ?3, ?4)", -1,
                               &insert_, nullptr) != SQLITE_OK) {
            fail("not an RSE telemetry archive (no telemetry table of its layout)");
        }
        // Newest first so LIMIT keeps the newest; returned oldest first.
        if (sqlite3_prepare_v2(db_,
                               "SELECT datum FROM telemetry WHERE packet = ?1 AND utc >= ?2 AND utc <= ?3 "
                               "AND datum IS NOT NULL ORDER BY utc DESC, rowid DESC LIMIT ?4",
                               -1, &history_, nullptr) != SQLITE_OK) {
            fail("not an RSE telemetry archive (no telemetry table of its layout)");
        }
    } catch (...) {
        sqlite3_finalize(insert_);
        sqlite3_finalize(history_);
        sqlite3_close(db_);
        db_ = nullptr;
        throw;
    }
}

TelemetryArchive::~TelemetryArchive() {
    sqlite3_finalize(insert_);
    sqlite3_finalize(history_);
    // The last connection closing checkpoints the WAL into the file and removes it.
    sqlite3_close(db_);
}

void TelemetryArchive::append(std::int64_t utcMs, const std::string& packet, const std::optional<std::string>& datum,
                              const std::vector<std::uint8_t>& bytes) {
    std::lock_guard<std::mutex> lock(mutex_);
    sqlite3_reset(insert_);
    sqlite3_bind_int64(insert_, 1, utcMs);
    sqlite3_bind_text(insert_, 2, packet.data(), static_cast<int>(packet.size()), SQLITE_TRANSIENT);
    if (datum) {
        sqlite3_bind_text(insert_, 3, datum->data(), static_cast<int>(datum->size()), SQLITE_TRANSIENT);
    } else {
        sqlite3_bind_null(insert_, 3);
    }
    // A zero-length blob still is a blob, not NULL (the column is NOT NULL).
    sqlite3_bind_blob(insert_, 4, bytes.empty() ? "" : static_cast<const void*>(bytes.data()),
                      static_cast<int>(bytes.size()), SQLITE_TRANSIENT);
    const int rc = sqlite3_step(insert_);
    sqlite3_reset(insert_);
    sqlite3_clear_bindings(insert_);
    if (rc != SQLITE_DONE) {
        fail("cannot append a " + packet + " packet");
    }
}

HistoryResult TelemetryArchive::history(const std::string& packet, std::int64_t startMs, std::int64_t endMs,
                                        std::size_t limit) const {
    HistoryResult result;
    if (limit == 0 || startMs > endMs) {
        return result;
    }
    std::lock_guard<std::mutex> lock(mutex_);
    sqlite3_reset(history_);
    sqlite3_bind_text(history_, 1, packet.data(), static_cast<int>(packet.size()), SQLITE_TRANSIENT);
    sqlite3_bind_int64(history_, 2, startMs);
    sqlite3_bind_int64(history_, 3, endMs);
    const std::size_t maxRows = std::min<std::size_t>(limit, static_cast<std::size_t>(std::numeric_limits<int>::max() - 1));
    sqlite3_bind_int64(history_, 4, static_cast<sqlite3_int64>(maxRows) + 1);  // one more: was it cut?
    int rc = SQLITE_ROW;
    while ((rc = sqlite3_step(history_)) == SQLITE_ROW) {
        const auto* text = reinterpret_cast<const char*>(sqlite3_column_text(history_, 0));
        const int length = sqlite3_column_bytes(history_, 0);
        result.datums.emplace_back(text != nullptr ? text : "", static_cast<std::size_t>(length));
    }
    sqlite3_reset(history_);
    if (rc != SQLITE_DONE) {
        fail("history query for " + packet + " failed");
    }
    if (result.datums.size() > maxRows) {
        result.truncated = true;
        result.datums.pop_back();  // the oldest
    }
    std::reverse(result.datums.begin(), result.datums.end());
    return result;
}

std::uint64_t TelemetryArchive::rows() const {
    std::lock_guard<std::mutex> lock(mutex_);
    Statement count(db_, "SELECT count(*) FROM telemetry");
    if (count.get() == nullptr || sqlite3_step(count.get()) != SQLITE_ROW) {
        fail("cannot count its rows");
    }
    return static_cast<std::uint64_t>(sqlite3_column_int64(count.get(), 0));
}

}  // namespace rse::ground::mission_control
