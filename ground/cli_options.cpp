#include "ground/cli_options.hpp"

#include <getopt.h>

#include <cmath>
#include <cstring>
#include <ostream>

#include "ground/text_format.hpp"

namespace rse::ground {
namespace {

constexpr int kFirstLongOnlyKey = 256;  // getopt_long's val for long-only options: above every char

// getopt_long's val for options[i].
int keyOf(const std::vector<CliOption>& options, std::size_t i) {
    return options[i].shortName != 0 ? options[i].shortName : kFirstLongOnlyKey + static_cast<int>(i);
}

// How the user writes the option with this val: "--count", "-o".
std::string nameOf(const std::vector<CliOption>& options, int key) {
    if (key == 'h') {
        return "--help";
    }
    for (std::size_t i = 0; i < options.size(); ++i) {
        if (keyOf(options, i) == key) {
            return options[i].longName != nullptr ? std::string("--") + options[i].longName
                                                  : std::string("-") + options[i].shortName;
        }
    }
    return std::string("-") + static_cast<char>(key);
}

// getopt_long's two descriptions of the options: the short letters and the long table.
struct GetoptTables {
    std::string shortOptions;
    std::vector<option> longOptions;
};

GetoptTables getoptTables(const std::vector<CliOption>& options, OperandOrder order) {
    GetoptTables t;
    // '+': stop at the first operand. '-': hand every operand back in place (key
    // 1), whatever POSIXLY_CORRECT says. ':' then: a missing value is ':', not '?'.
    t.shortOptions = order == OperandOrder::kOptionsFirst ? "+:h" : "-:h";
    for (std::size_t i = 0; i < options.size(); ++i) {
        const CliOption& o = options[i];
        if (o.shortName != 0) {
            t.shortOptions += o.shortName;
            t.shortOptions += o.takesValue ? ":" : "";
        }
        if (o.longName != nullptr) {
            t.longOptions.push_back(option{o.longName, o.takesValue ? required_argument : no_argument, nullptr,
                                           keyOf(options, i)});
        }
    }
    t.longOptions.push_back(option{"help", no_argument, nullptr, 'h'});
    t.longOptions.push_back(option{nullptr, 0, nullptr, 0});
    return t;
}

bool isGlobalOption(const std::string& longName) {
    for (const CliOption& o : globalCliOptions()) {
        if (longName == o.longName) {
            return true;
        }
    }
    return false;
}

// The message for an option getopt_long refused ('?'): written is the word as
// given ("--bogus=1", "-x").
std::string refusal(const std::string& where, const std::string& written, const std::vector<CliOption>& options) {
    const std::string prefix = where.empty() ? std::string() : where + ": ";
    if (written.rfind("--", 0) != 0) {
        return prefix + "unknown option " + nameOf(options, optopt);
    }
    const std::string name = written.substr(0, written.find('='));
    if (optopt != 0 && name.size() < written.size()) {
        return prefix + name + " takes no value";
    }
    if (!where.empty() && isGlobalOption(name.substr(2))) {
        return prefix + name + " is a global option: give it before the command (rse-ground [global options] " +
               where + " ...)";
    }
    return prefix + "unknown option " + name;
}

}  // namespace

bool ParsedOptions::has(const std::string& name) const {
    for (const auto& [option, value] : given) {
        if (option == name) {
            return true;
        }
    }
    return false;
}

std::optional<std::string> ParsedOptions::value(const std::string& name) const {
    std::optional<std::string> last;
    for (const auto& [option, value] : given) {
        if (option == name) {
            last = value;
        }
    }
    return last;
}

ParsedOptions parseCliOptions(const std::string& where, const std::vector<std::string>& words,
                              const std::vector<CliOption>& options, OperandOrder order) {
    // getopt_long wants a C argv it may reorder: a copy of the words behind where.
    std::vector<std::string> storage(1, where.empty() ? std::string("rse-ground") : where);
    storage.insert(storage.end(), words.begin(), words.end());
    std::vector<char*> argv;
    for (std::string& s : storage) {
        argv.push_back(s.data());
    }
    argv.push_back(nullptr);
    const int argc = static_cast<int>(storage.size());
    const GetoptTables tables = getoptTables(options, order);
    const std::string prefix = where.empty() ? std::string() : where + ": ";
    ParsedOptions parsed;
    opterr = 0;  // the messages are ours
    optind = 0;  // glibc: start afresh (every parse in a process, the sub-command's after the global one)
    // Bounded: each call takes at least one character of one word.
    for (std::size_t calls = 0; calls <= storage.size() + words.size(); ++calls) {
        const int key = getopt_long(argc, argv.data(), tables.shortOptions.c_str(), tables.longOptions.data(), nullptr);
        if (key == -1) {
            break;
        }
        if (key == 'h') {
            throw HelpRequested{};
        }
        if (key == ':') {
            throw UsageError(prefix + nameOf(options, optopt) + " needs a value");
        }
        if (key == '?') {
            throw UsageError(refusal(where, optind > 0 ? argv[static_cast<std::size_t>(optind - 1)] : "", options));
        }
        if (key == 1) {
            parsed.operands.emplace_back(optarg);
        } else {
            parsed.given.emplace_back(nameOf(options, key), optarg != nullptr ? optarg : "");
        }
    }
    // With '+', what follows the first operand (or "--") is all operands.
    for (int i = optind; i < argc; ++i) {
        parsed.operands.emplace_back(argv[static_cast<std::size_t>(i)]);
    }
    return parsed;
}

const char* groundUsage() {
    return "usage: rse-ground [global options] COMMAND [options and operands in any order]\n"
           "commands:\n"
           "  send NAME [arg=value ...] [--auth-seq N] [--no-wait]   send a command, print its CMD_ACK\n"
           "  watch [--count N] [--seconds S] [--only NAME,...]     print telemetry and events as they come\n"
           "  record FILE [--seconds S] [--until-outcome] [--tail S] [--quiet]\n"
           "                                                        record every packet received, with its time\n"
           "  summary FILE [--facts] [--no-events]                  the mission a recording's telemetry shows\n"
           "  report FILE [--map MAP] [--tables DIR] [--out DIR] [--name TEXT]\n"
           "                                                        the ten points, report.md and map.svg from a recording\n"
           "  resync [--auth-seq N]                                 AUTH_RESYNC with the nonce of the rover's next HK\n"
           "  run SCRIPT [--verbose]                                run a command script (docs/ground.md)\n"
           "  table load IMAGE.tbl [--activate] [--force]           upload, validate (and activate) a table\n"
           "  table dump ID|NAME [--inactive] [-o FILE]             download a table image and print it\n"
           "  table build SRC.toml -o OUT.tbl                       compile a table source into an image\n"
           "  table build --cpp OUT.cpp SRC.toml...                 the default images as C++ (the build's)\n"
           "  table show IMAGE.tbl|SRC.toml                         print a table image or source, checked\n"
           "  table check IMAGE.tbl                                 check a table image as the rover would\n"
           "  table list                                            every table and its fields\n"
           "  dict --markdown|--json [-o FILE]                      export the command/telemetry dictionary\n"
           "  plan check FILE [--failed C,...] [--degraded C,...]   check a mission plan with the flight code\n"
           "  plan load FILE [--failed C,...] [--degraded C,...] [--force]\n"
           "                                                        check, upload (PLAN_LOAD chunks, PLAN_START), verdict\n"
           "  plan short TEXT [--failed C,...] [--degraded C,...] [--force]\n"
           "                                                        the same for a plan in one PLAN_SHORT (';' lines)\n"
           "  plan abort                                            stop the plan running (PLAN_ABORT)\n"
           "                                                        components C: drive_FL drive_ML drive_RL drive_FR\n"
           "                                                        drive_MR drive_RR grinder camera\n"
           "  map check IMAGE                                       check a site map image with the flight check\n"
           "  map load IMAGE                                        check, upload (MAP_LOAD chunks, MAP_COMMIT), verdict\n"
           "  map abort                                             drop a site map upload (MAP_ABORT)\n"
           "  encode NAME [arg=value ...] [--auth-seq N] [-o FILE]  write a command packet (hex without -o)\n"
           "  serve [--http [ADDR:]PORT] [--archive FILE] [--web DIR] [--tables DIR] [--seconds S]\n"
           "                                                        mission control: telemetry archived and served to\n"
           "                                                        Open MCT over HTTP and WebSocket (default\n"
           "                                                        127.0.0.1:8090; docs/mission_control.md)\n"
           "  help                                                  this text (also -h or --help anywhere)\n"
           "global options (before the command):\n"
           "  --udp HOST[:PORT]        commands to HOST:PORT over UDP (default 127.0.0.1:1234)\n"
           "  --tlm-port [ADDR:]PORT   receive telemetry on ADDR:PORT (default 0.0.0.0:1235)\n"
           "  --can IFACE              ISO-TP on a SocketCAN interface instead of UDP\n"
           "  --can-tx ID --can-rx ID  ISO-TP ids in hex (default 6C0 and 6C1); --pad pads frames to 8 bytes\n"
           "  --key-file FILE          command keys, one ID:64hex a line (default: the built-in lab key, id 1)\n"
           "  --key-id N               which key of the file (default: its first)\n"
           "  --no-auth                unauthenticated commands (key id 0): only a lab-setting rover takes them\n"
           "  --state-dir DIR          anti-replay sequence state (default $RSE_GROUND_STATE or ~/.rse-ground)\n"
           "  --timeout S              how long to wait for an acknowledgement (default 2)\n"
           "exit: 0 ok/accepted, 1 link error/no acknowledgement/script failed, 2 bad command line or argument\n"
           "      (nothing sent), 3 rejected by the rover (report: not all ten points in order)\n";
}

std::vector<CliOption> globalCliOptions() {
    // A new vector each time: a static one would be heap the leak checks of the suites count.
    return {
        {"udp", 0, true},      {"tlm-port", 0, true},  {"can", 0, true},       {"can-tx", 0, true},
        {"can-rx", 0, true},   {"pad", 0, false},      {"key-file", 0, true},  {"key-id", 0, true},
        {"no-auth", 0, false}, {"state-dir", 0, true}, {"timeout", 0, true},
    };
}

double parsePositiveSeconds(const std::string& option, const std::string& text) {
    double value = 0.0;
    if (!parseDouble(text, &value) || !std::isfinite(value) || value <= 0.0 || value > 86400.0) {
        throw UsageError(option + " '" + text + "': expected seconds, a number > 0");
    }
    return value;
}

long long parseCount(const std::string& option, const std::string& text, long long min, long long max) {
    long long value = 0;
    if (!parseInteger(text, &value) || value < min || value > max) {
        throw UsageError(option + " '" + text + "': expected a whole number " + std::to_string(min) + ".." +
                         std::to_string(max));
    }
    return value;
}

std::uint32_t parseCanId(const std::string& option, const std::string& text) {
    long long value = 0;
    const std::string hex = text.rfind("0x", 0) == 0 || text.rfind("0X", 0) == 0 ? text : "0x" + text;
    if (!parseInteger(hex, &value) || value < 0 || value > 0x7FF) {
        throw UsageError(option + " '" + text + "': expected an 11-bit CAN id in hex (000..7FF)");
    }
    return static_cast<std::uint32_t>(value);
}

void expectOperands(const ParsedOptions& parsed, std::size_t count, const std::string& where,
                    const std::string& usage) {
    if (parsed.operands.size() < count) {
        throw UsageError(where + ": missing " + (count - parsed.operands.size() == 1 ? "an operand" : "operands") +
                         " (" + usage + ")");
    }
    if (parsed.operands.size() > count) {
        throw UsageError(where + ": unexpected '" + parsed.operands[count] + "' (" + usage + ")");
    }
}

int reportUsageError(std::ostream& err, const std::string& what, const char* program) {
    // One line: a message of several (a command's usage under its error) joined.
    std::string line = what;
    for (std::size_t at = line.find('\n'); at != std::string::npos; at = line.find('\n', at)) {
        line.replace(at, 1, at + 1 < line.size() ? "; " : "");
    }
    err << program << ": " << line << "\n" << program << ": see '" << program << " --help'\n";
    return 2;
}

}  // namespace rse::ground
