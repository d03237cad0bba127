// The issue-7 benchmark (make bench): the flight chance-constrained planner
// (fsw/deliberative/cc_planner.hpp, default CcPlannerParams: the flight work
// budget) against the exact MILP reference (cc_reference_milp.hpp, COIN-OR
// CBC) on the generated instance sets (cc_instances.hpp), every flight plan
// checked by Monte Carlo on the true plant (cc_monte_carlo.hpp, whole
// segments against the polygons).
//
//   provable  N = 10, M = 4, one obstacle across the straight path,
//             --count instances at Delta = 0.05 and the same at 1e-3,
//             CBC time limit --limit
//   eight     N = 10, M = 8, one across, --eight instances per Delta,
//             CBC time limit --eight-limit
//   large     N = 20, M = 8, four across, --large instances at Delta = 0.05,
//             CBC time limit --large-limit (CBC seldom proves these: the
//             flight cost is reported against CBC's best bound)
//   corner    the diagonal box (N = 4): waypoint-only against segment
//             constraints (CBC), and the flight planner on it
//
// Order of work. First every flight solve, in this process, one after the
// other and nothing else running in the benchmark: each instance with
// RiskAllocation::kEvenSplit and with kOptimised, --reps times each (default
// 3); the time of a solve is the MEDIAN of its repetitions (wall clock around
// CcPlanner::solve; the slowest single repetition is reported beside it).
// The planner reads no clock, so the repetitions must agree on cost and
// work (checked). Then CBC (even split, unaided: no cutoff, no start plan)
// and the Monte Carlo runs of both flight plans in --jobs worker processes
// (default 2, one per core; each CBC run is single-threaded).
//
// Per instance: the flight status, 16-gon cost, time, search nodes and work()
// for both allocations; CBC's status, cost, best bound, CPU and wall time
// (model build + CBC + polish; its limit is on wall time); the gap of the flight even-split cost to CBC's proven
// optimum, or, where CBC did not prove within its limit, to CBC's best bound
// (an upper bound on the gap, counted apart); the time ratio CBC / flight
// (even split), with CBC's CPU time so that other work on the machine during
// the CBC phase does not inflate it (where CBC did not prove, its time up to
// the limit: a lower bound on the ratio to proof; the ratio with CBC's wall
// time is printed too); the Monte Carlo collision rate of each flight plan
// (monteCarloSamples: max(--samples, 500 / Delta) trajectories, the same
// random numbers for both plans of an instance), its one-sided 95 %
// Clopper-Pearson upper bound and the conservatism Delta / rate (with no
// collision: Delta / upper bound, a lower bound, marked '>'); the cost saved
// by optimising, (even - optimised) / even.
// Then a summary per set and the targets, each PASS or FAIL (the
// program exits 0 either way: it reports). Targets over every instance:
// median and max gap to the proven optima <= 1 % and 5 %; median time ratio
// >= 100; worst flight time <= 50 ms; Monte Carlo rate <= Delta for every
// plan of both allocations; optimised cost <= even-split cost everywhere.
//
// Usage: bench_cc_reference [--count N] [--limit S] [--eight N] [--eight-limit S]
//                           [--large N] [--large-limit S] [--samples N] [--jobs N]
//                           [--reps N]
// Defaults: 50 provable per Delta at 8 s, 6 eight per Delta at 10 s, 4 large
// at 20 s, 1e5 samples, 2 jobs, 3 repetitions: about 6 minutes on the 2-core
// development VM (CBC takes nearly all of it; the flight solves about 7 s).
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <memory>
#include <string>
#include <vector>

#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_instances.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"
#include "unit_test/bench/cc_reference_milp.hpp"

using namespace rse::test::cc;
using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcStatus;
using rse::deliberative::RiskAllocation;

namespace {

constexpr double kGapTarget = 0.01;          // median
constexpr double kMaxGapTarget = 0.05;
constexpr double kTimeRatioTarget = 100.0;   // median
constexpr double kFlightBudgetS = 0.050;     // worst flight solve
constexpr double kNeverWorseTolerance = 1e-9;  // relative, optimised vs even

bool hasPlan(CcStatus s) { return s == CcStatus::kOptimal || s == CcStatus::kFeasible; }

const char* statusName(CcStatus s) {
    switch (s) {
        case CcStatus::kOptimal:
            return "optimal";
        case CcStatus::kFeasible:
            return "feasible";
        case CcStatus::kNoPlan:
            return "no-plan";
        default:
            return "bad";
    }
}

// One allocation's flight solve, timed over the repetitions.
struct FlightRun {
    CcPlan plan;
    double seconds = 0.0;   // median of the repetitions
    double slowest = 0.0;   // slowest repetition
    std::uint32_t nodes = 0;
    std::uint64_t work = 0;
    bool repeatable = true;  // every repetition gave the same cost and work
};

struct Instance {
    std::string set;
    std::size_t index = 0;
    CcProblem problem;
    double limit = 0.0;  // CBC's time limit (s)
    FlightRun even, optimised;
};

// What a worker sends back (raw bytes over a pipe: same binary, same machine).
struct Reference {
    CcStatus status = CcStatus::kNoPlan;  // CBC's
    double cost = 0.0, bound = 0.0;
    double seconds = 0.0;     // wall: build + CBC + polish
    double cpuSeconds = 0.0;  // CPU time of the same (this worker process), what the ratios use
    int nodes = 0;
    McResult mcEven, mcOptimised;  // of the flight plans (samples 0: no plan)
};

FlightRun runFlight(CcPlanner& planner, CcProblem problem, RiskAllocation allocation, int reps) {
    problem.allocation = allocation;
    FlightRun run;
    std::vector<double> times;
    for (int r = 0; r < reps; ++r) {
        CcPlan plan;
        const auto begin = std::chrono::steady_clock::now();
        planner.solve(problem, CcPlannerParams{}, &plan);
        times.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count());
        if (r == 0) {
            run.plan = plan;
            run.nodes = planner.nodes();
            run.work = planner.work();
        } else if (plan.status != run.plan.status || plan.cost != run.plan.cost || planner.work() != run.work) {
            run.repeatable = false;
        }
    }
    run.seconds = quantile(times, 0.5);
    run.slowest = quantile(times, 1.0);
    return run;
}

// CPU time of this process: CBC's time measured so that another job on the
// machine does not inflate it (its wall time does).
double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

McResult monteCarloOf(const Instance& job, const CcPlan& plan, std::size_t samples) {
    if (!hasPlan(plan.status)) {
        return McResult{};
    }
    McOptions mc;
    mc.samples = monteCarloSamples(job.problem.riskBound, samples);
    mc.seed = 1000 + job.index;  // the same numbers for both allocations' plans
    return monteCarloCollision(job.problem, plan, mc);
}

Reference runReference(const Instance& job, std::size_t samples) {
    MilpOptions options;
    options.timeLimitS = job.limit;
    const double cpuBefore = processCpuSeconds();
    const MilpResult r = solveReferenceMilp(job.problem, options);
    const double cpu = processCpuSeconds() - cpuBefore;
    Reference o;
    o.status = r.plan.status;
    o.cost = r.cost;
    o.bound = r.bestBound;
    o.seconds = r.seconds;
    o.cpuSeconds = cpu;
    o.nodes = r.nodes;
    o.mcEven = monteCarloOf(job, job.even.plan, samples);
    o.mcOptimised = monteCarloOf(job, job.optimised.plan, samples);
    return o;
}

// Runs the jobs in `workers` forked processes, longest CBC limit first.
std::vector<Reference> runReferences(const std::vector<Instance>& jobs, std::size_t samples, int workers) {
    std::vector<std::size_t> order(jobs.size());
    for (std::size_t k = 0; k < order.size(); ++k) {
        order[k] = k;
    }
    std::stable_sort(order.begin(), order.end(),
                     [&](std::size_t a, std::size_t b) { return jobs[a].limit > jobs[b].limit; });
    std::vector<Reference> out(jobs.size());
    if (workers <= 1) {
        for (std::size_t k : order) {
            out[k] = runReference(jobs[k], samples);
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
            for (std::size_t n = static_cast<std::size_t>(w); n < order.size(); n += static_cast<std::size_t>(workers)) {
                const std::size_t k = order[n];
                const Reference o = runReference(jobs[k], samples);
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
        Reference o;
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

// The figures of one instance, derived from its flight runs and reference.
struct Row {
    bool proven = false;       // CBC proved its optimum
    bool compared = false;     // a gap exists: CBC has a plan (gap +inf when the flight has none)
    double gap = NAN;          // to the optimum (proven) or to the best bound (an upper bound)
    double vsIncumbent = NAN;  // not proven: to CBC's incumbent (< 0: the flight plan is shorter)
    double ratio = NAN;        // CBC CPU seconds / flight even-split seconds
    double wallRatio = NAN;    // CBC wall seconds / flight even-split seconds
    double saved = NAN;        // (even - optimised) / even
    bool neverWorse = true;    // optimised <= even (within kNeverWorseTolerance)
    Conservatism consEven, consOptimised;
};

Row derive(const Instance& job, const Reference& ref) {
    Row row;
    const double even = job.even.plan.cost;
    row.proven = ref.status == CcStatus::kOptimal;
    const double reference = row.proven ? ref.cost : ref.bound;
    if (hasPlan(ref.status)) {
        row.compared = true;
        row.gap = hasPlan(job.even.plan.status) ? (even - reference) / reference : INFINITY;
        if (!row.proven) {
            row.vsIncumbent = hasPlan(job.even.plan.status) ? (even - ref.cost) / ref.cost : INFINITY;
        }
    }
    row.ratio = ref.cpuSeconds / job.even.seconds;
    row.wallRatio = ref.seconds / job.even.seconds;
    const bool both = hasPlan(job.even.plan.status) && hasPlan(job.optimised.plan.status);
    if (both) {
        row.saved = (even - job.optimised.plan.cost) / even;
        row.neverWorse = job.optimised.plan.cost <= even * (1.0 + kNeverWorseTolerance);
    } else {
        // No optimised plan where the even split has one is worse.
        row.neverWorse = !hasPlan(job.even.plan.status) || hasPlan(job.optimised.plan.status);
    }
    row.consEven = conservatism(job.problem.riskBound, ref.mcEven);
    row.consOptimised = conservatism(job.problem.riskBound, ref.mcOptimised);
    return row;
}

std::string gapText(const Row& w) {
    if (!w.compared) {
        return "      -  ";  // CBC found no plan: no gap
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%8.3f%s", 100.0 * w.gap, w.proven ? " " : "b");
    return buf;
}

std::string consText(const Conservatism& c, std::size_t samples) {
    if (samples == 0) {
        return "-";
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%s%.0f", c.lowerBound ? ">" : "", c.ratio);
    return buf;
}

void printRows(const std::vector<Instance>& jobs, const std::vector<Reference>& refs, const std::vector<Row>& rows) {
    std::printf("%-8s %2s %5s | %-8s %8s %5s %5s %6s | %-8s %8s %5s | %-8s %8s %8s %6s %6s | %9s %6s | %8s %8s %6s | %8s %8s %6s | %6s\n",
                "set", "k", "Delta", "even", "cost_m", "ms", "nodes", "Mwork", "optim", "cost_m", "ms", "CBC",
                "cost_m", "bound_m", "cpu_s", "wall_s", "gap%", "ratio", "mcE_rate", "mcE_cp95", "consE", "mcO_rate", "mcO_cp95",
                "consO", "saved%");
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        const Instance& j = jobs[k];
        const Reference& r = refs[k];
        const Row& w = rows[k];
        std::printf("%-8s %2zu %5.0e | %-8s %8.4f %5.1f %5u %6.2f | %-8s %8.4f %5.1f | %-8s %8.4f %8.4f %6.2f %6.2f | %s %6.0f | "
                    "%8.2e %8.2e %6s | %8.2e %8.2e %6s | %6.2f%s\n",
                    j.set.c_str(), j.index, j.problem.riskBound, statusName(j.even.plan.status), j.even.plan.cost,
                    1e3 * j.even.seconds, j.even.nodes, 1e-6 * static_cast<double>(j.even.work),
                    statusName(j.optimised.plan.status), j.optimised.plan.cost, 1e3 * j.optimised.seconds,
                    statusName(r.status), r.cost, r.bound, r.cpuSeconds, r.seconds, gapText(w).c_str(), w.ratio,
                    r.mcEven.rate, r.mcEven.upperClopperPearson, consText(w.consEven, r.mcEven.samples).c_str(),
                    r.mcOptimised.rate, r.mcOptimised.upperClopperPearson,
                    consText(w.consOptimised, r.mcOptimised.samples).c_str(), 100.0 * w.saved,
                    (j.even.repeatable && j.optimised.repeatable) ? "" : "  NOT REPEATABLE");
    }
    std::printf("(gap%% 'b': CBC did not prove within its limit; gap to its best bound, an upper bound. "
                "ratio: CBC CPU s / flight even-split s. cons: Delta / MC rate, '>' no collision: Delta / cp95.)\n");
}

// The Monte Carlo figures of one allocation's plans over a group of instances.
struct McTally {
    std::size_t plans = 0, withinDelta = 0, upperWithinDelta = 0, noHit = 0;
    std::vector<double> rates, ratios;  // ratios: conservatism, no-hit plans at their lower bound

    void add(double delta, const McResult& mc, const Conservatism& c) {
        if (mc.samples == 0) {
            return;  // no plan
        }
        ++plans;
        rates.push_back(mc.rate);
        ratios.push_back(c.ratio);
        noHit += c.lowerBound ? 1 : 0;
        withinDelta += mc.rate <= delta ? 1 : 0;
        upperWithinDelta += mc.upperClopperPearson <= delta ? 1 : 0;
    }
};

// The figures of a group of instances (a set at one Delta, or all of them).
struct Summary {
    std::size_t n = 0, proven = 0, unproven = 0, flightNoPlan = 0, notRepeatable = 0;
    std::vector<double> gaps, boundGaps, vsIncumbent, ratios, wallRatios, provenRatios, evenMs, optimisedMs,
        slowestMs, cbcS;
    std::vector<double> saved;
    McTally even, optimised;
    std::size_t neverWorse = 0;

    void add(const Instance& j, const Reference& r, const Row& w) {
        ++n;
        if (w.compared) {
            (w.proven ? gaps : boundGaps).push_back(w.gap);
        }
        if (!std::isnan(w.vsIncumbent)) {
            vsIncumbent.push_back(w.vsIncumbent);
        }
        (w.proven ? proven : unproven) += 1;
        if (!hasPlan(j.even.plan.status) || !hasPlan(j.optimised.plan.status)) {
            ++flightNoPlan;
        }
        if (!j.even.repeatable || !j.optimised.repeatable) {
            ++notRepeatable;
        }
        ratios.push_back(w.ratio);
        if (w.proven) {
            provenRatios.push_back(w.ratio);
        }
        evenMs.push_back(1e3 * j.even.seconds);
        optimisedMs.push_back(1e3 * j.optimised.seconds);
        slowestMs.push_back(1e3 * std::max(j.even.slowest, j.optimised.slowest));
        cbcS.push_back(r.cpuSeconds);
        wallRatios.push_back(w.wallRatio);
        even.add(j.problem.riskBound, r.mcEven, w.consEven);
        optimised.add(j.problem.riskBound, r.mcOptimised, w.consOptimised);
        if (!std::isnan(w.saved)) {
            saved.push_back(w.saved);
        }
        neverWorse += w.neverWorse ? 1 : 0;
    }
};

std::string pct(const std::vector<double>& v, double q) {
    if (v.empty()) {
        return "-";
    }
    char buf[32];
    std::snprintf(buf, sizeof buf, "%.2f", 100.0 * quantile(v, q));
    return buf;
}

void printSummaryHeader() {
    std::printf("%-14s %4s %9s | %11s %11s | %11s %11s | %11s %11s %9s | %9s %8s\n", "group", "n", "CBC prvd",
                "gap% med", "gap% max", "bgap% med", "bgap% max", "flt ms med", "flt ms max", "CBC cpu s",
                "ratio med", "ratio min");
}

void printSummaryTime(const char* name, const Summary& s) {
    std::printf("%-14s %4zu %4zu/%-4zu | %11s %11s | %11s %11s | %5.1f/%5.1f %5.1f/%5.1f %9.2f | %9.0f %8.0f\n", name,
                s.n, s.proven, s.n, pct(s.gaps, 0.5).c_str(), pct(s.gaps, 1.0).c_str(), pct(s.boundGaps, 0.5).c_str(),
                pct(s.boundGaps, 1.0).c_str(), quantile(s.evenMs, 0.5), quantile(s.optimisedMs, 0.5),
                quantile(s.evenMs, 1.0), quantile(s.optimisedMs, 1.0), quantile(s.cbcS, 0.5), quantile(s.ratios, 0.5),
                quantile(s.ratios, 0.0));
}

void printMcHeader() {
    std::printf("%-14s | %10s %10s %10s %12s | %10s %10s %10s %12s | %9s %9s %9s\n", "group", "E rate med", "E rate max",
                "E cons med", "E cons min", "O rate med", "O rate max", "O cons med", "O cons min", "saved%med",
                "saved%max", "O<=E");
}

std::string tallyText(const McTally& t) {
    char buf[96];
    std::snprintf(buf, sizeof buf, "%10.2e %10.2e %10.0f %6.0f (%zu>)", quantile(t.rates, 0.5), quantile(t.rates, 1.0),
                  quantile(t.ratios, 0.5), quantile(t.ratios, 0.0), t.noHit);
    return buf;
}

void printSummaryMc(const char* name, const Summary& s) {
    std::printf("%-14s | %s | %s | %9s %9s %4zu/%-4zu\n", name, tallyText(s.even).c_str(),
                tallyText(s.optimised).c_str(), pct(s.saved, 0.5).c_str(), pct(s.saved, 1.0).c_str(), s.neverWorse,
                s.n);
}

void target(const char* what, const std::string& value, bool pass) {
    std::printf("TARGET %-66s %-36s %s\n", what, value.c_str(), pass ? "PASS" : "FAIL");
}

std::string fmt(const char* format, double a, double b = 0.0) {
    char buf[96];
    std::snprintf(buf, sizeof buf, format, a, b);
    return buf;
}

// The corner-cutting fact: CBC with waypoint-only constraints steps over the
// box's corner; with segment constraints (the problem) it goes round.
void cornerDemonstration(std::size_t samples) {
    const CcProblem p = diagonalBoxInstance(0.05);
    MilpOptions w;
    w.mode = ConstraintMode::kWaypointOnly;
    const MilpResult rw = solveReferenceMilp(p, w);
    const MilpResult rs = solveReferenceMilp(p, MilpOptions{});
    McOptions mc;
    mc.samples = monteCarloSamples(p.riskBound, samples);
    const McResult mw = monteCarloCollision(p, rw.plan, mc);
    const McResult ms = monteCarloCollision(p, rs.plan, mc);
    std::printf("corner (diagonal box, N = 4, Delta = 0.05), CBC:\n");
    std::printf("  waypoint-only: %s cost %.4f m, mean path meets the box: %s, MC segment hits %.4f, waypoint hits %.4f\n",
                statusName(rw.plan.status), rw.cost, meanPathHitsObstacle(p, rw.plan.meanX, rw.plan.meanY) ? "yes" : "no",
                mw.rate, static_cast<double>(mw.waypointCollisions) / static_cast<double>(mw.samples));
    std::printf("  segment:       %s cost %.4f m, mean path meets the box: %s, MC segment hits %.2e (cp95 %.2e)\n\n",
                statusName(rs.plan.status), rs.cost, meanPathHitsObstacle(p, rs.plan.meanX, rs.plan.meanY) ? "yes" : "no",
                ms.rate, ms.upperClopperPearson);
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t count = 50, eight = 6, large = 4, samples = 100000;
    double limit = 8.0, eightLimit = 10.0, largeLimit = 20.0;
    int jobsN = 2, reps = 3;
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
        else if (key == "--reps") reps = std::max(1, static_cast<int>(v));
        else {
            std::fprintf(stderr, "unknown option %s\n", key.c_str());
            return 2;
        }
    }
    const auto begin = std::chrono::steady_clock::now();
    double load[3] = {0.0, 0.0, 0.0};
    if (getloadavg(load, 3) == 3) {
        std::printf("load average at start: %.2f %.2f %.2f (the flight timings want an idle machine)\n", load[0],
                    load[1], load[2]);
    }

    std::vector<Instance> jobs;
    auto add = [&](const char* set, const std::vector<CcProblem>& problems, double cbcLimit) {
        for (std::size_t k = 0; k < problems.size(); ++k) {
            Instance j;
            j.set = set;
            j.index = k;
            j.problem = problems[k];
            j.limit = cbcLimit;
            jobs.push_back(j);
        }
    };
    for (double delta : {0.05, 1e-3}) {
        add("provable", provableSet(delta, count), limit);
    }
    for (double delta : {0.05, 1e-3}) {
        add("eight", provableSet(delta, eight, 8), eightLimit);
    }
    add("large", largeSet(0.05, large), largeLimit);
    add("corner", {diagonalBoxInstance(0.05)}, limit);

    // 1. Every flight solve, sequentially, before anything else runs.
    {
        const auto flightBegin = std::chrono::steady_clock::now();
        const auto planner = std::make_unique<CcPlanner>();  // 450 kB: not on the stack
        for (Instance& j : jobs) {
            j.even = runFlight(*planner, j.problem, RiskAllocation::kEvenSplit, reps);
            j.optimised = runFlight(*planner, j.problem, RiskAllocation::kOptimised, reps);
        }
        std::printf("flight planner: %zu instances x 2 allocations x %d repetitions in %.1f s (sequential, "
                    "default CcPlannerParams, workBudget %u k units); time of a solve = median of its %d repetitions\n\n",
                    jobs.size(), reps,
                    std::chrono::duration<double>(std::chrono::steady_clock::now() - flightBegin).count(),
                    CcPlannerParams{}.workBudget, reps);
    }

    // 2. CBC and the Monte Carlo checks.
    cornerDemonstration(samples);
    const std::vector<Reference> refs = runReferences(jobs, samples, jobsN);
    std::vector<Row> rows;
    for (std::size_t k = 0; k < jobs.size(); ++k) {
        rows.push_back(derive(jobs[k], refs[k]));
    }

    std::printf("per instance (flight: ms = median of %d; CBC: even split, unaided, %d worker process(es), "
                "s = build + CBC + polish; MC: max(%zu, 500 / Delta) trajectories per plan):\n",
                reps, jobsN, samples);
    printRows(jobs, refs, rows);

    // 3. Summaries.
    struct Group {
        std::string name;
        std::string set;
        double delta;  // 0: any
    };
    const std::vector<Group> groups = {{"provable 5e-2", "provable", 0.05}, {"provable 1e-3", "provable", 1e-3},
                                       {"eight 5e-2", "eight", 0.05},       {"eight 1e-3", "eight", 1e-3},
                                       {"large 5e-2", "large", 0.05},       {"corner 5e-2", "corner", 0.05},
                                       {"all", "", 0.0}};
    std::vector<Summary> sums(groups.size());
    for (std::size_t g = 0; g < groups.size(); ++g) {
        for (std::size_t k = 0; k < jobs.size(); ++k) {
            if ((groups[g].set.empty() || jobs[k].set == groups[g].set) &&
                (groups[g].delta == 0.0 || jobs[k].problem.riskBound == groups[g].delta)) {
                sums[g].add(jobs[k], refs[k], rows[k]);
            }
        }
    }
    std::printf("\nsummary: cost and time (gap: flight even split to CBC's proven optimum; bgap: to CBC's best bound "
                "where it did not prove, an upper bound;\n  flight ms even/optimised, median of %d; ratio: CBC CPU time "
                "(to proof, or to its wall-clock limit: provable %.0f s, eight %.0f s, large %.0f s) / flight even-split "
                "time)\n",
                reps, limit, eightLimit, largeLimit);
    printSummaryHeader();
    for (std::size_t g = 0; g < groups.size(); ++g) {
        printSummaryTime(groups[g].name.c_str(), sums[g]);
    }
    std::printf("\nsummary: Monte Carlo (E = even split, O = optimised allocation; cons = Delta / rate; "
                "'min (n>)': n plans had no collision and enter at their lower bound Delta / cp95)\n");
    printMcHeader();
    for (std::size_t g = 0; g < groups.size(); ++g) {
        printSummaryMc(groups[g].name.c_str(), sums[g]);
    }

    // 4. The targets, over every instance.
    const Summary& all = sums.back();
    std::printf("\n");
    const double medGap = quantile(all.gaps, 0.5), maxGap = quantile(all.gaps, 1.0);
    target(fmt("median gap to the proven optimum <= 1 %% (%.0f proven)", static_cast<double>(all.gaps.size())).c_str(),
           pct(all.gaps, 0.5) + " %", medGap <= kGapTarget);
    target("max gap to the proven optimum <= 5 %", pct(all.gaps, 1.0) + " %", maxGap <= kMaxGapTarget);
    const double medRatio = quantile(all.ratios, 0.5);
    target("median time ratio CBC / flight >= 100", fmt("%.0f (min %.0f)", medRatio, quantile(all.ratios, 0.0)),
           medRatio >= kTimeRatioTarget);
    const double worstMs = std::max(quantile(all.evenMs, 1.0), quantile(all.optimisedMs, 1.0));
    target(fmt("worst flight time <= %.0f ms (median of reps, both allocations)", 1e3 * kFlightBudgetS).c_str(),
           fmt("%.1f ms (slowest single rep %.1f ms)", worstMs, quantile(all.slowestMs, 1.0)),
           worstMs <= 1e3 * kFlightBudgetS);
    for (const McTally* t : {&all.even, &all.optimised}) {
        target(t == &all.even ? "MC rate <= Delta on every even-split plan" : "MC rate <= Delta on every optimised plan",
               fmt("%.0f/%.0f plans", static_cast<double>(t->withinDelta), static_cast<double>(t->plans)),
               t->withinDelta == t->plans && t->plans == all.n);
    }
    target("optimised cost <= even-split cost everywhere", fmt("%.0f/%.0f", static_cast<double>(all.neverWorse),
           static_cast<double>(all.n)), all.neverWorse == all.n);
    std::printf("info: provable set (N = 10, M = 4): %zu of %zu instances proven by CBC (%zu/%zu at Delta 0.05, "
                "%zu/%zu at 1e-3); %zu proven over all sets\n",
                sums[0].proven + sums[1].proven, sums[0].n + sums[1].n, sums[0].proven, sums[0].n, sums[1].proven,
                sums[1].n, all.proven);
    std::printf("info: %zu instance(s) not proven by CBC within its limit: %zu with a CBC plan, gap to its best bound "
                "median %s %%, max %s %% (upper bounds); %zu where CBC found no plan (no gap)\n",
                all.unproven, all.boundGaps.size(), pct(all.boundGaps, 0.5).c_str(), pct(all.boundGaps, 1.0).c_str(),
                all.unproven - all.boundGaps.size());
    std::size_t shorter = 0, tied = 0, longer = 0;  // flight even split against CBC's incumbent
    for (double v : all.vsIncumbent) {
        (v < -1e-6 ? shorter : v > 1e-6 ? longer : tied) += 1;
    }
    std::printf("info: on those, the flight even-split plan against CBC's incumbent at its limit: shorter on %zu, "
                "within 1e-6 on %zu, longer on %zu (by at most %s %%)\n",
                shorter, tied, longer, pct(all.vsIncumbent, 1.0).c_str());
    std::printf("info: median time ratio over the proven instances only: %.0f (min %.0f); with CBC's wall time "
                "instead of its CPU time, over all: %.0f (min %.0f)\n",
                quantile(all.provenRatios, 0.5), quantile(all.provenRatios, 0.0), quantile(all.wallRatios, 0.5),
                quantile(all.wallRatios, 0.0));
    std::printf("info: MC 95 %% Clopper-Pearson upper bound <= Delta: even %zu/%zu, optimised %zu/%zu\n", all.even.upperWithinDelta,
                all.even.plans, all.optimised.upperWithinDelta, all.optimised.plans);
    std::printf("info: flight without a plan on %zu instance(s); repetitions disagreeing on %zu instance(s)\n",
                all.flightNoPlan, all.notRepeatable);
    const double total = std::chrono::duration<double>(std::chrono::steady_clock::now() - begin).count();
    std::printf("\ntotal wall time %.0f s\n", total);
    return 0;
}
