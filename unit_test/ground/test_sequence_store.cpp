// The anti-replay sequence store: numbers increase, are on disk before they are
// handed out, survive a new store (a new rse-ground invocation), and per key.
#include <cstdio>
#include <fstream>
#include <string>

#include "ground/key_file.hpp"
#include "ground/sequence_store.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

std::string fileText(const std::string& path) {
    std::ifstream in(path);
    std::string text;
    std::getline(in, text);
    return text;
}

void writeFile(const std::string& path, const std::string& text) {
    std::ofstream out(path);
    out << text;
}

}  // namespace

TEST_GROUP(GroundSequenceStore){};

TEST(GroundSequenceStore, NumbersIncreaseAndArePersistedBeforeUse) {
    test::TempDir dir;
    ground::SequenceStore store(dir.path());
    CHECK_EQUAL(0U, store.last(1));
    CHECK_EQUAL(1U, store.next(1));
    STRCMP_EQUAL("1", fileText(dir.file("auth_seq_key1")).c_str());
    CHECK_EQUAL(2U, store.next(1));
    STRCMP_EQUAL("2", fileText(dir.file("auth_seq_key1")).c_str());
    CHECK_EQUAL(2U, store.last(1));
}

TEST(GroundSequenceStore, ANewStoreContinuesWhereTheLastStopped) {
    test::TempDir dir;
    {
        ground::SequenceStore first(dir.path());
        for (int i = 0; i < 5; ++i) {
            (void)first.next(1);
        }
    }
    ground::SequenceStore second(dir.path());
    CHECK_EQUAL(6U, second.next(1));
}

TEST(GroundSequenceStore, KeysHaveSeparateCounters) {
    test::TempDir dir;
    ground::SequenceStore store(dir.path());
    CHECK_EQUAL(1U, store.next(1));
    CHECK_EQUAL(2U, store.next(1));
    CHECK_EQUAL(1U, store.next(7));
    CHECK_EQUAL(1U, store.next(0));
    CHECK_EQUAL(3U, store.next(1));
}

TEST(GroundSequenceStore, ForcedNumbersMoveTheCounterOnlyForward) {
    test::TempDir dir;
    ground::SequenceStore store(dir.path());
    store.noteUsed(1, 100);
    CHECK_EQUAL(101U, store.next(1));
    store.noteUsed(1, 50);  // a replay demonstration: older numbers do not rewind
    CHECK_EQUAL(102U, store.next(1));
}

TEST(GroundSequenceStore, CreatesItsDirectory) {
    test::TempDir dir;
    const std::string sub = dir.file("state");
    {
        ground::SequenceStore store(sub);
        CHECK_EQUAL(1U, store.next(1));
        STRCMP_EQUAL(sub.c_str(), store.directory().c_str());
    }
    std::remove((sub + "/auth_seq_key1").c_str());
    std::remove((sub + "/.lock").c_str());
    std::remove(sub.c_str());
}

TEST(GroundSequenceStore, CorruptStateIsAnErrorNotARestart) {
    test::TempDir dir;
    writeFile(dir.file("auth_seq_key1"), "12x\n");
    ground::SequenceStore store(dir.path());
    CHECK_THROWS(ground::StateError, store.next(1));
    writeFile(dir.file("auth_seq_key1"), "4294967295\n");
    CHECK_THROWS(ground::StateError, store.next(1));  // exhausted
    writeFile(dir.file("auth_seq_key1"), "41\n");
    CHECK_EQUAL(42U, store.next(1));
}

TEST(GroundSequenceStore, AFileWhereTheDirectoryShouldBeIsAnError) {
    test::TempDir dir;
    writeFile(dir.file("plain"), "x");
    CHECK_THROWS(ground::StateError, ground::SequenceStore(dir.file("plain")));
}

TEST(GroundSequenceStore, DefaultDirectoryFollowsTheEnvironment) {
    const char* saved = std::getenv("RSE_GROUND_STATE");
    const std::string keep = saved != nullptr ? saved : "";
    ::setenv("RSE_GROUND_STATE", "/tmp/somewhere", 1);
    STRCMP_EQUAL("/tmp/somewhere", ground::SequenceStore::defaultDirectory().c_str());
    ::unsetenv("RSE_GROUND_STATE");
    CHECK_TRUE(ground::SequenceStore::defaultDirectory().find(".rse-ground") != std::string::npos);
    if (saved != nullptr) {
        ::setenv("RSE_GROUND_STATE", keep.c_str(), 1);
    }
}

TEST_GROUP(GroundKeyFile){};

TEST(GroundKeyFile, LabKeyByDefault) {
    const ground::PacketAuth auth = ground::loadPacketAuth("", std::nullopt);
    CHECK_EQUAL(1, auth.keyId);
    CHECK_EQUAL(32U, auth.key.size());
    MEMCMP_EQUAL(cmdtlm::kLabKey, auth.key.data(), 32);
    CHECK_THROWS(ground::KeyFileError, ground::loadPacketAuth("", std::uint16_t{2}));
}

TEST(GroundKeyFile, KeysFromAFileByIdOrFirst) {
    test::TempDir dir;
    const std::string path = dir.file("keys");
    writeFile(path, "# ground keys\n\n7:" + std::string(64, 'a') + "\n9:" + std::string(62, '0') + "ff  # spare\n");
    ground::PacketAuth auth = ground::loadPacketAuth(path, std::nullopt);
    CHECK_EQUAL(7, auth.keyId);
    CHECK_EQUAL(0xAA, auth.key[0]);
    auth = ground::loadPacketAuth(path, std::uint16_t{9});
    CHECK_EQUAL(9, auth.keyId);
    CHECK_EQUAL(0xFF, auth.key[31]);
    CHECK_EQUAL(0x00, auth.key[0]);
    std::string message;
    try {
        (void)ground::loadPacketAuth(path, std::uint16_t{3});
    } catch (const ground::KeyFileError& e) {
        message = e.what();
    }
    CHECK_TRUE(message.find("no key 3 (the file has 7, 9)") != std::string::npos);
}

TEST(GroundKeyFile, BadLinesAreNamedByNumber) {
    test::TempDir dir;
    const std::string path = dir.file("keys");
    writeFile(path, "# ok\n1:" + std::string(64, 'a') + "\n2:tooshort\n");
    std::string message;
    try {
        (void)ground::loadPacketAuth(path, std::nullopt);
    } catch (const ground::KeyFileError& e) {
        message = e.what();
    }
    CHECK_TRUE(message.find(path + ":3: not a key line") == 0);
    CHECK_THROWS(ground::KeyFileError, ground::loadPacketAuth(dir.file("missing"), std::nullopt));
}
