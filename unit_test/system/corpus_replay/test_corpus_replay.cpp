// Replays the fuzz seed corpora (unit_test/fuzz/corpus/) and any crash
// reproducers (unit_test/fuzz/regressions/) through the flight code, so every
// `make test` checks that the seeds still mean what their names say - and that
// a fixed crash stays fixed. Runs from the repository root (also under
// qemu-aarch64); the seeds are rewritten by `make fuzz-seeds`.
//
// Command seeds (command/):
//   NAME.bin             authenticated with the lab key: accepted in every mode
//                        NAME allows, wrong_mode in the others; the generated
//                        decodeArgs consumes exactly the argument bytes, in range
//   NAME.nokey.bin       key id 0: mac_missing when authentication is required,
//                        accepted in the lab setting (in NAME's modes)
//   invalid.REASON[.WHAT].bin   rejected with REASON in every mode
// Table seeds (table/):
//   NAME.tbl             valid image of table NAME; decodeTable + encodeTable
//                        reproduce it byte for byte
//   invalid.REASON[.WHAT].tbl   checkTableImage refuses it with REASON
// Plan seeds (plan/, hand-written):
//   NAME.plan            parsePlan accepts it (the odd-but-legal inputs among them)
//   invalid.REASON.plan  parsePlan refuses it with REASON (kPlanSeedReasons)
#include <dirent.h>

#include <algorithm>
#include <cctype>
#include <cstdint>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "unit_test/support/decoded_args_check.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;
using Bytes = std::vector<std::uint8_t>;

namespace {

const char* const kCommandSeeds = "unit_test/fuzz/corpus/command";
const char* const kTableSeeds = "unit_test/fuzz/corpus/table";
const char* const kCommandRegressions = "unit_test/fuzz/regressions/command";
const char* const kTableRegressions = "unit_test/fuzz/regressions/table";
const char* const kPlanSeeds = "unit_test/fuzz/corpus/plan";
const char* const kPlanRegressions = "unit_test/fuzz/regressions/plan";

// The REASON of an invalid plan seed's name and the error it must give.
struct PlanSeedReason {
    const char* name;
    plan_executive::PlanError error;
};
const PlanSeedReason kPlanSeedReasons[] = {
    {"empty", plan_executive::PlanError::kEmptyText},
    {"cycle", plan_executive::PlanError::kCycle},
    {"unknown_activity", plan_executive::PlanError::kUnknownActivityKind},
    {"bounds_reversed", plan_executive::PlanError::kBoundsReversed},
    {"no_end_marker", plan_executive::PlanError::kNoEndMarker},
    {"unterminated_string", plan_executive::PlanError::kUnterminatedString},
    {"radius_without_within", plan_executive::PlanError::kRadiusWithoutWithin},
};

constexpr Mode kModes[kModeCount] = {Mode::kSafe, Mode::kStandby, Mode::kAutonomous, Mode::kManual};

// Regular files of a directory, sorted; none if it does not exist. Dot files
// and notes (*.md, *.txt) are not inputs.
std::vector<std::string> listInputs(const char* dir) {
    std::vector<std::string> names;
    DIR* d = ::opendir(dir);
    if (d == nullptr) {
        return names;
    }
    while (const dirent* e = ::readdir(d)) {
        const std::string name = e->d_name;
        const auto endsWith = [&name](const char* suffix) {
            const std::size_t n = std::strlen(suffix);
            return name.size() >= n && name.compare(name.size() - n, n, suffix) == 0;
        };
        if (name.empty() || name[0] == '.' || endsWith(".md") || endsWith(".txt")) {
            continue;
        }
        names.push_back(name);
    }
    ::closedir(d);
    std::sort(names.begin(), names.end());
    return names;
}

Bytes readFile(const std::string& path) {
    Bytes bytes;
    FILE* f = std::fopen(path.c_str(), "rb");
    if (f == nullptr) {
        FAIL(("cannot open " + path + " (tests run from the repository root)").c_str());
        return bytes;
    }
    std::uint8_t buffer[512];
    std::size_t n = 0;
    while ((n = std::fread(buffer, 1, sizeof buffer, f)) > 0) {
        bytes.insert(bytes.end(), buffer, buffer + n);
    }
    std::fclose(f);
    return bytes;
}

bool startsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

// "invalid.bad_length.truncated.bin" -> "bad_length".
std::string reasonToken(const std::string& name) {
    const std::size_t from = std::strlen("invalid.");
    const std::size_t to = name.find('.', from);
    return to == std::string::npos ? name.substr(from) : name.substr(from, to - from);
}

// "out of range" -> "out_of_range", "bad CRC" -> "bad_crc".
std::string fileToken(const char* text) {
    std::string out;
    for (; *text != '\0'; ++text) {
        out += *text == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(*text)));
    }
    return out;
}

// Round trip through the typed codec of the image's table.
bool roundTrips(const Bytes& image) {
    tables::TableHeader header;
    if (!tables::readTableHeader(image.data(), image.size(), &header)) {
        return false;
    }
    std::uint8_t out[tables::kMaxTableImageSize];
    switch (static_cast<tables::TableId>(header.tableId)) {
#define RSE_TABLE(Name, id, description)                                                                  \
    case tables::TableId::k##Name: {                                                                      \
        tables::Name##Table table;                                                                        \
        if (!tables::decodeTable(image.data(), image.size(), &table).ok()) {                             \
            return false;                                                                                 \
        }                                                                                                 \
        const std::size_t n = tables::encodeTable(table, header.version, out, sizeof out);               \
        return n == image.size() && std::memcmp(out, image.data(), n) == 0;                             \
    }
#include "fsw/tables/table_defs.def"
    }
    return false;
}

}  // namespace

constexpr std::uint64_t kSeedResyncNonce = 0x0000000100000001ULL;

TEST_GROUP(CorpusReplay) {
    HmacSha256 hmac;
    KeyStore keys;
    CommandValidator* validator = nullptr;

    void setup() override {
        CHECK(core::isOk(hmac.init()));
        validator = new CommandValidator(keys, hmac);
    }
    void teardown() override { delete validator; }

    // A fresh key store holding the lab key for every check: a seed's verdict
    // does not depend on the seeds checked before it.
    CommandVerdict check(const Bytes& packet, bool authRequired, Mode mode) {
        keys.clear();
        CHECK(core::isOk(keys.add(kLabKeyId, kLabKey)));
        validator->setAuthRequired(authRequired);
        // The AUTH_RESYNC seed carries nonce 1:1 (make_seeds' in-range value 1);
        // each check starts with the rover's nonce there, since an accepted one moves it.
        validator->replay().setChallengeSeed(kSeedResyncNonce);
        return validator->check(packet.data(), packet.size(), mode);
    }

    // Accepted (and decoded in range) exactly in the command's modes.
    void expectAcceptedInItsModes(const std::string& file, const Bytes& packet, const char* name, bool authRequired) {
        const CommandDesc* desc = findCommand(name);
        CHECK_TEXT(desc != nullptr, (file + ": no command " + name + " in the dictionary (make fuzz-seeds)").c_str());
        for (const Mode mode : kModes) {
            const CommandVerdict v = check(packet, authRequired, mode);
            const std::string where = file + " in " + toString(mode);
            if (modeAllows(desc->modes, mode)) {
                STRCMP_EQUAL_TEXT("accepted", toString(v.reason), where.c_str());
                CHECK_TEXT(v.command == desc, where.c_str());
                CHECK_TEXT(test::decodesInRange(v), where.c_str());
            } else {
                STRCMP_EQUAL_TEXT("wrong_mode", toString(v.reason), where.c_str());
            }
        }
    }
};

TEST(CorpusReplay, EveryDictionaryCommandHasAnAuthenticatedSeed) {
    const std::vector<std::string> files = listInputs(kCommandSeeds);
    CHECK_TEXT(!files.empty(), "no command seeds: run from the repository root");
    std::size_t count = 0;
    const CommandDesc* descs = commandDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::string want = std::string(descs[i].name) + ".bin";
        CHECK_TEXT(std::find(files.begin(), files.end(), want) != files.end(),
                   (want + " missing from " + kCommandSeeds + " (make fuzz-seeds)").c_str());
    }
}

TEST(CorpusReplay, AuthenticatedSeedsAreAcceptedInTheirModesAndDecode) {
    std::size_t replayed = 0;
    for (const std::string& file : listInputs(kCommandSeeds)) {
        const std::size_t dot = file.find('.');
        if (startsWith(file, "invalid.") || dot == std::string::npos || file.substr(dot) != ".bin") {
            continue;
        }
        const Bytes packet = readFile(std::string(kCommandSeeds) + "/" + file);
        // Authenticated with key id 1: accepted with or without the lab setting.
        expectAcceptedInItsModes(file, packet, file.substr(0, dot).c_str(), true);
        expectAcceptedInItsModes(file, packet, file.substr(0, dot).c_str(), false);
        CHECK_EQUAL(kLabKeyId, check(packet, true, Mode::kSafe).keyId);
        ++replayed;
    }
    CHECK(replayed >= kCommandCount);
}

TEST(CorpusReplay, UnauthenticatedSeedsNeedTheLabSetting) {
    std::size_t replayed = 0;
    for (const std::string& file : listInputs(kCommandSeeds)) {
        const std::size_t dot = file.find('.');
        if (startsWith(file, "invalid.") || dot == std::string::npos || file.substr(dot) != ".nokey.bin") {
            continue;
        }
        const Bytes packet = readFile(std::string(kCommandSeeds) + "/" + file);
        for (const Mode mode : kModes) {
            const CommandVerdict v = check(packet, true, mode);
            STRCMP_EQUAL_TEXT("mac_missing", toString(v.reason), file.c_str());
            CHECK_EQUAL(kNoKey, v.keyId);
        }
        expectAcceptedInItsModes(file, packet, file.substr(0, dot).c_str(), false);
        ++replayed;
    }
    CHECK(replayed > 0);
}

TEST(CorpusReplay, InvalidCommandSeedsAreRejectedForTheReasonTheirNameGives) {
    std::size_t replayed = 0;
    for (const std::string& file : listInputs(kCommandSeeds)) {
        if (!startsWith(file, "invalid.")) {
            continue;
        }
        const Bytes packet = readFile(std::string(kCommandSeeds) + "/" + file);
        const std::string reason = reasonToken(file);
        for (const bool authRequired : {true, false}) {
            for (const Mode mode : kModes) {
                const CommandVerdict v = check(packet, authRequired, mode);
                STRCMP_EQUAL_TEXT(reason.c_str(), toString(v.reason), (file + " in " + toString(mode)).c_str());
                if (v.reason == CommandReject::kArgumentOutOfRange) {
                    CHECK(v.command != nullptr && v.detail >= 0 && v.detail < v.command->argCount);
                }
            }
        }
        ++replayed;
    }
    CHECK(replayed >= 8);
}

TEST(CorpusReplay, EveryTableHasAValidSeedThatRoundTrips) {
    std::size_t count = 0;
    const tables::TableDesc* descs = tables::tableDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::string name = fileToken(descs[i].name) + ".tbl";
        const Bytes image = readFile(std::string(kTableSeeds) + "/" + name);
        const tables::TableCheck c = tables::checkTableImage(image.data(), image.size(), descs[i].id);
        STRCMP_EQUAL_TEXT("ok", tables::toString(c.reason), (name + " (make fuzz-seeds after a layout change)").c_str());
        CHECK_TEXT(roundTrips(image), name.c_str());
    }
}

TEST(CorpusReplay, InvalidTableSeedsAreRefusedForTheReasonTheirNameGives) {
    std::size_t replayed = 0;
    for (const std::string& file : listInputs(kTableSeeds)) {
        const Bytes image = readFile(std::string(kTableSeeds) + "/" + file);
        const tables::TableCheck c = tables::checkTableImage(image.data(), image.size());
        if (!startsWith(file, "invalid.")) {
            CHECK_TEXT(c.ok(), file.c_str());
            continue;
        }
        STRCMP_EQUAL_TEXT(reasonToken(file).c_str(), fileToken(tables::toString(c.reason)).c_str(), file.c_str());
        CHECK_TEXT(!roundTrips(image), file.c_str());
        ++replayed;
    }
    CHECK(replayed >= 5);
}

// Crash reproducers the fuzzers found: each must now go through the same
// calls without a crash, with verdicts that make sense.
TEST(CorpusReplay, CommandRegressionsReplayCleanly) {
    for (const std::string& file : listInputs(kCommandRegressions)) {
        const Bytes packet = readFile(std::string(kCommandRegressions) + "/" + file);
        for (const bool authRequired : {true, false}) {
            for (const Mode mode : kModes) {
                const CommandVerdict v = check(packet, authRequired, mode);
                CHECK_TEXT(v.reason < CommandReject::kCount, file.c_str());
                if (v.reason == CommandReject::kAccepted) {
                    CHECK_TEXT(test::decodesInRange(v), file.c_str());
                }
            }
        }
    }
}

TEST(CorpusReplay, TableRegressionsReplayCleanly) {
    for (const std::string& file : listInputs(kTableRegressions)) {
        const Bytes image = readFile(std::string(kTableRegressions) + "/" + file);
        const tables::TableCheck c = tables::checkTableImage(image.data(), image.size());
        CHECK_TEXT(static_cast<std::size_t>(c.reason) < tables::kTableRejectCount, file.c_str());
        CHECK_EQUAL_TEXT(c.ok(), roundTrips(image), file.c_str());
    }
}

TEST(CorpusReplay, PlanSeedsGiveTheVerdictTheirNameGives) {
    static plan_executive::Tpn plan;
    std::size_t valid = 0, invalid = 0;
    for (const std::string& file : listInputs(kPlanSeeds)) {
        const Bytes text = readFile(std::string(kPlanSeeds) + "/" + file);
        const plan_executive::ParseResult r =
            plan_executive::parsePlan(reinterpret_cast<const char*>(text.data()), text.size(), &plan);
        if (file.rfind("invalid.", 0) == 0) {
            const std::string reason = file.substr(8, file.size() - 8 - 5);  // between "invalid." and ".plan"
            const PlanSeedReason* expected = nullptr;
            for (const PlanSeedReason& k : kPlanSeedReasons) {
                expected = reason == k.name ? &k : expected;
            }
            CHECK_TEXT(expected != nullptr, ("no reason for plan seed " + file).c_str());
            CHECK_TEXT(r.error == expected->error, (file + ": " + plan_executive::toString(r.error)).c_str());
            ++invalid;
        } else {
            CHECK_TEXT(r.error == plan_executive::PlanError::kOk, (file + ": " + plan_executive::toString(r.error)).c_str());
            ++valid;
        }
    }
    CHECK(valid >= 6);
    CHECK(invalid >= 6);
}

TEST(CorpusReplay, PlanRegressionsReplayCleanly) {
    static plan_executive::Tpn plan;
    for (const std::string& file : listInputs(kPlanRegressions)) {
        const Bytes text = readFile(std::string(kPlanRegressions) + "/" + file);
        const plan_executive::ParseResult r =
            plan_executive::parsePlan(reinterpret_cast<const char*>(text.data()), text.size(), &plan);
        CHECK_TEXT(static_cast<std::size_t>(r.error) < plan_executive::kPlanErrorCount, file.c_str());
    }
}
