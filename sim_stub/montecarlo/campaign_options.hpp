// rse-montecarlo's command line (docs/montecarlo.md; docs/operations.md,
// "Command lines"):
//
//   rse-montecarlo [--help] COMMAND [OPTIONS] [OPERANDS]
//
// getopt_long (sim_stub/cli/command_line.hpp): --help (-h) before the command;
// then the command (run, block, merge, seed, or help) and its options, which
// operands may follow or precede (merge's FILE|DIR..., seed's N). Every
// command takes every option, as before: those it does not use are ignored.
// The mission options (--scenario, --goto, --duration, --no-faults) are
// collected for prepareCampaign, which checks them as rse-demo does.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

namespace rse::sim::mc {

enum class CampaignCommand : std::uint8_t { kRun, kBlock, kMerge, kSeed };

struct CampaignArgs {
    CampaignCommand command = CampaignCommand::kRun;
    std::uint64_t first = 1, count = 200;  // --seeds FIRST:COUNT
    bool seedsGiven = false;
    std::uint64_t blockSize = 0;  // --block-size B
    long task = -1;               // --task I (-1: $SLURM_ARRAY_TASK_ID)
    int jobs = 0;                 // --jobs N (0: the command's default)
    std::string out, table;       // --out, --table
    bool console = false;         // --console (seed)
    std::uint64_t seed = 0;       // seed N
    std::vector<std::string> mission;  // the mission options, in rse-demo's words (canonical names)
    std::vector<std::string> inputs;   // merge's result files and folders
};

enum class CampaignParse : std::uint8_t { kRun, kHelp, kUsageError };

// argv[0] is the program; argv is not written. On kUsageError *error says
// what is wrong (without the program's name).
CampaignParse parseCampaignArgs(int argc, const char* const* argv, CampaignArgs* args, std::string* error);
void printCampaignUsage(std::FILE* out);

// A whole number (digits only, at most 19 of them), as rse-montecarlo reads
// seeds, counts and Slurm's environment.
bool parseWholeCount(const std::string& text, std::uint64_t* value);

}  // namespace rse::sim::mc
