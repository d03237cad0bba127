// rse-montecarlo: Monte Carlo campaigns of the lockstep mission (`make
// montecarlo`, docs/montecarlo.md).
//
//   rse-montecarlo run   [--seeds FIRST:COUNT] [--jobs N] [--out FILE] [--table FILE] [MISSION]
//   rse-montecarlo block --seeds FIRST:COUNT --block-size B [--task I] [--jobs N] --out FILE|DIR [MISSION]
//   rse-montecarlo merge [--table FILE] [--out FILE] FILE|DIR...
//   rse-montecarlo seed N [--console] [MISSION]
//
//   rse-montecarlo --help
//
// MISSION: rse-demo's --scenario FILE, --goto X,Y[,RISK], --duration S, --no-faults.
// The command line: sim_stub/montecarlo/campaign_options.hpp.
// Exit status: 0 when every check of the table passed (or --help), 3 when one
// failed, 1 for an error (a file, a missing seed, a worker that could not
// start), 2 for a bad command line (one line on stderr says why, a second
// points to --help).
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

#include "sim_stub/cli/command_line.hpp"
#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/montecarlo/campaign_options.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/montecarlo/worker_pool.hpp"

namespace {

using namespace rse::sim::mc;

constexpr int kExitOk = 0;
constexpr int kExitError = 1;
constexpr int kExitUsage = 2;
constexpr int kExitCheckFailed = 3;

int usageError(const std::string& what) { return rse::sim::cli::usageError(stderr, "rse-montecarlo", what); }

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
int report(const ResultSet& set, const CampaignArgs& a) {
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

int commandRun(const CampaignArgs& a) {
    CampaignSpec spec;
    std::string error;
    if (!prepareCampaign(a.mission, &spec, &error)) {
        return usageError(error);
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

int commandBlock(const CampaignArgs& a) {
    CampaignSpec spec;
    std::string error;
    if (!prepareCampaign(a.mission, &spec, &error)) {
        return usageError(error);
    }
    spec.firstSeed = a.first;
    spec.seedCount = a.count;
    long task = a.task;
    const char* envTask = std::getenv("SLURM_ARRAY_TASK_ID");
    std::uint64_t u = 0;
    if (task < 0 && envTask != nullptr && parseWholeCount(envTask, &u)) {
        task = static_cast<long>(u);
    }
    if (task < 0) {
        return usageError("block: no --task and no SLURM_ARRAY_TASK_ID");
    }
    const std::uint64_t offset = static_cast<std::uint64_t>(task) * a.blockSize;
    if (offset >= a.count) {
        return usageError("block: task " + std::to_string(task) + " starts past the campaign's " +
                          std::to_string(a.count) + " seeds");
    }
    const std::uint64_t first = a.first + offset;
    const std::uint64_t count = std::min(a.blockSize, a.count - offset);
    int jobs = a.jobs;
    const char* cpus = std::getenv("SLURM_CPUS_PER_TASK");
    if (jobs < 1) {
        jobs = cpus != nullptr && parseWholeCount(cpus, &u) && u >= 1 && u <= 1024 ? static_cast<int>(u) : 1;
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

int commandMerge(const CampaignArgs& a) {
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
        return usageError("merge: no result files");
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

int commandSeed(const CampaignArgs& a) {
    CampaignSpec spec;
    std::string error;
    const std::uint64_t seed = a.seed;
    if (!prepareCampaign(a.mission, &spec, &error)) {
        return usageError(error);
    }
    spec.firstSeed = seed;
    spec.seedCount = 1;
    const SeedRun r = runSeed(spec, seed, a.console ? stdout : nullptr);
    std::printf("%s\n%s\n", r.row.c_str(), r.timing.c_str());
    return kExitOk;
}

}  // namespace

int main(int argc, char** argv) {
    CampaignArgs a;
    std::string error;
    switch (parseCampaignArgs(argc, argv, &a, &error)) {
        case CampaignParse::kHelp:
            printCampaignUsage(stdout);
            return kExitOk;
        case CampaignParse::kUsageError:
            return usageError(error);
        case CampaignParse::kRun:
            break;
    }
    switch (a.command) {
        case CampaignCommand::kRun: return commandRun(a);
        case CampaignCommand::kBlock: return commandBlock(a);
        case CampaignCommand::kMerge: return commandMerge(a);
        case CampaignCommand::kSeed: return commandSeed(a);
    }
    return kExitUsage;
}
