#include "sim_stub/cli/command_line.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace rse::sim::cli {

bool parseFiniteNumber(const std::string& text, double* value) {
    // strtod skips leading blanks: a value with one is not the whole string.
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) != 0) {
        return false;
    }
    char* end = nullptr;
    *value = std::strtod(text.c_str(), &end);
    return *end == '\0' && std::isfinite(*value);
}

bool parseWholeNumber(const std::string& text, std::uint64_t max, std::uint64_t* value) {
    if (text.empty() || text.size() > 20 || text.find_first_not_of("0123456789") != std::string::npos) {
        return false;
    }
    errno = 0;
    const unsigned long long parsed = std::strtoull(text.c_str(), nullptr, 10);
    if (errno != 0 || parsed > max) {
        return false;
    }
    *value = parsed;
    return true;
}

int usageError(std::FILE* err, const char* program, const std::string& what) {
    std::fprintf(err, "%s: %s\n%s: see '%s --help'\n", program, what.c_str(), program, program);
    return kExitUsage;
}

OptionScanner::OptionScanner(int argc, const char* const* argv, const char* shortOptions, const option* longOptions,
                             int first)
    // getopt_long scans from its argv[1]: the array is shifted so that its
    // argv[1] is our argv[first]. '+': stop at the first operand, and never
    // permute (so never write) argv; ':': a missing value is told apart.
    : argc_(argc - (first - 1)),
      argv_(const_cast<char* const*>(argv + (first - 1))),
      shortOptions_(std::string("+:") + shortOptions),
      longOptions_(longOptions),
      offset_(first - 1) {
    optind = 0;  // glibc: a full reset of getopt's state, so each scan starts afresh
    opterr = 0;
}

int OptionScanner::next() {
    value_ = nullptr;
    if (optionsOver_ || argc_ < 1) {
        ended_ = true;
        return kEnd;
    }
    const int at = optind == 0 ? 1 : optind;
    const char* element = at < argc_ ? argv_[at] : nullptr;
    const int c = getopt_long(argc_, argv_, shortOptions_.c_str(), longOptions_, nullptr);
    if (c == -1) {
        // getopt_long consumed a "--": what follows is operands only.
        optionsOver_ = element != nullptr && std::strcmp(element, "--") == 0;
        ended_ = true;
        return kEnd;
    }
    if (c == '?' || c == ':') {
        error_ = describe(c, element != nullptr ? element : "");
        return kBad;
    }
    value_ = optarg;
    return c;
}

// What is wrong with the option in `element`, naming it as it was typed.
std::string OptionScanner::describe(int code, const std::string& element) const {
    const bool isLong = element.rfind("--", 0) == 0;
    const std::string name = isLong ? element.substr(0, element.find('=')) : std::string("-") + static_cast<char>(optopt);
    if (code == ':') {
        return "option '" + name + "' needs a value";
    }
    if (isLong && optopt != 0 && element.find('=') != std::string::npos) {
        return "option '" + name + "' takes no value";  // a known option, given "=value"
    }
    return "unknown or incomplete option '" + (isLong ? element : name) + "'";
}

const char* OptionScanner::takeOperand() {
    const int at = optind == 0 ? 1 : optind;
    if (!ended_ || at >= argc_) {
        return nullptr;
    }
    optind = at + 1;
    ended_ = optionsOver_;  // scanning for options resumes unless "--" ended them
    return argv_[at];
}

int OptionScanner::index() const { return (optind == 0 ? 1 : optind) + offset_; }

}  // namespace rse::sim::cli
