// The telemetry archive (ground/mission_control/telemetry_archive.hpp): what
// goes in comes out, across a close and reopen (a restart of rse-ground
// serve); history is bounded by time both ends and filtered by packet, keeps
// the newest when cut; a file that is not an archive, or a damaged one, is
// refused with a message that says so.
#include <sqlite3.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "ground/mission_control/telemetry_archive.hpp"
#include "unit_test/ground/mission_control/mc_test_support.hpp"

#include "CppUTest/TestHarness.h"

using rse::ground::mission_control::ArchiveError;
using rse::ground::mission_control::HistoryResult;
using rse::ground::mission_control::TelemetryArchive;
using rse::test::mc::ScratchDir;

namespace {

std::string datum(std::int64_t utc, int value) {
    return "{\"utc\":" + std::to_string(utc) + ",\"v\":" + std::to_string(value) + "}";
}

std::vector<std::uint8_t> bytesOf(int value) {
    return {0x08, 0x10, static_cast<std::uint8_t>(value), 0xFF};
}

// The error opening path gives ("" when it opens).
std::string openError(const std::string& path) {
    try {
        TelemetryArchive archive(path);
    } catch (const ArchiveError& e) {
        return e.what();
    }
    return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_GROUP(TelemetryArchive) {
    ScratchDir dir;
};

TEST(TelemetryArchive, RoundTripAndSurvivesReopen) {
    const std::string path = dir.file("sub/folder/archive.sqlite");  // the folders are made
    {
        TelemetryArchive archive(path);
        archive.append(1000, "HK", datum(1000, 1), bytesOf(1));
        archive.append(1001, "ROVER_STATE", datum(1001, 2), bytesOf(2));
        archive.append(1002, "UNDECODED", std::nullopt, bytesOf(3));
        CHECK_EQUAL(3U, archive.rows());
        const HistoryResult hk = archive.history("HK", 0, 5000, 100);
        CHECK_EQUAL(1U, hk.datums.size());
        STRCMP_EQUAL(datum(1000, 1).c_str(), hk.datums[0].c_str());
        CHECK_FALSE(hk.truncated);
    }
    // Reopened (a restart): everything is there, and appends go on.
    TelemetryArchive archive(path);
    CHECK_EQUAL(3U, archive.rows());
    archive.append(2000, "HK", datum(2000, 4), bytesOf(4));
    const HistoryResult hk = archive.history("HK", 0, 5000, 100);
    CHECK_EQUAL(2U, hk.datums.size());
    STRCMP_EQUAL(datum(1000, 1).c_str(), hk.datums[0].c_str());
    STRCMP_EQUAL(datum(2000, 4).c_str(), hk.datums[1].c_str());
    // An undecoded packet is kept, but never served as a datum.
    CHECK_EQUAL(0U, archive.history("UNDECODED", 0, 5000, 100).datums.size());
}

TEST(TelemetryArchive, FileLayoutKeepsTheBytesAndIsWal) {
    const std::string path = dir.file("archive.sqlite");
    {
        TelemetryArchive archive(path);
        archive.append(7, "UNDECODED", std::nullopt, bytesOf(9));
        archive.append(8, "HK", datum(8, 1), {});
    }
    sqlite3* db = nullptr;
    CHECK_EQUAL(SQLITE_OK, sqlite3_open_v2(path.c_str(), &db, SQLITE_OPEN_READONLY, nullptr));
    sqlite3_stmt* s = nullptr;
    CHECK_EQUAL(SQLITE_OK, sqlite3_prepare_v2(db, "SELECT utc, packet, datum IS NULL, bytes FROM telemetry ORDER BY utc",
                                              -1, &s, nullptr));
    CHECK_EQUAL(SQLITE_ROW, sqlite3_step(s));
    CHECK_EQUAL(7, sqlite3_column_int64(s, 0));
    STRCMP_EQUAL("UNDECODED", reinterpret_cast<const char*>(sqlite3_column_text(s, 1)));
    CHECK_EQUAL(1, sqlite3_column_int(s, 2));
    const std::vector<std::uint8_t> expected = bytesOf(9);
    CHECK_EQUAL(static_cast<int>(expected.size()), sqlite3_column_bytes(s, 3));
    MEMCMP_EQUAL(expected.data(), sqlite3_column_blob(s, 3), expected.size());
    CHECK_EQUAL(SQLITE_ROW, sqlite3_step(s));
    CHECK_EQUAL(0, sqlite3_column_bytes(s, 3));
    CHECK_EQUAL(SQLITE_DONE, sqlite3_step(s));
    sqlite3_finalize(s);
    CHECK_EQUAL(SQLITE_OK, sqlite3_prepare_v2(db, "PRAGMA journal_mode", -1, &s, nullptr));
    CHECK_EQUAL(SQLITE_ROW, sqlite3_step(s));
    STRCMP_EQUAL("wal", reinterpret_cast<const char*>(sqlite3_column_text(s, 0)));
    sqlite3_finalize(s);
    // The index the history queries use.
    CHECK_EQUAL(SQLITE_OK,
                sqlite3_prepare_v2(db, "SELECT count(*) FROM sqlite_master WHERE type = 'index' AND tbl_name = 'telemetry'",
                                   -1, &s, nullptr));
    CHECK_EQUAL(SQLITE_ROW, sqlite3_step(s));
    CHECK_EQUAL(1, sqlite3_column_int(s, 0));
    sqlite3_finalize(s);
    sqlite3_close(db);
}

TEST(TelemetryArchive, HistoryBoundsArePerPacketAndInclusive) {
    TelemetryArchive archive(dir.file("archive.sqlite"));
    for (int i = 0; i < 10; ++i) {
        archive.append(100 + i * 10, "HK", datum(100 + i * 10, i), bytesOf(i));     // 100, 110 .. 190
        archive.append(105 + i * 10, "DRIVES", datum(105 + i * 10, i), bytesOf(i));  // 105 .. 195
    }
    // Both ends inclusive, HK only, oldest first.
    const HistoryResult hk = archive.history("HK", 110, 150, 100);
    CHECK_EQUAL(5U, hk.datums.size());
    STRCMP_EQUAL(datum(110, 1).c_str(), hk.datums.front().c_str());
    STRCMP_EQUAL(datum(150, 5).c_str(), hk.datums.back().c_str());
    // Between two HKs: none.
    CHECK_EQUAL(0U, archive.history("HK", 111, 119, 100).datums.size());
    // One instant.
    CHECK_EQUAL(1U, archive.history("DRIVES", 125, 125, 100).datums.size());
    // Outside everything, and a packet with no rows.
    CHECK_EQUAL(0U, archive.history("HK", 200, 300, 100).datums.size());
    CHECK_EQUAL(0U, archive.history("PLAN", 0, 1000, 100).datums.size());
    // start after end: nothing.
    CHECK_EQUAL(0U, archive.history("HK", 150, 110, 100).datums.size());
}

TEST(TelemetryArchive, HistoryCutKeepsTheNewestOldestFirst) {
    TelemetryArchive archive(dir.file("archive.sqlite"));
    for (int i = 0; i < 10; ++i) {
        archive.append(i, "HK", datum(i, i), bytesOf(i));
    }
    archive.append(5, "HK", datum(5, 55), bytesOf(55));  // two at one ms: kept in arrival order
    const HistoryResult cut = archive.history("HK", 0, 100, 4);
    CHECK_TRUE(cut.truncated);
    CHECK_EQUAL(4U, cut.datums.size());
    STRCMP_EQUAL(datum(6, 6).c_str(), cut.datums[0].c_str());
    STRCMP_EQUAL(datum(9, 9).c_str(), cut.datums[3].c_str());
    const HistoryResult ties = archive.history("HK", 5, 5, 10);
    CHECK_EQUAL(2U, ties.datums.size());
    STRCMP_EQUAL(datum(5, 5).c_str(), ties.datums[0].c_str());
    STRCMP_EQUAL(datum(5, 55).c_str(), ties.datums[1].c_str());
    // Exactly the limit: not cut.
    CHECK_FALSE(archive.history("HK", 0, 3, 4).truncated);
}

TEST(TelemetryArchive, RefusesAFileThatIsNotAnArchive) {
    const std::string garbage = dir.file("garbage.sqlite");
    std::ofstream(garbage) << std::string(4096, 'x');
    const std::string error = openError(garbage);
    CHECK_TEXT(contains(error, garbage), error.c_str());
    CHECK_TEXT(contains(error, "not an RSE telemetry archive"), error.c_str());

    // Another program's SQLite database.
    const std::string other = dir.file("other.sqlite");
    sqlite3* db = nullptr;
    CHECK_EQUAL(SQLITE_OK, sqlite3_open(other.c_str(), &db));
    CHECK_EQUAL(SQLITE_OK, sqlite3_exec(db, "CREATE TABLE notes (text TEXT)", nullptr, nullptr, nullptr));
    sqlite3_close(db);
    const std::string otherError = openError(other);
    CHECK_TEXT(contains(otherError, "an SQLite file, but not an RSE telemetry archive"), otherError.c_str());
}

TEST(TelemetryArchive, RefusesADamagedArchive) {
    const std::string path = dir.file("archive.sqlite");
    {
        TelemetryArchive archive(path);
        for (int i = 0; i < 2000; ++i) {
            archive.append(i, "HK", datum(i, i) + std::string(100, ' '), bytesOf(i));
        }
    }
    // Cut in half (a copy interrupted, a disk that filled): the pages the
    // header promises are missing.
    const auto size = std::filesystem::file_size(path);
    CHECK_TRUE(size > 8192);
    std::filesystem::resize_file(path, size / 2);
    const std::string error = openError(path);
    CHECK_TEXT(contains(error, path), error.c_str());
    CHECK_TEXT(contains(error, "damaged") || contains(error, "malformed"), error.c_str());
    // Left as it was: nothing rewritten.
    CHECK_EQUAL(size / 2, std::filesystem::file_size(path));
}

TEST(TelemetryArchive, RefusesAnotherVersion) {
    const std::string path = dir.file("archive.sqlite");
    { TelemetryArchive archive(path); }
    sqlite3* db = nullptr;
    CHECK_EQUAL(SQLITE_OK, sqlite3_open(path.c_str(), &db));
    CHECK_EQUAL(SQLITE_OK, sqlite3_exec(db, "PRAGMA user_version = 7", nullptr, nullptr, nullptr));
    sqlite3_close(db);
    const std::string error = openError(path);
    CHECK_TEXT(contains(error, "archive version 7"), error.c_str());
}
