// rse-montecarlo: Monte Carlo campaigns of the lockstep mission (`make
// montecarlo`, docs/montecarlo.md).
//
//   rse-montecarlo run   [--seeds FIRST:COUNT] [--jobs N] [--out FILE] [--table FILE] [MISSION]
//   rse-montecarlo block --seeds FIRST:COUNT --block-size B [--task I] [--jobs N] --out FILE|DIR [MISSION]
//   rse-montecarlo merge [--table FILE] [--out FILE] FILE|DIR...
//   rse-montecarlo seed N [--console] [MISSION]
//
// MISSION: rse-demo's --scenario FILE, --goto X,Y[,RISK], --duration S, --no-faults.
// Exit status: 0 when every check of the table passed, 3 when one failed, 1
// for an error (a file, a missing seed, a worker that could not start), 2 for
// a bad command line.
#include <dirent.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/montecarlo/worker_pool.hpp"

namespace {

using namespace rse::sim::mc;

constexpr int kExitOk = 0;
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitCheckFailed = 3;

void usage(std::FILE* out) {
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
                 "MISSION: rse-demo's --scenario FILE, --goto X,Y[,RISK], --duration S, --no-faults\n"
                 "Exit status: 0 every check passed, 3 a check failed, 1 error, 2 bad usage. docs/montecarlo.md.\n");
}

bool parseU64(const std::string& text, std::uint64_t* v) {
    if (text.empty() || text.find_first_not_of("0123456789") != std::string::npos || text.size() > 19) {
        return false;
    }
    *v = std::strtoull(text.c_str(), nullptr, 10);
    return true;
}

bool parseSeeds(const std::string& text, std::uint64_t* first, std::uint64_t* count) {
    const std::size_t colon = text.find(':');
    return colon != std::string::npos && parseU64(text.substr(0, colon), first) &&
           parseU64(text.substr(colon + 1), count) && *count > 0 && *first + *count > *first;
}

int coreCount() {
    const long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : static_cast<int>(n);
}

bool isDirectory(const std::string& path) {
    struct stat st {};
    return stat(path.c_str(), &st) == 0 && S_ISDIR(st.st_mode);
}

bool makeParent(const std::string& path) {
    const std::size_t slash = path.rfind('/');
    if (slash == std::string::npos || slash == 0) {
        return true;
    }
    const std::string dir = path.substr(0, slash);
    if (isDirectory(dir)) {
        return true;
    }
    if (!makeParent(dir)) {
        return false;
    }
    return mkdir(dir.c_str(), 0755) == 0 || isDirectory(dir);
}

bool writeText(const std::string& path, const std::string& text) {
    if (!makeParent(path)) {
        return false;
    }
    std::FILE* f = std::fopen(path.c_str(), "w");
    if (f == nullptr) {
        return false;
    }
    const bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
    return std::fclose(f) == 0 && ok;
}

// The options every command shares; the rest go to the mission.
struct Args {
    std::string command;
    std::uint64_t first = 1, count = 200, blockSize = 0, seed = 0;
    bool seedsGiven = false, console = false;
    long task = -1;
    int jobs = 0;
    std::string out, table;
    std::vector<std::string> mission, inputs;
};

bool parseArgs(int argc, char** argv, Args* a, std::string* error) {
    if (argc < 2) {
        *error = "no command";
        return false;
    }
    a->command = argv[1];
    for (int i = 2; i < argc; ++i) {
        const std::string s = argv[i];
        const bool value = i + 1 < argc;
        std::uint64_t u = 0;
        if (s == "--seeds" && value) {
            if (!parseSeeds(argv[++i], &a->first, &a->count)) {
                *error = std::string("--seeds '") + argv[i] + "': expected FIRST:COUNT, COUNT > 0";
                return false;
            }
            a->seedsGiven = true;
        } else if (s == "--jobs" && value) {
            if (!parseU64(argv[++i], &u) || u < 1 || u > 1024) {
                *error = std::string("--jobs '") + argv[i] + "': 1..1024";
                return false;
            }
            a->jobs = static_cast<int>(u);
        } else if (s == "--block-size" && value) {
            if (!parseU64(argv[++i], &a->blockSize) || a->blockSize < 1) {
                *error = std::string("--block-size '") + argv[i] + "': a count > 0";
                return false;
            }
        } else if (s == "--task" && value) {
            if (!parseU64(argv[++i], &u) || u > 100000000) {
                *error = std::string("--task '") + argv[i] + "': an array index";
                return false;
            }
            a->task = static_cast<long>(u);
        } else if (s == "--out" && value) {
            a->out = argv[++i];
        } else if (s == "--table" && value) {
            a->table = argv[++i];
        } else if (s == "--console") {
            a->console = true;
        } else if ((s == "--scenario" || s == "--goto" || s == "--duration") && value) {
            a->mission.push_back(s);
            a->mission.push_back(argv[++i]);
        } else if (s == "--no-faults") {
            a->mission.push_back(s);
        } else if (s == "--help" || s == "-h") {
            a->command = "help";
        } else if (!s.empty() && s[0] != '-') {
            a->inputs.push_back(s);
        } else {
            *error = "unknown or incomplete option '" + s + "'";
            return false;
        }
    }
    return true;
}

// Runs the seeds on the workers; the rows and timings in seed order.
bool runSeeds(const CampaignSpec& spec, const std::vector<std::uint64_t>& seeds, int jobs,
              std::vector<std::pair<std::string, std::string>>* lines, std::string* error) {
    std::vector<std::pair<std::uint64_t, SeedRun>> runs;
    std::size_t shown = 0;
    const bool progress = isatty(STDERR_FILENO) != 0;
    const bool ok = runOnWorkers(
        seeds, jobs, [&spec](std::uint64_t seed) { return runSeed(spec, seed); },
        [&](std::uint64_t seed, const SeedRun& r) {
            runs.emplace_back(seed, r);
            if (progress && (runs.size() * 20 / seeds.size() != shown || runs.size() == seeds.size())) {
                shown = runs.size() * 20 / seeds.size();
                std::fprintf(stderr, "\rrse-montecarlo: %zu/%zu seeds", runs.size(), seeds.size());
                std::fprintf(stderr, runs.size() == seeds.size() ? "\n" : "");
            }
        },
        error);
    std::sort(runs.begin(), runs.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const auto& [seed, r] : runs) {
        lines->emplace_back(r.row, r.timing);
    }
    return ok;
}

// The table and the host timing of a set; --table FILE gets the table alone.
int report(const ResultSet& set, const Args& a) {
    const std::string table = formatTable(set);
    std::fputs(table.c_str(), stdout);
    std::fputs("\n", stdout);
    std::fputs(formatHostTiming(set).c_str(), stdout);
    if (!a.table.empty() && !writeText(a.table, table)) {
        std::fprintf(stderr, "rse-montecarlo: %s: cannot be written\n", a.table.c_str());
        return kExitError;
    }
    return failedChecks(set) == 0 ? kExitOk : kExitCheckFailed;
}

int commandRun(const Args& a) {
    CampaignSpec spec;
    std::string error;
    if (!prepareCampaign(a.mission, &spec, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitUsage;
    }
    spec.firstSeed = a.first;
    spec.seedCount = a.count;
    const int jobs = a.jobs > 0 ? a.jobs : coreCount();
    std::vector<std::uint64_t> seeds;
    for (std::uint64_t s = a.first; s - a.first < a.count; ++s) {
        seeds.push_back(s);
    }
    const std::string out = a.out.empty() ? "build/montecarlo/results.txt" : a.out;
    if (!makeParent(out)) {
        std::fprintf(stderr, "rse-montecarlo: %s: cannot make its folder\n", out.c_str());
        return kExitError;
    }
    const auto wall0 = std::chrono::steady_clock::now();
    std::vector<std::pair<std::string, std::string>> lines;
    if (!runSeeds(spec, seeds, jobs, &lines, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitError;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();
    if (!writeResultFile(out, campaignLine(spec), blockLine(a.first, a.count, -1, jobs), lines, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitError;
    }
    ResultSet set;
    if (!addResultFile(out, &set, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitError;
    }
    const int status = report(set, a);
    std::printf("wall time: %zu seeds on %d worker processes (%d cores online) in %.1f s: %.3f s a seed, "
                "%.1f seeds/s; results in %s\n",
                seeds.size(), jobs, coreCount(), wall, wall / static_cast<double>(seeds.size()),
                static_cast<double>(seeds.size()) / wall, out.c_str());
    return status;
}

int commandBlock(const Args& a) {
    CampaignSpec spec;
    std::string error;
    if (!a.seedsGiven || a.blockSize == 0 || a.out.empty()) {
        std::fprintf(stderr, "rse-montecarlo block: --seeds, --block-size and --out are needed\n");
        return kExitUsage;
    }
    if (!prepareCampaign(a.mission, &spec, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitUsage;
    }
    spec.firstSeed = a.first;
    spec.seedCount = a.count;
    long task = a.task;
    const char* envTask = std::getenv("SLURM_ARRAY_TASK_ID");
    std::uint64_t u = 0;
    if (task < 0 && envTask != nullptr && parseU64(envTask, &u)) {
        task = static_cast<long>(u);
    }
    if (task < 0) {
        std::fprintf(stderr, "rse-montecarlo block: no --task and no SLURM_ARRAY_TASK_ID\n");
        return kExitUsage;
    }
    const std::uint64_t offset = static_cast<std::uint64_t>(task) * a.blockSize;
    if (offset >= a.count) {
        std::fprintf(stderr, "rse-montecarlo block: task %ld starts past the campaign's %llu seeds\n", task,
                     static_cast<unsigned long long>(a.count));
        return kExitUsage;
    }
    const std::uint64_t first = a.first + offset;
    const std::uint64_t count = std::min(a.blockSize, a.count - offset);
    int jobs = a.jobs;
    const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
    if (jobs < 1) {
        jobs = cpus != nullptr && parseU64(cpus, &u) && u >= 1 && u <= 1024 ? static_cast<int>(u) : 1;
    }
    std::string out = a.out;
    if (isDirectory(out)) {
        char name[64];
        std::snprintf(name, sizeof name, "/block-%06ld.txt", task);
        out += name;
    }
    std::vector<std::uint64_t> seeds;
    for (std::uint64_t s = first; s - first < count; ++s) {
        seeds.push_back(s);
    }
    std::vector<std::pair<std::string, std::string>> lines;
    if (!runSeeds(spec, seeds, jobs, &lines, &error) ||
        !writeResultFile(out, campaignLine(spec), blockLine(first, count, task, jobs), lines, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitError;
    }
    std::printf("rse-montecarlo block %ld: seeds %llu..%llu on %d workers: %s\n", task,
                static_cast<unsigned long long>(first), static_cast<unsigned long long>(first + count - 1), jobs,
                out.c_str());
    return kExitOk;
}

int commandMerge(const Args& a) {
    std::vector<std::string> files;
    for (const std::string& in : a.inputs) {
        if (!isDirectory(in)) {
            files.push_back(in);
            continue;
        }
        DIR* d = opendir(in.c_str());
        std::vector<std::string> names;
        for (dirent* e = d == nullptr ? nullptr : readdir(d); e != nullptr; e = readdir(d)) {
            const std::string name = e->d_name;
            if (name.size() > 4 && name.compare(name.size() - 4, 4, ".txt") == 0) {
                names.push_back(in + "/" + name);
            }
        }
        if (d != nullptr) {
            closedir(d);
        }
        std::sort(names.begin(), names.end());
        files.insert(files.end(), names.begin(), names.end());
    }
    if (files.empty()) {
        std::fprintf(stderr, "rse-montecarlo merge: no result files\n");
        return kExitUsage;
    }
    ResultSet set;
    std::string error;
    for (const std::string& f : files) {
        if (!addResultFile(f, &set, &error)) {
            std::fprintf(stderr, "rse-montecarlo merge: %s\n", error.c_str());
            return kExitError;
        }
    }
    const std::vector<std::uint64_t> missing = missingSeeds(set);
    const std::vector<std::uint64_t> strangers = strangerSeeds(set);
    if (!missing.empty() || !strangers.empty()) {
        std::fprintf(stderr, "rse-montecarlo merge: %zu files: %zu seeds of the campaign missing, %zu outside it:",
                     files.size(), missing.size(), strangers.size());
        for (std::size_t i = 0; i < missing.size() && i < 20; ++i) {
            std::fprintf(stderr, " %llu", static_cast<unsigned long long>(missing[i]));
        }
        std::fprintf(stderr, "%s\n", missing.size() > 20 ? " ..." : "");
        return kExitError;
    }
    if (!a.out.empty()) {
        std::vector<std::pair<std::string, std::string>> lines;
        for (const auto& [seed, text] : set.rowText) {
            const auto t = set.timings.find(seed);
            lines.emplace_back(text, t == set.timings.end() ? "" : formatTiming(t->second));
        }
        if (!makeParent(a.out) ||
            !writeResultFile(a.out, set.campaign, blockLine(set.firstSeed, set.seedCount, -1, 0), lines, &error)) {
            std::fprintf(stderr, "rse-montecarlo merge: %s\n", error.empty() ? a.out.c_str() : error.c_str());
            return kExitError;
        }
    }
    const int status = report(set, a);
    std::printf("merged: %zu result files, %zu seeds\n", set.files, set.rows.size());
    return status;
}

int commandSeed(const Args& a) {
    CampaignSpec spec;
    std::string error;
    std::uint64_t seed = 0;
    if (a.inputs.size() != 1 || !parseU64(a.inputs[0], &seed)) {
        std::fprintf(stderr, "rse-montecarlo seed: one seed number\n");
        return kExitUsage;
    }
    if (!prepareCampaign(a.mission, &spec, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        return kExitUsage;
    }
    spec.firstSeed = seed;
    spec.seedCount = 1;
    const SeedRun r = runSeed(spec, seed, a.console ? stdout : nullptr);
    std::printf("%s\n%s\n", r.row.c_str(), r.timing.c_str());
    return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    Args a;
    std::string error;
    if (!parseArgs(argc, argv, &a, &error)) {
        std::fprintf(stderr, "rse-montecarlo: %s\n", error.c_str());
        usage(stderr);
        return kExitUsage;
    }
    if (a.command == "help") {
        usage(stdout);
        return kExitOk;
    }
    if ((a.command == "run" || a.command == "block") && !a.inputs.empty()) {
        std::fprintf(stderr, "rse-montecarlo %s: unexpected '%s'\n", a.command.c_str(), a.inputs[0].c_str());
        usage(stderr);
        return kExitUsage;
    }
    if (a.command == "run") {
        return commandRun(a);
    }
    if (a.command == "block") {
        return commandBlock(a);
    }
    if (a.command == "merge") {
        return commandMerge(a);
    }
    if (a.command == "seed") {
        return commandSeed(a);
    }
    std::fprintf(stderr, "rse-montecarlo: unknown command '%s'\n", a.command.c_str());
    usage(stderr);
    return kExitUsage;
}
