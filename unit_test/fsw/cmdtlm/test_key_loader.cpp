// rse-fsw --key-file: cmdtlm::loadKeyFile and the key checks of issue 14 item 4
// (docs/icd.md §5.3, "Keys"): no lab key unless asked for (under any key id), no
// weak key unless asked for, no key file that group or others may read.
#include <cerrno>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <sys/stat.h>
#include <unistd.h>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/key_loader.hpp"
#include "fsw/core/clock.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

std::string hexKey(const std::uint8_t key[kKeySize]) {
    static const char digits[] = "0123456789abcdef";
    std::string out;
    for (std::size_t i = 0; i < kKeySize; ++i) {
        out += digits[key[i] >> 4];
        out += digits[key[i] & 0x0F];
    }
    return out;
}

// A good key: 32 distinct bytes.
void goodKey(std::uint8_t key[kKeySize], std::uint8_t seed) {
    for (std::size_t i = 0; i < kKeySize; ++i) {
        key[i] = static_cast<std::uint8_t>(seed + i * 7);
    }
}

}  // namespace

TEST_GROUP(KeyLoader) {
    core::VirtualClock clock;
    core::EventLog* events = nullptr;
    KeyStore keys;
    std::string path;
    KeyLoadOptions options;

    void setup() override {
        events = new core::EventLog(clock);
        char name[] = "/tmp/rse-keys-XXXXXX";
        const int fd = mkstemp(name);
        CHECK(fd >= 0);
        close(fd);
        path = name;
    }
    void teardown() override {
        std::remove(path.c_str());
        delete events;
    }
    void write(const std::string& text, mode_t mode = 0600) {
        std::FILE* f = std::fopen(path.c_str(), "w");
        CHECK(f != nullptr);
        std::fputs(text.c_str(), f);
        std::fclose(f);
        CHECK(chmod(path.c_str(), mode) == 0);
    }
    KeyLoadResult load() { return loadKeyFile(path.c_str(), options, keys, *events); }
    void expectRefused(const KeyLoadResult& r, KeyLoadError error) {
        STRCMP_EQUAL(toString(error), toString(r.error));
        CHECK(!core::isOk(r.status));
        LONGS_EQUAL(0, keys.size());  // nothing half-loaded
        LONGS_EQUAL(1, test::drainEventsWithId(*events, events::kKeyFileRefused));
    }
};

TEST(KeyLoader, LoadsAGoodPrivateKeyFile) {
    std::uint8_t a[kKeySize];
    std::uint8_t b[kKeySize];
    goodKey(a, 1);
    goodKey(b, 100);
    write("# flight keys\n3:" + hexKey(a) + "\n\n7:" + hexKey(b) + "  # spare\n");
    const KeyLoadResult r = load();
    CHECK(core::isOk(r.status));
    LONGS_EQUAL(2, r.keysLoaded);
    MEMCMP_EQUAL(a, keys.find(3), kKeySize);
    MEMCMP_EQUAL(b, keys.find(7), kKeySize);
    CHECK_FALSE(keys.labKeyInUse());
    LONGS_EQUAL(0, test::drainEventsWithId(*events, events::kKeyFileRefused));
}

TEST(KeyLoader, RefusesTheLabKeyUnderAnyKeyIdWithoutLabKeyOption) {
    for (const std::uint16_t id : {1, 2, 999}) {
        write(std::to_string(id) + ":" + hexKey(kLabKey) + "\n");
        const KeyLoadResult r = load();
        expectRefused(r, KeyLoadError::kLabKeyRefused);
        LONGS_EQUAL(id, r.keyId);
        LONGS_EQUAL(1, r.line);
    }
}

TEST(KeyLoader, LoadsTheLabKeyUnderAnyIdWithLabKeyOptionAndKnowsItIsTheLabKey) {
    options.labKeyAllowed = true;
    std::uint8_t a[kKeySize];
    goodKey(a, 9);
    write("4:" + hexKey(a) + "\n12:" + hexKey(kLabKey) + "\n");
    const KeyLoadResult r = load();
    CHECK(core::isOk(r.status));
    CHECK_TRUE(keys.labKeyInUse());
    LONGS_EQUAL(12, keys.labKeyId());
}

TEST(KeyLoader, RefusesWeakKeys) {
    std::uint8_t weak[3][kKeySize] = {};
    std::memset(weak[1], 0x5A, kKeySize);  // all equal
    for (std::size_t i = 0; i < kKeySize; ++i) {
        weak[2][i] = static_cast<std::uint8_t>(i % 7);  // 7 distinct values
    }
    const KeyWeakness why[3] = {KeyWeakness::kAllZero, KeyWeakness::kAllEqual, KeyWeakness::kFewDistinct};
    for (int k = 0; k < 3; ++k) {
        std::uint8_t good[kKeySize];
        goodKey(good, 3);
        write("2:" + hexKey(good) + "\n5:" + hexKey(weak[k]) + "\n");
        const KeyLoadResult r = load();
        expectRefused(r, KeyLoadError::kWeakKeyRefused);
        CHECK(why[k] == r.weakness);
        LONGS_EQUAL(5, r.keyId);
        LONGS_EQUAL(2, r.line);
    }
}

TEST(KeyLoader, EightDistinctByteValuesAreEnough) {
    std::uint8_t key[kKeySize];
    for (std::size_t i = 0; i < kKeySize; ++i) {
        key[i] = static_cast<std::uint8_t>(0x30 + i % 8);
    }
    CHECK(KeyWeakness::kNone == keyWeakness(key));
    CHECK(KeyWeakness::kNone == keyWeakness(kLabKey));
}

TEST(KeyLoader, LoadsAWeakKeyWithTheOptionAndWarns) {
    options.weakKeyAllowed = true;
    const std::uint8_t zero[kKeySize] = {};
    write("6:" + hexKey(zero) + "\n");
    const KeyLoadResult r = load();
    CHECK(core::isOk(r.status));
    LONGS_EQUAL(1, r.weakKeysAccepted);
    CHECK(keys.find(6) != nullptr);
    LONGS_EQUAL(1, test::drainEventsWithId(*events, events::kWeakKeyAccepted));
}

TEST(KeyLoader, RefusesAKeyFileGroupOrOthersMayReadOrWrite) {
    std::uint8_t a[kKeySize];
    goodKey(a, 1);
    for (const mode_t mode : {0640, 0604, 0644, 0620, 0602}) {
        write("3:" + hexKey(a) + "\n", mode);
        expectRefused(load(), KeyLoadError::kOpenToOthers);
    }
}

TEST(KeyLoader, LoadsAReadableKeyFileWithTheOptionAndWarns) {
    options.readableFileAllowed = true;
    std::uint8_t a[kKeySize];
    goodKey(a, 1);
    write("3:" + hexKey(a) + "\n", 0644);
    const KeyLoadResult r = load();
    CHECK(core::isOk(r.status));
    CHECK_TRUE(r.openFileAccepted);
    LONGS_EQUAL(1, test::drainEventsWithId(*events, events::kKeyFileOpenAccepted));
}

TEST(KeyLoader, RefusesBadLinesDuplicatesTooManyAndEmptyFiles) {
    std::uint8_t k[6][kKeySize];
    for (int i = 0; i < 6; ++i) {
        goodKey(k[i], static_cast<std::uint8_t>(i * 40));
    }
    write("3:" + hexKey(k[0]) + "\n3:" + hexKey(k[1]) + "\n");
    expectRefused(load(), KeyLoadError::kDuplicateKeyId);
    write("3:" + hexKey(k[0]).substr(2) + "\n");
    expectRefused(load(), KeyLoadError::kBadLine);
    write("0:" + hexKey(k[0]) + "\n");
    expectRefused(load(), KeyLoadError::kBadLine);
    write("3:" + hexKey(k[0]) + std::string(300, ' ') + "\n");
    expectRefused(load(), KeyLoadError::kBadLine);  // longer than a line may be
    std::string five;
    for (int i = 0; i < 5; ++i) {
        five += std::to_string(i + 1) + ":" + hexKey(k[i]) + "\n";
    }
    write(five);
    const KeyLoadResult tooMany = load();
    expectRefused(tooMany, KeyLoadError::kTooManyKeys);
    LONGS_EQUAL(5, tooMany.line);
    write("# nothing here\n\n");
    expectRefused(load(), KeyLoadError::kNoKeyInFile);
}

TEST(KeyLoader, RefusesAMissingFileAndADirectory) {
    const KeyLoadResult missing = loadKeyFile("/nonexistent/rse-keys", options, keys, *events);
    expectRefused(missing, KeyLoadError::kCannotOpen);
    LONGS_EQUAL(ENOENT, missing.osError);
    expectRefused(loadKeyFile("/tmp", options, keys, *events), KeyLoadError::kNotRegularFile);
}
