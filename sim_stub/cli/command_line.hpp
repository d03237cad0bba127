// The command lines of the simulator's programs (rse-sim, rse-demo,
// rse-montecarlo), as docs/operations.md ("Command lines") has them: options
// parsed with getopt_long, opterr 0 (the program says what is wrong, in its
// own words), parsing stopped at the first operand (optstring '+': no
// permutation, so argv is never written), values checked by the strict number
// helpers below, and a bad command line told in one line on stderr followed
// by a pointer to --help, exit status 2.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <getopt.h>

#include <cstdint>
#include <cstdio>
#include <string>

namespace rse::sim::cli {

// The exit status of a bad command line (every program of the project).
constexpr int kExitUsage = 2;

// A whole string as a finite number (strtod's syntax; no leading blank, no
// trailing character). False leaves *value unspecified.
bool parseFiniteNumber(const std::string& text, double* value);
// A whole string of decimal digits (no sign, no blank) as a number <= max.
bool parseWholeNumber(const std::string& text, std::uint64_t max, std::uint64_t* value);

// The bad command line: "PROGRAM: what" and "PROGRAM: see 'PROGRAM --help'"
// on err. Returns kExitUsage.
int usageError(std::FILE* err, const char* program, const std::string& what);

// One pass of getopt_long over a command line. Options are given as to
// getopt_long (shortOptions without a leading '+' or ':': the scanner adds
// both). It resets getopt's state (optind 0) when constructed, so a program
// or a test may parse several command lines one after the other, never two
// at once.
class OptionScanner {
public:
    static constexpr int kEnd = -1;  // no more options: an operand, "--", or the end
    static constexpr int kBad = '?';  // an unknown option or a missing value: error() says which

    // argv[first] is the first element scanned (1: after the program's name).
    OptionScanner(int argc, const char* const* argv, const char* shortOptions, const option* longOptions,
                  int first = 1);
    // The next option's val (the long option's val, or the short option's
    // letter), kEnd or kBad.
    int next();
    // The value of the option next() returned (nullptr: none).
    const char* value() const { return value_; }
    const std::string& error() const { return error_; }
    // After kEnd: the next operand, scanning on for options after it unless
    // "--" was seen (nullptr: none left). Commands whose operands and options
    // mix (rse-montecarlo merge FILE... --table FILE) call it, then next() again.
    const char* takeOperand();
    // The index of the first element not scanned yet (the first operand after kEnd).
    int index() const;

private:
    std::string describe(int code, const std::string& element) const;

    int argc_;
    char* const* argv_;
    std::string shortOptions_;
    const option* longOptions_;
    int offset_;  // our index of getopt_long's argv[0]
    const char* value_ = nullptr;
    std::string error_;
    bool ended_ = false;        // next() returned kEnd: takeOperand() may take one
    bool optionsOver_ = false;  // "--" seen: every element after it is an operand
};

}  // namespace rse::sim::cli
