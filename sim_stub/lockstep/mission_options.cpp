#include "sim_stub/lockstep/mission_options.hpp"

#include <arpa/inet.h>

#include <cstdlib>

#include "ground/command_encoder.hpp"
#include "sim_stub/cli/command_line.hpp"

namespace rse::sim {

namespace {

// GOTO x, y, risk into the options, checked against the dictionary's ranges
// by the ground's encoder (*error: its reason).
bool encodeGoto(double x, double y, double risk, MissionOptions* o, std::string* error) {
    try {
        o->gotoArgs = ground::encodeArguments(
            *ground::lookupCommand("GOTO"),
            {encoderArgument("x", x), encoderArgument("y", y), encoderArgument("risk", risk)});
    } catch (const ground::CommandError& e) {
        // The reason only: the encoder's usage line after it is the ground tool's.
        const std::string why = e.what();
        *error = why.substr(0, why.find('\n'));
        return false;
    }
    o->goalX = x;
    o->goalY = y;
    o->risk = risk;
    return true;
}

// "X,Y[,RISK]" into the options, checked against the dictionary's GOTO ranges.
bool parseGoto(const std::string& text, MissionOptions* o, std::string* error) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma = text.find(','); comma != std::string::npos; comma = text.find(',', start)) {
        fields.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    fields.push_back(text.substr(start));
    if (fields.size() < 2 || fields.size() > 3) {
        *error = "--goto '" + text + "': expected X,Y or X,Y,RISK";
        return false;
    }
    if (fields.size() == 2) {
        fields.push_back("1e-3");
    }
    double v[3] = {};
    for (std::size_t i = 0; i < 3; ++i) {
        if (!cli::parseFiniteNumber(fields[i], &v[i])) {
            *error = "--goto '" + text + "': '" + fields[i] + "' is not a number";
            return false;
        }
    }
    if (!encodeGoto(v[0], v[1], v[2], o, error)) {
        *error = "--goto '" + text + "': " + *error;
        return false;
    }
    return true;
}

// A UDP port, 1..65535, as a whole number.
bool parsePort(const std::string& text, std::uint16_t* port) {
    std::uint64_t value = 0;
    if (!cli::parseWholeNumber(text, 65535, &value) || value == 0) {
        return false;
    }
    *port = static_cast<std::uint16_t>(value);
    return true;
}

// A numeric IPv4 address, as hal::UdpPacketLink takes it (it looks up no names).
bool isIpv4(const std::string& text) {
    in_addr parsed{};
    return inet_pton(AF_INET, text.c_str(), &parsed) == 1;
}

// "HOST:PORT" (or, hostOptional, "PORT" alone: *host left as it is) for the
// option `option`; *error says what is wrong.
bool parseUdpAddress(const std::string& option, const std::string& text, bool hostOptional, std::string* host,
                     std::uint16_t* port, std::string* error) {
    const std::size_t colon = text.rfind(':');
    if (colon == std::string::npos && !hostOptional) {
        *error = option + " '" + text + "': expected HOST:PORT (e.g. 127.0.0.1:1235)";
        return false;
    }
    const std::string address = colon == std::string::npos ? *host : text.substr(0, colon);
    const std::string number = colon == std::string::npos ? text : text.substr(colon + 1);
    if (!isIpv4(address)) {
        *error = option + " '" + text + "': '" + address + "' is not a numeric IPv4 address (no names are looked up)";
        return false;
    }
    if (!parsePort(number, port)) {
        *error = option + " '" + text + "': '" + number + "' is not a port in 1..65535";
        return false;
    }
    *host = address;
    return true;
}

// A number of seconds in [lo, hi] (lowOpen: in (lo, hi]; `range` says which)
// for `option`.
bool parseSeconds(const char* option, const std::string& text, double lo, bool lowOpen, double hi,
                  const char* range, double* value, std::string* error) {
    if (cli::parseFiniteNumber(text, value) && (lowOpen ? *value > lo : *value >= lo) && *value <= hi) {
        return true;
    }
    *error = std::string(option) + " '" + text + "' is not a number of seconds in " + range;
    return false;
}

bool parsePace(const std::string& text, double* pace, std::string* error) {
    if (cli::parseFiniteNumber(text, pace) && *pace >= kMinPace && *pace <= kMaxPace) {
        return true;
    }
    char range[64];
    std::snprintf(range, sizeof range, "[%g, %g]", kMinPace, kMaxPace);
    *error = "--pace '" + text + "' is not a factor over real time in " + range +
             " (1: real time; leave --pace out to run as fast as the CPU allows)";
    return false;
}

// The long options (every one of rse-demo's); -h is --help's short form.
enum : int {
    kOptScenario = 1000,
    kOptNoFaults,
    kOptGoto,
    kOptDuration,
    kOptCommandAt,
    kOptQuiet,
    kOptReport,
    kOptNoReport,
    kOptAnyOutcome,
    kOptPace,
    kOptUdpTelemetry,
    kOptUdpCommands,
};
const option kMissionLongOptions[] = {
    {"scenario", required_argument, nullptr, kOptScenario},
    {"no-faults", no_argument, nullptr, kOptNoFaults},
    {"goto", required_argument, nullptr, kOptGoto},
    {"duration", required_argument, nullptr, kOptDuration},
    {"command-at", required_argument, nullptr, kOptCommandAt},
    {"quiet", no_argument, nullptr, kOptQuiet},
    {"report", required_argument, nullptr, kOptReport},
    {"no-report", no_argument, nullptr, kOptNoReport},
    {"any-outcome", no_argument, nullptr, kOptAnyOutcome},
    {"pace", required_argument, nullptr, kOptPace},
    {"udp-telemetry", required_argument, nullptr, kOptUdpTelemetry},
    {"udp-commands", required_argument, nullptr, kOptUdpCommands},
    {"help", no_argument, nullptr, 'h'},
    {nullptr, 0, nullptr, 0},
};

// One option (its id from the scanner) and its value into *o; false with
// the reason in *error.
bool applyOption(int id, const std::string& value, MissionOptions* o, std::string* error) {
    switch (id) {
        case kOptScenario: o->scenarioPath = value; return true;
        case kOptNoFaults: o->clearFaults = true; return true;
        case kOptGoto: return parseGoto(value, o, error);
        case kOptDuration:
            return parseSeconds("--duration", value, 0.0, true, 1e6, "(0, 1e6]", &o->durationS, error);
        case kOptCommandAt:
            return parseSeconds("--command-at", value, 0.0, false, 1e5, "[0, 1e5]", &o->commandAtS, error);
        case kOptQuiet: o->quiet = true; return true;
        case kOptReport:
            o->reportDir = value;
            if (o->reportDir.empty()) {
                *error = "--report wants a folder";
                return false;
            }
            return true;
        case kOptNoReport:
            o->reportDir.clear();
            o->noReport = true;
            return true;
        case kOptAnyOutcome: o->anyOutcome = true; return true;
        case kOptPace: return parsePace(value, &o->pace, error);
        case kOptUdpTelemetry:
            return parseUdpAddress("--udp-telemetry", value, false, &o->udpTelemetryHost, &o->udpTelemetryPort, error);
        case kOptUdpCommands:
            return parseUdpAddress("--udp-commands", value, true, &o->udpCommandHost, &o->udpCommandPort, error);
        default: break;
    }
    *error = "option " + std::to_string(id) + " is not rse-demo's";  // a table entry without a case
    return false;
}

// The UDP link's two options together: a command port needs the telemetry's
// address, and must not be it.
bool udpOptionsAgree(const MissionOptions& o, std::string* error) {
    if (o.udpCommandPort != 0 && o.udpTelemetryHost.empty()) {
        *error = "--udp-commands is the UDP link's command port: it wants --udp-telemetry HOST:PORT too";
        return false;
    }
    // The link would read its own telemetry as commands (each refused, counted).
    if (o.udpCommandPort != 0 && o.udpCommandPort == o.udpTelemetryPort &&
        (o.udpCommandHost == o.udpTelemetryHost || o.udpCommandHost == "0.0.0.0")) {
        *error = "--udp-commands and --udp-telemetry name the same address: telemetry would come back as commands";
        return false;
    }
    return true;
}

}  // namespace

std::string encoderArgument(const char* name, double v) {
    char text[40];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, v);
        if (std::strtod(text, nullptr) == v) {
            break;
        }
    }
    return std::string(name) + "=" + text;
}

void printMissionUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-demo [--scenario FILE] [--no-faults] [--goto X,Y[,RISK]] [--duration SECONDS] [--quiet]\n"
                 "                [--command-at SECONDS] [--report DIR | --no-report] [--any-outcome]\n"
                 "                [--pace F] [--udp-telemetry HOST:PORT [--udp-commands [ADDR:]PORT]]\n"
                 "       rse-demo --help\n"
                 "  --scenario FILE     TOML scenario (default %s);\n"
                 "                      its [mission] (a goal and risk bound, or a plan) is flown\n"
                 "                      unless --goto is given\n"
                 "  --no-faults         leave the scenario's faults out\n"
                 "  --goto X,Y[,RISK]   the goal in metres and the risk bound (RISK default 1e-3; without\n"
                 "                      --goto: the scenario's [mission], else 20,0,1e-3)\n"
                 "  --duration SECONDS  simulated seconds at most, boot included (default: the scenario's\n"
                 "                      duration_s when it has a [mission], else 180)\n"
                 "  --command-at SECONDS  SET_MODE and GOTO (or the plan) at this simulated time at the\n"
                 "                      earliest (default: once the drives are up and the map uploaded)\n"
                 "  --quiet             no console lines, only the points and the summary\n"
                 "  --report DIR        write the mission report and map to DIR/report.md, DIR/map.svg\n"
                 "                      (default %s); --no-report writes none\n"
                 "  --any-outcome       exit 0 whatever the mission showed (else 3 when the ten points\n"
                 "                      of the RSE demonstration were not all seen, in order)\n"
                 "  --pace F            run F times faster than real time against the wall clock (1: real\n"
                 "                      time, 10: ten times; %g..%g; default: as fast as the CPU allows);\n"
                 "                      frames reached late run at once and are reported (\"behind by up to\")\n"
                 "  --udp-telemetry HOST:PORT  also send every telemetry packet and event as UDP datagrams\n"
                 "                      to HOST:PORT (numeric IPv4), rse-fsw --udp's link, e.g. for\n"
                 "                      rse-ground --tlm-port PORT watch or serve\n"
                 "  --udp-commands [ADDR:]PORT  that link's command port (ADDR default %s; default:\n"
                 "                      an unannounced port the kernel picks on 127.0.0.1)\n"
                 "  -h, --help          this text (on stdout, exit status 0)\n"
                 "Runs rse-fsw and rse-sim in lockstep, sends SET_MODE AUTONOMOUS and GOTO through the\n"
                 "authenticated ground link and runs until the rover reaches the goal, calls home or the\n"
                 "duration passes, printing the ten points as the flight software shows them.\n"
                 "Exit status: 0 the mission ran and showed the ten points in order, 3 it ran but did not,\n"
                 "1 setup failure (or the report not written), 2 bad usage (one line on stderr says why).\n",
                 kDefaultMissionScenario, kDefaultReportDir, kMinPace, kMaxPace, kDefaultUdpCommandHost);
}

ParseOutcome parseMissionArgs(int argc, const char* const* argv, MissionOptions* o, std::string* error) {
    cli::OptionScanner scanner(argc, argv, "h", kMissionLongOptions);
    for (int id = scanner.next(); id != cli::OptionScanner::kEnd; id = scanner.next()) {
        if (id == cli::OptionScanner::kBad) {
            *error = scanner.error();
            return ParseOutcome::kUsageError;
        }
        if (id == 'h') {
            return ParseOutcome::kHelp;
        }
        if (!applyOption(id, scanner.value() != nullptr ? scanner.value() : "", o, error)) {
            return ParseOutcome::kUsageError;
        }
    }
    if (scanner.index() < argc) {
        *error = std::string("unexpected argument '") + argv[scanner.index()] + "' (rse-demo takes options only)";
        return ParseOutcome::kUsageError;
    }
    return udpOptionsAgree(*o, error) ? ParseOutcome::kRun : ParseOutcome::kUsageError;
}

bool applyScenarioMission(const Scenario& scenario, MissionOptions* o, std::string* error) {
    const MissionSpec& m = scenario.mission;
    if (!(o->durationS > 0.0)) {
        o->durationS = m.present ? scenario.durationS : kDefaultMissionDurationS;
    }
    if (!o->gotoArgs.empty() || !o->planText.empty()) {
        return true;  // the command line's goal (or already applied)
    }
    if (m.present && !m.hasGoal) {
        o->planText = m.planText;
        o->planFile = m.planFile;
        o->risk = m.riskBound;
        return true;
    }
    const bool own = m.present && m.hasGoal;
    if (!encodeGoto(own ? m.goalX : kDefaultGoalX, own ? m.goalY : kDefaultGoalY,
                    own ? m.riskBound : kDefaultMissionRiskBound, o, error)) {
        *error = scenario.source + ": [mission]: " + *error;
        return false;
    }
    return true;
}

}  // namespace rse::sim
