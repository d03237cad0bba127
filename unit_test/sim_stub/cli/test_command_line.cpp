// The simulator programs' command-line helpers (sim_stub/cli/command_line.hpp):
// strict numbers (the whole string, finite, in range), the usage error's two
// lines, and the getopt_long scanner: options and their values, the bad ones
// named as typed, parsing stopped at the first operand (argv never permuted),
// operands mixed with options for the commands that take both, "--", and a
// fresh start for every scanner.
#include <cstdio>
#include <string>
#include <vector>

#include "sim_stub/cli/command_line.hpp"

#include "CppUTest/TestHarness.h"

using rse::sim::cli::OptionScanner;

namespace {

enum : int { kAlpha = 1000, kBeta, kQuiet };
const option kLong[] = {
    {"alpha", required_argument, nullptr, kAlpha},
    {"beta", required_argument, nullptr, kBeta},
    {"quiet", no_argument, nullptr, kQuiet},
    {"help", no_argument, nullptr, 'h'},
    {nullptr, 0, nullptr, 0},
};

// One scan of args (the program's name first), as "val=value" words; a bad
// option as "BAD:<error>", the end as "END@<index>".
std::vector<std::string> scan(std::vector<const char*> args, bool operandsToo = false) {
    args.insert(args.begin(), "prog");
    OptionScanner s(static_cast<int>(args.size()), args.data(), "h", kLong);
    std::vector<std::string> seen;
    for (int guard = 0; guard < 32; ++guard) {
        const int c = s.next();
        if (c == OptionScanner::kBad) {
            seen.push_back("BAD:" + s.error());
            return seen;
        }
        if (c == OptionScanner::kEnd) {
            const char* operand = operandsToo ? s.takeOperand() : nullptr;
            if (operand == nullptr) {
                seen.push_back("END@" + std::to_string(s.index()));
                return seen;
            }
            seen.push_back(std::string("operand=") + operand);
            continue;
        }
        seen.push_back(std::to_string(c) + "=" + (s.value() != nullptr ? s.value() : ""));
    }
    FAIL("the scan did not end");
    return seen;
}

std::string joined(const std::vector<std::string>& v) {
    std::string s;
    for (const std::string& w : v) {
        s += (s.empty() ? "" : " ") + w;
    }
    return s;
}

}  // namespace

TEST_GROUP(CliNumbers){};

TEST(CliNumbers, AFiniteNumberIsTheWholeString) {
    double v = 0.0;
    CHECK_TRUE(rse::sim::cli::parseFiniteNumber("2.5", &v));
    DOUBLES_EQUAL(2.5, v, 0.0);
    CHECK_TRUE(rse::sim::cli::parseFiniteNumber("-1e-3", &v));
    DOUBLES_EQUAL(-1e-3, v, 0.0);
    for (const char* bad : {"", " 2", "2 ", "2s", "x", "nan", "inf", "-inf", "1e999", "--2"}) {
        if (rse::sim::cli::parseFiniteNumber(bad, &v)) {
            FAIL((std::string("'") + bad + "' was taken as a number").c_str());
        }
    }
}

TEST(CliNumbers, AWholeNumberIsDigitsOnlyWithinItsMaximum) {
    std::uint64_t v = 0;
    CHECK_TRUE(rse::sim::cli::parseWholeNumber("0", 10, &v));
    LONGS_EQUAL(0, v);
    CHECK_TRUE(rse::sim::cli::parseWholeNumber("10", 10, &v));
    LONGS_EQUAL(10, v);
    CHECK_TRUE(rse::sim::cli::parseWholeNumber("18446744073709551615", UINT64_MAX, &v));
    CHECK_TRUE(v == UINT64_MAX);
    for (const char* bad : {"", "11", "-1", "+1", " 1", "1 ", "1.0", "0x1", "18446744073709551616"}) {
        if (rse::sim::cli::parseWholeNumber(bad, bad[0] == '1' && bad[1] == '8' ? UINT64_MAX : 10, &v)) {
            FAIL((std::string("'") + bad + "' was taken as a whole number").c_str());
        }
    }
}

TEST(CliNumbers, AUsageErrorIsOneLineAndThePointerToHelpOnErrExitTwo) {
    std::FILE* err = std::tmpfile();
    CHECK(err != nullptr);
    LONGS_EQUAL(2, rse::sim::cli::usageError(err, "rse-x", "--y '3' is not a z"));
    std::rewind(err);
    char text[256] = {};
    const std::size_t n = std::fread(text, 1, sizeof text - 1, err);
    STRCMP_EQUAL("rse-x: --y '3' is not a z\nrse-x: see 'rse-x --help'\n", std::string(text, n).c_str());
    std::fclose(err);
}

TEST_GROUP(CliOptionScanner){};

TEST(CliOptionScanner, OptionsAndTheirValuesInEitherForm) {
    STRCMP_EQUAL("1000=a 1001=b 1002= 104= END@6",
                 joined(scan({"--alpha", "a", "--beta=b", "--quiet", "-h"})).c_str());
    // A value may start with '-': it is the option's, as before getopt.
    STRCMP_EQUAL("1000=-3 END@3", joined(scan({"--alpha", "-3"})).c_str());
    // Unambiguous abbreviations are getopt_long's.
    STRCMP_EQUAL("1001=7 END@3", joined(scan({"--be", "7"})).c_str());
}

TEST(CliOptionScanner, BadOptionsAreNamedAsTyped) {
    STRCMP_EQUAL("BAD:unknown or incomplete option '--fast'", joined(scan({"--fast"})).c_str());
    STRCMP_EQUAL("BAD:unknown or incomplete option '--fast=1'", joined(scan({"--fast=1"})).c_str());
    STRCMP_EQUAL("BAD:unknown or incomplete option '-x'", joined(scan({"-x"})).c_str());
    STRCMP_EQUAL("104= BAD:unknown or incomplete option '-x'", joined(scan({"-hx"})).c_str());
    STRCMP_EQUAL("BAD:option '--alpha' needs a value", joined(scan({"--alpha"})).c_str());
    STRCMP_EQUAL("1002= BAD:option '--beta' needs a value", joined(scan({"--quiet", "--beta"})).c_str());
    STRCMP_EQUAL("BAD:option '--quiet' takes no value", joined(scan({"--quiet=yes"})).c_str());
}

TEST(CliOptionScanner, ScanningStopsAtTheFirstOperandAndLeavesArgvAsItWas) {
    std::vector<const char*> args = {"prog", "--quiet", "run", "--alpha", "1"};
    const std::vector<const char*> before = args;
    OptionScanner s(static_cast<int>(args.size()), args.data(), "h", kLong);
    LONGS_EQUAL(kQuiet, s.next());
    LONGS_EQUAL(OptionScanner::kEnd, s.next());
    LONGS_EQUAL(2, s.index());
    CHECK_TRUE(args == before);
    // A second scanner from the operand on: the sub-command's options.
    OptionScanner sub(static_cast<int>(args.size()), args.data(), "h", kLong, s.index() + 1);
    LONGS_EQUAL(kAlpha, sub.next());
    STRCMP_EQUAL("1", sub.value());
    LONGS_EQUAL(OptionScanner::kEnd, sub.next());
    LONGS_EQUAL(5, sub.index());
}

TEST(CliOptionScanner, OperandsMixedWithOptionsAndEverythingAfterTwoDashes) {
    STRCMP_EQUAL("operand=a 1002= operand=b 1000=1 operand=c END@7",
                 joined(scan({"a", "--quiet", "b", "--alpha", "1", "c"}, true)).c_str());
    STRCMP_EQUAL("1002= operand=--alpha operand=x END@5", joined(scan({"--quiet", "--", "--alpha", "x"}, true)).c_str());
    STRCMP_EQUAL("operand=a operand=--quiet END@4", joined(scan({"a", "--", "--quiet"}, true)).c_str());
}

TEST(CliOptionScanner, EveryScannerStartsAfresh) {
    // A scan left in the middle of "-hx" (at the bad 'x') ...
    STRCMP_EQUAL("104= BAD:unknown or incomplete option '-x'", joined(scan({"-hx"})).c_str());
    // ... does not leak into the next one.
    STRCMP_EQUAL("1002= END@2", joined(scan({"--quiet"})).c_str());
    STRCMP_EQUAL("END@1", joined(scan({})).c_str());
}
