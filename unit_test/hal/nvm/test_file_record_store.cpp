// hal/nvm FileRecordStore: the anti-replay store on a real file system
// (atomic replace, missing and damaged files), and the anti-replay state over it
// across a "restart" (a new reader of the same file).
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>

#include "fsw/cmdtlm/anti_replay_state.hpp"
#include "hal/nvm/file_record_store.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

std::string makeTempDir() {
    const char* base = std::getenv("TMPDIR");
    std::string pattern = std::string(base != nullptr && base[0] != '\0' ? base : "/tmp") + "/rse-nvm-XXXXXX";
    char* made = ::mkdtemp(pattern.data());
    CHECK(made != nullptr);
    return pattern;
}

void removeTree(const std::string& dir) {
    if (DIR* d = ::opendir(dir.c_str())) {
        while (dirent* e = ::readdir(d)) {
            if (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) {
                (void)::unlink((dir + "/" + e->d_name).c_str());
            }
        }
        ::closedir(d);
    }
    (void)::rmdir(dir.c_str());
}

unsigned entriesIn(const std::string& dir) {
    unsigned n = 0;
    if (DIR* d = ::opendir(dir.c_str())) {
        while (dirent* e = ::readdir(d)) {
            n += (std::strcmp(e->d_name, ".") != 0 && std::strcmp(e->d_name, "..") != 0) ? 1U : 0U;
        }
        ::closedir(d);
    }
    return n;
}

}  // namespace

TEST_GROUP(FileRecordStore) {
    std::string dir;
    std::string path;
    void setup() override {
        dir = makeTempDir();
        path = dir + "/auth.dat";
    }
    void teardown() override { removeTree(dir); }
};

TEST(FileRecordStore, RefusesAnEmptyOrOverlongPath) {
    hal::FileRecordStore s;
    CHECK(core::Status::kInvalidArgument == s.open(""));
    CHECK(core::Status::kInvalidArgument == s.open(nullptr));
    const std::string longPath(hal::FileRecordStore::kMaxPath + 1, 'a');
    CHECK(core::Status::kInvalidArgument == s.open(longPath.c_str()));
    std::uint8_t b[4];
    std::size_t n = 0;
    CHECK(core::Status::kNotInitialized == s.read(b, sizeof b, &n));
}

TEST(FileRecordStore, AMissingFileReadsAsNotFoundAndOpeningCreatesNothing) {
    hal::FileRecordStore s;
    CHECK(core::isOk(s.open(path.c_str())));
    std::uint8_t b[16];
    std::size_t n = 0;
    CHECK(core::Status::kNotFound == s.read(b, sizeof b, &n));
    LONGS_EQUAL(0, entriesIn(dir));
}

TEST(FileRecordStore, WritesReplaceTheWholeRecordAndLeaveNoTemporary) {
    hal::FileRecordStore s;
    CHECK(core::isOk(s.open(path.c_str())));
    const std::uint8_t first[5] = {1, 2, 3, 4, 5};
    const std::uint8_t second[3] = {9, 8, 7};
    CHECK(core::isOk(s.write(first, sizeof first)));
    CHECK(core::isOk(s.write(second, sizeof second)));
    LONGS_EQUAL(2, s.writes());
    LONGS_EQUAL(1, entriesIn(dir));  // no auth.dat.tmp left behind
    struct stat st {};
    CHECK(::stat(path.c_str(), &st) == 0);
    LONGS_EQUAL(0600, st.st_mode & 0777);

    hal::FileRecordStore again;  // a restart
    CHECK(core::isOk(again.open(path.c_str())));
    std::uint8_t b[16];
    std::size_t n = 0;
    CHECK(core::isOk(again.read(b, sizeof b, &n)));
    LONGS_EQUAL(3, n);
    MEMCMP_EQUAL(second, b, 3);
}

TEST(FileRecordStore, ARecordLargerThanTheBufferIsTooLarge) {
    hal::FileRecordStore s;
    CHECK(core::isOk(s.open(path.c_str())));
    const std::uint8_t data[8] = {};
    CHECK(core::isOk(s.write(data, sizeof data)));
    std::uint8_t b[8];
    std::size_t n = 0;
    CHECK(core::isOk(s.read(b, 8, &n)));  // exactly full is fine
    CHECK(core::Status::kTooLarge == s.read(b, 7, &n));
}

TEST(FileRecordStore, AWriteThatCannotBeDoneIsCountedWithItsErrno) {
    hal::FileRecordStore s;
    const std::string nowhere = dir + "/no-such-dir/auth.dat";
    CHECK(core::isOk(s.open(nowhere.c_str())));
    const std::uint8_t data[2] = {1, 2};
    CHECK(core::Status::kUnavailable == s.write(data, sizeof data));
    LONGS_EQUAL(ENOENT, s.lastErrno());
    LONGS_EQUAL(1, s.failures());
    // A directory where the file should be: unreadable, not "missing".
    hal::FileRecordStore d;
    CHECK(core::isOk(d.open(dir.c_str())));
    std::uint8_t b[4];
    std::size_t n = 0;
    CHECK(core::Status::kUnavailable == d.read(b, sizeof b, &n));
}

TEST(FileRecordStore, TheAntiReplayFloorSurvivesARestartOnAFile) {
    hal::FileRecordStore file;
    CHECK(core::isOk(file.open(path.c_str())));
    {
        cmdtlm::KeyStore keys;
        CHECK(core::isOk(keys.add(cmdtlm::kLabKeyId, cmdtlm::kLabKey)));
        cmdtlm::AntiReplayState state;
        state.attach(&file);
        state.load(keys, true);
        CHECK(cmdtlm::AuthStoreState::kOk == state.state());
        CHECK(core::isOk(state.reserve(cmdtlm::kLabKeyId, 40)));
        keys.commit(cmdtlm::kLabKeyId, 40);
    }
    hal::FileRecordStore reopened;
    CHECK(core::isOk(reopened.open(path.c_str())));
    cmdtlm::KeyStore keys;
    CHECK(core::isOk(keys.add(cmdtlm::kLabKeyId, cmdtlm::kLabKey)));
    cmdtlm::AntiReplayState state;
    state.attach(&reopened);
    state.load(keys, false);
    CHECK(cmdtlm::AuthStoreState::kOk == state.state());
    LONGS_EQUAL(40 + cmdtlm::kReserveBlock, state.reserved(cmdtlm::kLabKeyId));
    CHECK(cmdtlm::KeyStore::Freshness::kFresh != keys.check(cmdtlm::kLabKeyId, 40));
    CHECK(cmdtlm::KeyStore::Freshness::kFresh != keys.check(cmdtlm::kLabKeyId, 40 + cmdtlm::kReserveBlock));
    CHECK(cmdtlm::KeyStore::Freshness::kFresh == keys.check(cmdtlm::kLabKeyId, 41 + cmdtlm::kReserveBlock));
}

TEST(FileRecordStore, RandomNoncesDiffer) {
    std::uint64_t a = 0, b = 0;
    int error = 0;
    CHECK(core::isOk(hal::readRandom64(&a, &error)));
    CHECK(core::isOk(hal::readRandom64(&b, &error)));
    CHECK(a != b);
}
