// rse-ground's command lines, parsed with getopt_long (docs/operations.md,
// "Command lines"): the global options before the sub-command, then each
// sub-command's own options and operands, in any order after it.
//
// A bad command line throws UsageError with one line naming the option and the
// value; runGroundCli (ground/ground_cli.cpp) prints it after "rse-ground: ",
// then "rse-ground: see 'rse-ground --help'", and exits 2. -h or --help
// anywhere throws HelpRequested: the usage text on stdout, exit 0.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <optional>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace rse::ground {

class UsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

// Not a std::exception, so that no catch of errors takes it for one.
struct HelpRequested {};

// One option a command takes: a long name ("count" for --count), a short one
// ('o' for -o), or both; with a value or not.
struct CliOption {
    const char* longName;  // nullptr: short only
    char shortName;        // 0: long only
    bool takesValue;
};

// What the command line held: the options in the order given, each named as
// the user may write it ("--count", "-o"; the long name when it has both) with
// its value ("" for a flag), and the operands, in order.
struct ParsedOptions {
    std::vector<std::pair<std::string, std::string>> given;
    std::vector<std::string> operands;

    bool has(const std::string& name) const;
    // The value of the last one given (a repeated option: the last wins).
    std::optional<std::string> value(const std::string& name) const;
};

enum class OperandOrder : std::uint8_t {
    kOptionsFirst,  // the first operand ends the options (the global options before a sub-command)
    kAnywhere,      // options and operands mixed (a sub-command's)
};

// Parses words (what follows the program or sub-command name) against options
// (-h/--help are always known). where ("send", "table load") starts every
// message. Throws UsageError for an unknown option, a missing value or a value
// given to a flag; HelpRequested for -h/--help.
ParsedOptions parseCliOptions(const std::string& where, const std::vector<std::string>& words,
                              const std::vector<CliOption>& options,
                              OperandOrder order = OperandOrder::kAnywhere);

// rse-ground's usage text: every command, its options and the global options
// (what --help prints, on stdout).
const char* groundUsage();

// The global options (ground/cli_context.hpp applies them); a sub-command that
// finds one among its own words says to give it before the sub-command.
std::vector<CliOption> globalCliOptions();

// Strict numbers: the whole text, finite, in range; UsageError naming the
// option and the text otherwise.
double parsePositiveSeconds(const std::string& option, const std::string& text);  // (0, 86400]
long long parseCount(const std::string& option, const std::string& text, long long min, long long max);
std::uint32_t parseCanId(const std::string& option, const std::string& text);  // hex, 000..7FF

// Exactly count operands, or UsageError: "where: missing an operand (usage)", or
// "where: unexpected 'X' (usage)" naming the first one too many.
void expectOperands(const ParsedOptions& parsed, std::size_t count, const std::string& where,
                    const std::string& usage);

// A bad command line as the convention reports it: "PROGRAM: what" (its lines
// joined with "; ": one line) and "PROGRAM: see 'PROGRAM --help'" on err;
// returns the exit code 2.
int reportUsageError(std::ostream& err, const std::string& what, const char* program = "rse-ground");

}  // namespace rse::ground
