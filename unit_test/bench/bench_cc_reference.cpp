// Chance-constrained planning reference benchmark (make bench): the exact MILP
// (cc_reference_milp.hpp, COIN-OR CBC) on the generated instance sets
// (cc_instances.hpp) with the even risk split, each plan checked by Monte
// Carlo on the true plant (cc_monte_carlo.hpp, 1e5 trajectories, whole
// segments against the polygons). To be merged into the planner benchmark.
//
//   provable  N = 10, M = 4, one obstacle across the straight path,
//             Delta = 0.05 and 1e-3, time limit --limit per solve
//   eight     N = 10, M = 8, one across, --eight instances per Delta,
//             time limit --eight-limit
//   large     N = 20, M = 8, four across, --large instances at Delta = 0.05,
//             time limit --large-limit (gap at the limit reported)
//   corner    the diagonal box: waypoint-only against segment constraints
//
// Per solve: proven optimal?, 16-gon cost, CBC's best bound and gap, wall time
// (model build + CBC + polish), nodes, and the Monte Carlo collision rate
// (max(--samples, 500 / Delta) trajectories, default 1e5 at Delta = 0.05,
// 5e5 at 1e-3) with its one-sided 95 % Clopper-Pearson upper bound and the conservatism
// Delta / rate (Delta / upper bound is what the sample can guarantee).
// Solves run in --jobs worker processes (default 2: one per core of the
// 2-core target machine; each CBC run is single-threaded), so the wall times
// are those of one core each.
//
// Usage: bench_cc_reference [--count N] [--limit S] [--eight N] [--eight-limit S]
//                           [--large N] [--large-limit S] [--samples N] [--jobs N]
// Defaults: 50 provable at 8 s, 6 eight at 10 s, 4 large at 20 s, 2 jobs: about
// 4-5 minutes on the 2-core machine.
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_instances.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"
#include "unit_test/bench/cc_reference_milp.hpp"

using namespace rse::test::cc;
using rse::deliberative::CcStatus;

namespace {

struct Job {
    std::string set;
    std::size_t index = 0;
    CcProblem problem;
    double limit = 0.0;
};

struct Outcome {
    int status = 0;
    double cost = 0, bound = 0, gap = 0, seconds = 0;
    int nodes = 0, binaries = 0;
    double slack = 0;
    std::size_t collisions = 0, waypointCollisions = 0, samples = 0;
    double rate = 0, upper = 0, mcSeconds = 0;
};

Outcome run(const Job& job, std::size_t samples) {
    MilpOptions options;
    options.timeLimitS = job.limit;
    const MilpResult r = solveReferenceMilp(job.problem, options);
    Outcome o;
    o.status = static_cast<int>(r.plan.status);
    o.cost = r.cost;
    o.bound = r.bestBound;
    o.gap = r.gap;
    o.seconds = r.seconds;
    o.nodes = r.nodes;
    o.binaries = r.binaries;
    o.slack = r.constraintSlack;
    if (r.plan.status == CcStatus::kOptimal || r.plan.status == CcStatus::kFeasible) {
        McOptions mc;
        // At least 500 / Delta trajectories, so that a plan 100x inside Delta
        // still shows about 5 hits (1e5 at 0.05, 5e5 at 1e-3).
        mc.samples = std::max(samples, static_cast<std::size_t>(500.0 / job.problem.riskBound));
        mc.seed = 1000 + job.index;
        const McResult m = monteCarloCollision(job.problem, r.plan, mc);
        o.collisions = m.collisions;
        o.waypointCollisions = m.waypointCollisions;
        o.samples = m.samples;
        o.rate = m.rate;
        o.upper = m.upperClopperPearson;
        o.mcSeconds = m.seconds;
    }
    return o;
}

// Runs the jobs in `workers` forked processes; results come back over pipes
// as raw Outcome structs (same binary, same machine).
std::vector<Outcome> runAll(const std::vector<Job>& jobs, std::size_t samples, int workers) {
    std::vector<Outcome> out(jobs.size());
    if (workers <= 1) {
        for (std::size_t k = 0; k < jobs.size(); ++k) {
            out[k] = run(jobs[k], samples);
        }
        return out;
    }
    std::fflush(stdout);  // or the children (CBC flushes stdout) print it again
    std::fflush(stderr);
    std::vector<int> fds;
    std::vector<pid_t> pids;
    for (int w = 0; w < workers; ++w) {
        int fd[2];
        if (pipe(fd) != 0) {
            std::perror("pipe");
            std::exit(1);
        }
        const pid_t pid = fork();
        if (pid == 0) {
            close(fd[0]);
            for (std::size_t k = static_cast<std::size_t>(w); k < jobs.size(); k += static_cast<std::size_t>(workers)) {
                const Outcome o = run(jobs[k], samples);
                if (write(fd[1], &k, sizeof k) != static_cast<ssize_t>(sizeof k) ||
                    write(fd[1], &o, sizeof o) != static_cast<ssize_t>(sizeof o)) {
                    _exit(1);
                }
            }
            close(fd[1]);
            _exit(0);
        }
        close(fd[1]);
        fds.push_back(fd[0]);
        pids.push_back(pid);
    }
    for (int fd : fds) {
        std::size_t k = 0;
        Outcome o;
        while (read(fd, &k, sizeof k) == static_cast<ssize_t>(sizeof k)) {
            if (read(fd, &o, sizeof o) != static_cast<ssize_t>(sizeof o) || k >= out.size()) {
                break;
            }
            out[k] = o;
        }
        close(fd);
    }
    for (pid_t pid : pids) {
        int status = 0;
        waitpid(pid, &status, 0);
    }
    return out;
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) {
        return NAN;
    }
    std::sort(v.begin(), v.end());
    const double pos = q * static_cast<double>(v.size() - 1);
    const std::size_t lo = static_cast<std::size_t>(pos);
    const std::size_t hi = std::min(lo + 1, v.size() - 1);
    return v[lo] + (pos - static_cast<double>(lo)) * (v[hi] - v[lo]);
}

const char* statusName(int s) {
    switch (s) {
        case 0:
            return "optimal";
        case 1:
            return "feasible";
        case 2:
            return "no-plan";
        default:
            return "bad";
    }
}

void printRows(const std::vector<Job>& jobs, const std::vector<Outcome>& res) {
    std::printf("%-9s %3s %7s %-8s %9s %9s %8s %7s %7s %8s %9s %9s %8s %8s\n", "set", "k", "Delta", "status",
                "cost_m", "bound_m", "gap", "time_s", "nodes", "mc_hits", "mc_rate", "mc_cp95", "D/rate", "D/cp95");
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        const Outcome& o = res[k];
        const double delta = jobs[k].problem.riskBound;
        std::printf("%-9s %3zu %7.0e %-8s %9.4f %9.4f %8.1e %7.2f %7d %8zu %9.2e %9.2e %8.0f %8.0f\n",
                    jobs[k].set.c_str(), jobs[k].index, delta, statusName(o.status), o.cost, o.bound, o.gap,
                    o.seconds, o.nodes, o.collisions, o.rate, o.upper, o.rate > 0 ? delta / o.rate : INFINITY,
                    o.upper > 0 ? delta / o.upper : INFINITY);
    }
}

void summarise(const char* name, double delta, const std::vector<Job>& jobs, const std::vector<Outcome>& res) {
    std::vector<double> times, provenTimes, rates, ratios, gaps;
    std::size_t proven = 0, feasible = 0, none = 0, zero = 0, within = 0, n = 0;
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        if (jobs[k].set != name || jobs[k].problem.riskBound != delta) {
            continue;
        }
        const Outcome& o = res[k];
        ++n;
        times.push_back(o.seconds);
        if (o.status == 0) {
            ++proven;
            provenTimes.push_back(o.seconds);
        } else if (o.status == 1) {
            ++feasible;
            gaps.push_back(o.gap);
        } else {
            ++none;
        }
        if (o.status <= 1) {
            rates.push_back(o.rate);
            if (o.rate > 0) {
                ratios.push_back(delta / o.rate);
            } else {
                ++zero;
            }
            if (o.upper < delta) {
                ++within;
            }
        }
    }
    if (n == 0) {
        return;
    }
    std::printf("%-9s Delta %.0e: %zu instances, proven optimal %zu, feasible at the limit %zu, no plan %zu\n",
                name, delta, n, proven, feasible, none);
    std::printf("          time (s): median %.2f  p90 %.2f  max %.2f   | proven only: median %.2f  max %.2f\n",
                quantile(times, 0.5), quantile(times, 0.9), quantile(times, 1.0), quantile(provenTimes, 0.5),
                quantile(provenTimes, 1.0));
    if (!gaps.empty()) {
        std::printf("          gap at the limit: median %.2e  max %.2e\n", quantile(gaps, 0.5), quantile(gaps, 1.0));
    }
    std::printf("          MC collision rate: median %.2e  quartiles %.2e .. %.2e  min %.2e  max %.2e;"
                " 95%% upper bound below Delta in %zu/%zu\n",
                quantile(rates, 0.5), quantile(rates, 0.25), quantile(rates, 0.75), quantile(rates, 0.0),
                quantile(rates, 1.0), within, rates.size());
    std::printf("          conservatism Delta/rate: median %.0f  quartiles %.0f .. %.0f  min %.0f  max %.0f"
                "  (%zu plans with no hit, left out)\n",
                quantile(ratios, 0.5), quantile(ratios, 0.25), quantile(ratios, 0.75), quantile(ratios, 0.0),
                quantile(ratios, 1.0), zero);
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t count = 50, eight = 6, large = 4, samples = 100000;
    double limit = 8.0, eightLimit = 10.0, largeLimit = 20.0;
    int jobsN = 2;
    for (int a = 1; a + 1 < argc; a += 2) {
        const std::string key = argv[a];
        const double v = std::atof(argv[a + 1]);
        if (key == "--count") count = static_cast<std::size_t>(v);
        else if (key == "--limit") limit = v;
        else if (key == "--eight") eight = static_cast<std::size_t>(v);
        else if (key == "--large") large = static_cast<std::size_t>(v);
        else if (key == "--eight-limit") eightLimit = v;
        else if (key == "--large-limit") largeLimit = v;
        else if (key == "--samples") samples = static_cast<std::size_t>(v);
        else if (key == "--jobs") jobsN = static_cast<int>(v);
        else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    const auto begin = std::chrono::steady_clock::now();

    // The corner-cutting fact first (seconds).
    {
        const CcProblem p = diagonalBoxInstance(0.05);
        MilpOptions w;
        w.mode = ConstraintMode::kWaypointOnly;
        const MilpResult rw = solveReferenceMilp(p, w);
        const MilpResult rs = solveReferenceMilp(p, MilpOptions{});
        McOptions mc;
        mc.samples = samples;
        const McResult mw = monteCarloCollision(p, rw.plan, mc);
        const McResult ms = monteCarloCollision(p, rs.plan, mc);
        std::printf("corner (diagonal box, N = 4, Delta = 0.05):\n");
        std::printf("  waypoint-only: %s cost %.4f m, mean path meets the box: %s, MC segment hits %.4f, waypoint hits %.4f\n",
                    statusName(static_cast<int>(rw.plan.status)), rw.cost,
                    meanPathHitsObstacle(p, rw.plan.meanX, rw.plan.meanY) ? "yes" : "no", mw.rate,
                    static_cast<double>(mw.waypointCollisions) / static_cast<double>(mw.samples));
        std::printf("  segment:       %s cost %.4f m, mean path meets the box: %s, MC segment hits %.2e (cp95 %.2e)\n\n",
                    statusName(static_cast<int>(rs.plan.status)), rs.cost,
                    meanPathHitsObstacle(p, rs.plan.meanX, rs.plan.meanY) ? "yes" : "no", ms.rate,
                    ms.upperClopperPearson);
    }

    std::vector<Job> jobs;
    for (double delta : {0.05, 1e-3}) {
        const std::vector<CcProblem> set = provableSet(delta, count);
        for (std::size_t k = 0; k < set.size(); ++k) {
            jobs.push_back({"provable", k, set[k], limit});
        }
    }
    for (double delta : {0.05, 1e-3}) {
        const std::vector<CcProblem> set = provableSet(delta, eight, 8);
        for (std::size_t k = 0; k < set.size(); ++k) {
            jobs.push_back({"eight", k, set[k], eightLimit});
        }
    }
    const std::vector<CcProblem> big = largeSet(0.05, large);
    for (std::size_t k = 0; k < big.size(); ++k) {
        jobs.push_back({"large", k, big[k], largeLimit});
    }
    // Longest first, so the workers finish together.
    std::vector<std::size_t> order(jobs.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        order[k] = k;
    }
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return jobs[a].limit > jobs[b].limit; });
    std::vector<Job> sorted;
    for (std::size_t k : order) {
        sorted.push_back(jobs[k]);
    }
    const std::vector<Outcome> sortedRes = runAll(sorted, samples, jobsN);
    std::vector<Outcome> res(jobs.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        res[order[k]] = sortedRes[k];
    }

    std::printf("per solve (even split; time = build + CBC + polish, %d worker process(es); "
                "MC max(%zu, 500 / Delta) trajectories):\n",
                jobsN, samples);
    printRows(jobs, res);
    std::printf("\nsummary (limits: provable %.0f s, eight %.0f s, large %.0f s):\n", limit, eightLimit, largeLimit);
    for (const char* name : {"provable", "eight"}) {
        for (double delta : {0.05, 1e-3}) {
            summarise(name, delta, jobs, res);
        }
    }
    summarise("large", 0.05, jobs, res);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::printf("\ntotal wall time %.0f s\n", total);
    return 0;
}
