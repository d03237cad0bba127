// rse-ground's option parsing (ground/cli_options.hpp): getopt_long over a
// command's words, the global options up to the sub-command, the messages of a
// bad command line and the strict numbers.
#include <sstream>
#include <string>
#include <vector>

#include "ground/cli_options.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::ground;

namespace {

const std::vector<CliOption> kRecordLike = {
    {"seconds", 0, true}, {"quiet", 0, false}, {nullptr, 'o', true}, {"cpp", 0, true}};

// The message of the UsageError parsing words throws ("" when none).
std::string refusal(const std::vector<std::string>& words, const std::string& where = "record") {
    try {
        (void)parseCliOptions(where, words, kRecordLike);
    } catch (const UsageError& e) {
        return e.what();
    }
    return "";
}

bool helpWanted(const std::vector<std::string>& words) {
    try {
        (void)parseCliOptions("record", words, kRecordLike);
    } catch (const HelpRequested&) {
        return true;
    }
    return false;
}

}  // namespace

TEST_GROUP(CliOptions){};

TEST(CliOptions, OptionsAndOperandsInAnyOrder) {
    const ParsedOptions p =
        parseCliOptions("record", {"a.rec", "--seconds", "5", "b", "--quiet", "-o", "out", "--seconds=7", "c"},
                        kRecordLike);
    CHECK_EQUAL(3U, p.operands.size());
    STRCMP_EQUAL("a.rec", p.operands[0].c_str());
    STRCMP_EQUAL("b", p.operands[1].c_str());
    STRCMP_EQUAL("c", p.operands[2].c_str());
    CHECK_TRUE(p.has("--quiet"));
    CHECK_FALSE(p.has("--cpp"));
    STRCMP_EQUAL("7", p.value("--seconds")->c_str());  // the last one given wins
    STRCMP_EQUAL("out", p.value("-o")->c_str());
    CHECK_FALSE(p.value("--cpp").has_value());
    CHECK_EQUAL(4U, p.given.size());
}

TEST(CliOptions, DoubleDashEndsTheOptions) {
    const ParsedOptions p = parseCliOptions("record", {"--quiet", "--", "--seconds", "-o"}, kRecordLike);
    CHECK_EQUAL(2U, p.operands.size());
    STRCMP_EQUAL("--seconds", p.operands[0].c_str());
    STRCMP_EQUAL("-o", p.operands[1].c_str());
}

TEST(CliOptions, GlobalOptionsStopAtTheSubCommand) {
    const ParsedOptions p = parseCliOptions(
        "", {"--timeout", "3", "--pad", "send", "NOOP", "--no-wait", "--timeout", "1"}, globalCliOptions(),
        OperandOrder::kOptionsFirst);
    STRCMP_EQUAL("3", p.value("--timeout")->c_str());
    CHECK_TRUE(p.has("--pad"));
    CHECK_EQUAL(5U, p.operands.size());
    STRCMP_EQUAL("send", p.operands[0].c_str());
    STRCMP_EQUAL("--no-wait", p.operands[2].c_str());
    STRCMP_EQUAL("1", p.operands[4].c_str());
}

TEST(CliOptions, ABadCommandLineIsNamed) {
    STRCMP_EQUAL("record: unknown option --bogus", refusal({"x", "--bogus"}).c_str());
    STRCMP_EQUAL("record: unknown option --bogus", refusal({"--bogus=1"}).c_str());
    STRCMP_EQUAL("record: unknown option -x", refusal({"-x"}).c_str());
    STRCMP_EQUAL("record: --seconds needs a value", refusal({"x", "--seconds"}).c_str());
    STRCMP_EQUAL("record: -o needs a value", refusal({"x", "-o"}).c_str());
    STRCMP_EQUAL("record: --quiet takes no value", refusal({"--quiet=yes"}).c_str());
    CHECK_TRUE(refusal({"f", "--udp", "h"}).find("--udp is a global option: give it before the command") !=
               std::string::npos);
    STRCMP_EQUAL("unknown option --bogus", refusal({"--bogus"}, "").c_str());  // the global options' parse
}

TEST(CliOptions, HelpAnywhere) {
    CHECK_TRUE(helpWanted({"--help"}));
    CHECK_TRUE(helpWanted({"f", "-h"}));
    CHECK_TRUE(helpWanted({"--quiet", "--help", "--bogus"}));
    CHECK_FALSE(helpWanted({"--quiet"}));
}

TEST(CliOptions, ParsesAgainAndAgain) {
    for (int i = 0; i < 3; ++i) {
        const ParsedOptions p = parseCliOptions("record", {"f", "--quiet"}, kRecordLike);
        CHECK_EQUAL(1U, p.operands.size());
        CHECK_TRUE(p.has("--quiet"));
    }
}

TEST(CliOptions, StrictNumbers) {
    CHECK_EQUAL(2.5, parsePositiveSeconds("--seconds", "2.5"));
    for (const char* bad : {"0", "-1", "x", "1s", "", " 1", "inf", "nan", "86401"}) {
        CHECK_THROWS(UsageError, parsePositiveSeconds("--seconds", bad));
    }
    CHECK_EQUAL(7, parseCount("--count", "7", 1, 10));
    for (const char* bad : {"0", "11", "1.5", "x", ""}) {
        CHECK_THROWS(UsageError, parseCount("--count", bad, 1, 10));
    }
    CHECK_EQUAL(0x6C0U, parseCanId("--can-tx", "6C0"));
    CHECK_EQUAL(0x7FFU, parseCanId("--can-tx", "0x7ff"));
    CHECK_THROWS(UsageError, parseCanId("--can-tx", "800"));
    try {
        (void)parseCount("--count", "0", 1, 10);
    } catch (const UsageError& e) {
        STRCMP_EQUAL("--count '0': expected a whole number 1..10", e.what());
    }
}

TEST(CliOptions, OperandsCounted) {
    const ParsedOptions none = parseCliOptions("record", {}, kRecordLike);
    const ParsedOptions two = parseCliOptions("record", {"a", "b"}, kRecordLike);
    expectOperands(two, 2, "record", "usage: U");
    try {
        expectOperands(none, 1, "record", "usage: U");
        FAIL("no error");
    } catch (const UsageError& e) {
        STRCMP_EQUAL("record: missing an operand (usage: U)", e.what());
    }
    try {
        expectOperands(two, 1, "record", "usage: U");
        FAIL("no error");
    } catch (const UsageError& e) {
        STRCMP_EQUAL("record: unexpected 'b' (usage: U)", e.what());
    }
}

TEST(CliOptions, AUsageErrorIsTwoLinesOnStderr) {
    std::ostringstream err;
    CHECK_EQUAL(2, reportUsageError(err, "GOTO: missing argument 'y'\nusage: GOTO x=X y=Y\n"));
    STRCMP_EQUAL("rse-ground: GOTO: missing argument 'y'; usage: GOTO x=X y=Y\nrse-ground: see 'rse-ground --help'\n",
                 err.str().c_str());
}

TEST(CliOptions, TheUsageNamesEveryCommandAndGlobalOption) {
    const std::string usage = groundUsage();
    for (const char* command : {"send", "watch", "record", "summary", "report", "resync", "run", "table load",
                                "table dump", "table build", "table show", "table check", "table list", "dict",
                                "plan check", "plan load", "plan short", "plan abort", "encode", "serve"}) {
        CHECK_TEXT(usage.find(std::string("  ") + command + " ") != std::string::npos ||
                       usage.find(std::string("  ") + command + "\n") != std::string::npos,
                   command);
    }
    for (const CliOption& o : globalCliOptions()) {
        CHECK_TEXT(usage.find(std::string("--") + o.longName) != std::string::npos, o.longName);
    }
}
