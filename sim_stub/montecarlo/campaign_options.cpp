#include "sim_stub/montecarlo/campaign_options.hpp"

#include <cstring>

#include "sim_stub/cli/command_line.hpp"

namespace rse::sim::mc {

namespace {

using cli::OptionScanner;

// "FIRST:COUNT", COUNT > 0, the last seed within 64 bits.
bool parseSeeds(const std::string& text, std::uint64_t* first, std::uint64_t* count) {
    const std::size_t colon = text.find(':');
    return colon != std::string::npos && parseWholeCount(text.substr(0, colon), first) &&
           parseWholeCount(text.substr(colon + 1), count) && *count > 0 && *first + *count > *first;
}

const option kGlobalOptions[] = {
    {"help", no_argument, nullptr, 'h'},
    {nullptr, 0, nullptr, 0},
};

enum : int {
    kOptSeeds = 1000,
    kOptJobs,
    kOptBlockSize,
    kOptTask,
    kOptOut,
    kOptTable,
    kOptConsole,
    kOptScenario,
    kOptGoto,
    kOptDuration,
    kOptNoFaults,
};
const option kCommandOptions[] = {
    {"seeds", required_argument, nullptr, kOptSeeds},
    {"jobs", required_argument, nullptr, kOptJobs},
    {"block-size", required_argument, nullptr, kOptBlockSize},
    {"task", required_argument, nullptr, kOptTask},
    {"out", required_argument, nullptr, kOptOut},
    {"table", required_argument, nullptr, kOptTable},
    {"console", no_argument, nullptr, kOptConsole},
    {"scenario", required_argument, nullptr, kOptScenario},
    {"goto", required_argument, nullptr, kOptGoto},
    {"duration", required_argument, nullptr, kOptDuration},
    {"no-faults", no_argument, nullptr, kOptNoFaults},
    {"help", no_argument, nullptr, 'h'},
    {nullptr, 0, nullptr, 0},
};

bool parseCommand(const std::string& name, CampaignCommand* command) {
    const struct {
        const char* name;
        CampaignCommand command;
    } kCommands[] = {{"run", CampaignCommand::kRun},
                     {"block", CampaignCommand::kBlock},
                     {"merge", CampaignCommand::kMerge},
                     {"seed", CampaignCommand::kSeed}};
    for (const auto& c : kCommands) {
        if (name == c.name) {
            *command = c.command;
            return true;
        }
    }
    return false;
}

// A value that must be a whole number in [lo, hi], for `option`; `what` says
// what is expected in the message.
bool wholeIn(const char* option, const std::string& value, std::uint64_t lo, std::uint64_t hi, const char* what,
             std::uint64_t* out, std::string* error) {
    if (parseWholeCount(value, out) && *out >= lo && *out <= hi) {
        return true;
    }
    *error = std::string(option) + " '" + value + "': " + what;
    return false;
}

// One of the command's options and its value into *a; false with *error.
bool applyOption(int id, const std::string& value, CampaignArgs* a, std::string* error) {
    std::uint64_t u = 0;
    switch (id) {
        case kOptSeeds:
            a->seedsGiven = true;
            if (!parseSeeds(value, &a->first, &a->count)) {
                *error = "--seeds '" + value + "': expected FIRST:COUNT, COUNT > 0";
                return false;
            }
            return true;
        case kOptJobs:
            if (!wholeIn("--jobs", value, 1, 1024, "1..1024", &u, error)) {
                return false;
            }
            a->jobs = static_cast<int>(u);
            return true;
        case kOptBlockSize:
            return wholeIn("--block-size", value, 1, UINT64_MAX, "a count > 0", &a->blockSize, error);
        case kOptTask:
            if (!wholeIn("--task", value, 0, 100000000, "an array index", &u, error)) {
                return false;
            }
            a->task = static_cast<long>(u);
            return true;
        case kOptOut: a->out = value; return true;
        case kOptTable: a->table = value; return true;
        case kOptConsole: a->console = true; return true;
        case kOptScenario: a->mission.insert(a->mission.end(), {"--scenario", value}); return true;
        case kOptGoto: a->mission.insert(a->mission.end(), {"--goto", value}); return true;
        case kOptDuration: a->mission.insert(a->mission.end(), {"--duration", value}); return true;
        case kOptNoFaults: a->mission.emplace_back("--no-faults"); return true;
        default: break;
    }
    *error = "option " + std::to_string(id) + " is not rse-montecarlo's";  // a table entry without a case
    return false;
}

// What the command needs beyond its options' own checks.
bool commandComplete(const std::string& name, CampaignArgs* a, std::string* error) {
    switch (a->command) {
        case CampaignCommand::kRun:
        case CampaignCommand::kBlock:
            if (!a->inputs.empty()) {
                *error = name + ": unexpected argument '" + a->inputs[0] + "'";
                return false;
            }
            if (a->command == CampaignCommand::kBlock && (!a->seedsGiven || a->blockSize == 0 || a->out.empty())) {
                *error = "block: --seeds, --block-size and --out are needed";
                return false;
            }
            return true;
        case CampaignCommand::kMerge:
            return true;  // its files are checked when read
        case CampaignCommand::kSeed:
            if (a->inputs.size() != 1 || !parseWholeCount(a->inputs[0], &a->seed)) {
                *error = "seed: one seed number";
                return false;
            }
            return true;
    }
    return true;
}

}  // namespace

bool parseWholeCount(const std::string& text, std::uint64_t* value) {
    return text.size() <= 19 && cli::parseWholeNumber(text, UINT64_MAX, value);
}

CampaignParse parseCampaignArgs(int argc, const char* const* argv, CampaignArgs* a, std::string* error) {
    OptionScanner global(argc, argv, "h", kGlobalOptions);
    for (int id = global.next(); id != OptionScanner::kEnd; id = global.next()) {
        if (id == OptionScanner::kBad) {
            *error = global.error();
            return CampaignParse::kUsageError;
        }
        return CampaignParse::kHelp;  // 'h', the only global option
    }
    const int at = global.index();
    if (at >= argc) {
        *error = "no command (run, block, merge or seed)";
        return CampaignParse::kUsageError;
    }
    const std::string name = argv[at];
    if (name == "help") {
        return CampaignParse::kHelp;
    }
    if (!parseCommand(name, &a->command)) {
        *error = "unknown command '" + name + "' (run, block, merge or seed)";
        return CampaignParse::kUsageError;
    }
    OptionScanner scanner(argc, argv, "h", kCommandOptions, at + 1);
    for (int id = scanner.next();; id = scanner.next()) {
        if (id == OptionScanner::kEnd) {
            const char* operand = scanner.takeOperand();
            if (operand == nullptr) {
                break;
            }
            a->inputs.emplace_back(operand);
        } else if (id == OptionScanner::kBad) {
            *error = scanner.error();
            return CampaignParse::kUsageError;
        } else if (id == 'h') {
            return CampaignParse::kHelp;
        } else if (!applyOption(id, scanner.value() != nullptr ? scanner.value() : "", a, error)) {
            return CampaignParse::kUsageError;
        }
    }
    return commandComplete(name, a, error) ? CampaignParse::kRun : CampaignParse::kUsageError;
}

void printCampaignUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage:\n"
                 "  rse-montecarlo run   [--seeds FIRST:COUNT] [--jobs N] [--out FILE] [--table FILE] [MISSION]\n"
                 "      COUNT seeds (default 1:200) on N worker processes (default: every core), the result file\n"
                 "      (default build/montecarlo/results.txt), then the table, the host timing and the wall time\n"
                 "  rse-montecarlo block --seeds FIRST:COUNT --block-size B [--task I] [--jobs N] --out FILE|DIR [MISSION]\n"
                 "      block I (default $SLURM_ARRAY_TASK_ID) of the campaign: seeds FIRST+I*B .. on N workers\n"
                 "      (default $SLURM_CPUS_PER_TASK, else 1); a DIR gets block-IIIIII.txt\n"
                 "  rse-montecarlo merge [--table FILE] [--out FILE] FILE|DIR...\n"
                 "      the result files (a DIR: its *.txt) of one campaign merged: the table; every seed must be there\n"
                 "  rse-montecarlo seed N [--console] [MISSION]\n"
                 "      one seed: its R and T lines (--console: the mission's console and summary too)\n"
                 "  rse-montecarlo --help (or -h, or help; also after a command)\n"
                 "      this text (on stdout, exit status 0)\n"
                 "MISSION: rse-demo's --scenario FILE, --goto X,Y[,RISK], --duration S, --no-faults\n"
                 "Exit status: 0 every check passed, 3 a check failed, 1 error, 2 bad usage (one line on stderr\n"
                 "says why). docs/montecarlo.md.\n");
}

}  // namespace rse::sim::mc
