// make bench: the plan executive's consistency check and method selection
// (issue 16, "must show" 4).
//
//   build/x86_64/bin/bench_plan_executive [--plans 100]
//
// Plans: tpn_builders.hpp's seeded mission plans (drives and science
// choices with alternatives, stop windows, deadlines from the start, a plan
// variable) of 10, 50 and 200 activities, --plans of each (seeds 1..N), with
// typical deadlines (some bind in about half the plans); and 200 activities
// with tight deadlines (every plan over-subscribed), reported without a target.
// Per size, over the plans (thread CPU time, this host):
//   check      the selected plan's STN (loadStn, Stn::check): CPU us and
//              units (rows, n^2); one execution update (Stn::execute, O(n^2))
//   selection  MethodSelector with its default budget, run in slices of
//              kUnitsPerPeriod units as the deliberative task would: CPU ms,
//              work units, ns per unit, periods (slices) to the end, the
//              full slices' CPU (99th percentile and largest), and how many
//              ended proven optimal.
// Also: sizeof the STN, the selector and a plan, and start()'s CPU (the
// plan's checks and analysis, not counted in work units) on plans of
// kMaxActivities activities.
// The slice. The deliberative task runs at 10 Hz with a 5000 us budget
// (fsw/app/fsw_app.cpp, its rate-group row; not 1 Hz), and its path
// planner's slice already takes 1.1 - 2.3 ms of it (deliberative_task.hpp,
// kSliceWork). Method selection gets kUnitsPerPeriod = 150 000 units a run:
// 0.3 - 0.65 ms here (2 - 4.3 ns a unit by the host's load, printed below),
// about a tenth of the budget; MethodSelector's default budget is ten of
// them. Recalibrate on the flight computer, as for the path planner.
// Reference: the exhaustive enumeration (selection_reference.hpp: every
// selection judged on its own, with a Floyd-Warshall STN) on every 10-activity
// plan and on 300 seeded random plans of up to 6 choices.
// Targets (bench_targets.hpp):
//   - 200 activities, typical: every selection ends proven optimal within
//     10 deliberative periods;
//   - the 99th percentile of the full slices' CPU is under 1000 us (a fifth
//     of the budget). The largest is printed too: on this shared development
//     host it moves with the other processes (cache, the sibling core; 390 -
//     860 us over runs where the 99th percentile stayed within 310 - 510 us),
//     so it is not the target; on the flight computer it is what counts;
//   - the selector's cost and feasibility equal the exhaustive optimum's on
//     every reference plan.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <string>
#include <vector>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "unit_test/bench/bench_targets.hpp"
#include "unit_test/plan_executive/selection_reference.hpp"
#include "unit_test/plan_executive/tpn_builders.hpp"

using namespace rse::plan_executive;

namespace {

constexpr std::uint32_t kUnitsPerPeriod = 150000;
constexpr std::size_t kTargetPeriods = 10;
constexpr double kSliceBudgetUs = 1000.0;

// Static storage, as in flight.
MethodSelector selector;
Stn stn;
Tpn plan;

double cpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

double quantile(std::vector<double> v, double q) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    return v[static_cast<std::size_t>(q * static_cast<double>(v.size() - 1) + 0.5)];
}

struct SizeResult {
    std::vector<double> checkUs, checkUnits, executeUs, selectMs, work, periods, events, choices;
    std::vector<double> fullSliceUs;  // slices that did a whole kUnitsPerPeriod
    double largestSliceUs = 0.0;
    double nsPerUnitSum = 0.0;
    std::size_t plans = 0, proven = 0, withinTarget = 0, none = 0;
};

void runSize(std::size_t activities, bool tight, std::size_t plans, SizeResult* out) {
    for (std::uint32_t seed = 1; seed <= plans; ++seed) {
        rse::test::plan::missionPlan(seed, activities, &plan, tight);
        out->events.push_back(plan.eventCount);
        out->choices.push_back(plan.choiceCount);
        const SelectionInput input;
        const SelectionParams params;
        double cpu = 0.0;
        std::size_t periods = 0;
        const double s0 = cpuSeconds();
        const bool started = selector.start(plan, input, params) == rse::core::Status::kOk;
        cpu += cpuSeconds() - s0;
        for (std::size_t k = 0; started && k < 100000 && !selector.finished(); ++k) {
            const std::uint64_t w0 = selector.work();
            const double t0 = cpuSeconds();
            (void)selector.step(kUnitsPerPeriod);
            const double us = 1e6 * (cpuSeconds() - t0);
            cpu += us * 1e-6;
            out->largestSliceUs = std::max(out->largestSliceUs, us);
            if (selector.work() - w0 >= kUnitsPerPeriod) {
                out->fullSliceUs.push_back(us);
            }
            ++periods;
        }
        const SelectionResult& r = selector.result();
        ++out->plans;
        out->proven += r.status == SelectionStatus::kSelected ? 1U : 0U;
        out->none += r.hasSelection ? 0U : 1U;
        out->withinTarget += r.status == SelectionStatus::kSelected && periods <= kTargetPeriods ? 1U : 0U;
        out->selectMs.push_back(1e3 * cpu);
        out->work.push_back(static_cast<double>(selector.work()));
        out->periods.push_back(static_cast<double>(periods));
        out->nsPerUnitSum += 1e9 * cpu / static_cast<double>(std::max<std::uint64_t>(selector.work(), 1));
        if (!r.hasSelection || loadStn(plan, r.selection, &stn) != rse::core::Status::kOk) {
            continue;
        }
        const double c0 = cpuSeconds();
        const StnState st = stn.check();
        out->checkUs.push_back(1e6 * (cpuSeconds() - c0));
        out->checkUnits.push_back(static_cast<double>(stn.work()));
        if (st == StnState::kConsistent) {
            const double e0 = cpuSeconds();
            (void)stn.execute(1, stn.window(1).earliestMs);
            out->executeUs.push_back(1e6 * (cpuSeconds() - e0));
        }
    }
}

void report(const char* label, const SizeResult& r) {
    std::printf("%-16s %5zu %4.0f %4.0f | %8.1f %8.1f %8.0f %7.1f | "
                "%8.2f %8.2f %10.0f %10.0f %5.2f %4.0f %4.0f %7.0f %5zu/%zu\n",
                label, r.plans, quantile(r.events, 0.5), quantile(r.choices, 0.5), quantile(r.checkUs, 0.5),
                quantile(r.checkUs, 1.0), quantile(r.checkUnits, 0.5), quantile(r.executeUs, 0.5),
                quantile(r.selectMs, 0.5), quantile(r.selectMs, 1.0), quantile(r.work, 0.5), quantile(r.work, 1.0),
                r.nsPerUnitSum / static_cast<double>(std::max<std::size_t>(r.plans, 1)), quantile(r.periods, 0.5),
                quantile(r.periods, 1.0), r.largestSliceUs, r.proven, r.plans);
}

// The selector against the exhaustive reference on one plan: true when they agree.
bool agreesWithReference(const SelectionInput& input, std::size_t* selections) {
    SelectionParams params;
    params.workBudget = 0xFFFFFFFFU;
    SelectionResult r;
    const SelectionStatus st = selector.solve(plan, input, params, &r);
    const rse::test::plan::ReferenceOutcome ref = rse::test::plan::exhaustiveOptimum(plan, input, params, &stn);
    *selections += ref.selections;
    if (!ref.found) {
        return st == SelectionStatus::kNoneExists;
    }
    return st == SelectionStatus::kSelected && std::fabs(r.cost - ref.cost) <= 1e-9 * (1.0 + std::fabs(ref.cost));
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t plans = 100;
    for (int a = 1; a + 1 < argc; a += 2) {
        if (std::string(argv[a]) == "--plans") {
            plans = static_cast<std::size_t>(std::atoi(argv[a + 1]));
        } else {
            std::fprintf(stderr, "unknown option %s\n", argv[a]);
            return 2;
        }
    }
    if (plans < 1 || plans > 10000) {
        std::fprintf(stderr, "--plans must be in 1..10000\n");
        return 2;
    }
    std::printf("plan executive: STN check and method selection, %zu seeded mission plans a row; slice %u units a "
                "deliberative period (10 Hz, 5000 us budget)\n",
                plans, kUnitsPerPeriod);
    std::printf("sizeof: Stn %zu B, MethodSelector %zu B, Tpn %zu B\n", sizeof(Stn), sizeof(MethodSelector),
                sizeof(Tpn));
    std::printf("%-16s %5s %4s %4s | %8s %8s %8s %7s | %8s %8s %10s %10s %5s %4s %4s %7s %7s\n", "plans", "n", "ev",
                "ch", "chk us", "max", "rows", "exec us", "sel ms", "max", "units", "max", "ns/u", "per", "max",
                "slice us", "proven");
    SizeResult sizes[4];
    const std::size_t activities[4] = {10, 50, 200, 200};
    const char* labels[4] = {"10 activities", "50 activities", "200 activities", "200 tight"};
    for (std::size_t i = 0; i < 4; ++i) {
        runSize(activities[i], i == 3, plans, &sizes[i]);
        report(labels[i], sizes[i]);
    }
    std::printf("(medians and maxima over the plans: ev events, ch choices; chk the full check, rows its units; exec "
                "one execution update; sel selection CPU incl. start(); per periods to the end; proven: ended "
                "optimal)\n");
    double startWorstUs = 0.0;
    for (std::uint32_t seed = 1; seed <= plans; ++seed) {
        rse::test::plan::missionPlan(seed, kMaxActivities, &plan);
        const double t0 = cpuSeconds();
        const bool started = selector.start(plan, SelectionInput{}, SelectionParams{}) == rse::core::Status::kOk;
        startWorstUs = std::max(startWorstUs, 1e6 * (cpuSeconds() - t0));
        if (!started) {
            std::fprintf(stderr, "bench: a generated plan was refused\n");
            return 1;
        }
    }
    std::printf("start() on plans of %zu activities: at most %.0f us of CPU\n", kMaxActivities, startWorstUs);
    const SizeResult& tight = sizes[3];
    std::printf("tight deadlines (no target): %zu of %zu proven within %zu periods, %zu ended on the budget "
                "(best so far kept), %zu without a selection\n",
                tight.withinTarget, tight.plans, kTargetPeriods, tight.plans - tight.proven, tight.none);

    // The reference: every 10-activity plan, then random plans of up to 6 choices.
    std::size_t agreed = 0, compared = 0, selections = 0;
    for (std::uint32_t seed = 1; seed <= plans; ++seed) {
        rse::test::plan::missionPlan(seed, 10, &plan);
        agreed += agreesWithReference(SelectionInput{}, &selections) ? 1U : 0U;
        ++compared;
    }
    for (std::uint32_t seed = 1; seed <= 300; ++seed) {
        SelectionInput input;
        rse::test::plan::randomSmallPlan(seed, 6, &plan, &input);
        agreed += agreesWithReference(input, &selections) ? 1U : 0U;
        ++compared;
    }

    rse::bench::Targets targets;
    const SizeResult& big = sizes[2];
    bool ok = targets.check(big.withinTarget == big.plans);
    std::printf("TARGET 200 activities: selection proven optimal within %zu periods on every plan: %zu of %zu "
                "(max %.0f periods)  %s\n",
                kTargetPeriods, big.withinTarget, big.plans, quantile(big.periods, 1.0), ok ? "PASS" : "FAIL");
    double largestSlice = 0.0;
    std::vector<double> fullSlices;
    for (const SizeResult& s : sizes) {
        largestSlice = std::max(largestSlice, s.largestSliceUs);
        fullSlices.insert(fullSlices.end(), s.fullSliceUs.begin(), s.fullSliceUs.end());
    }
    const double p99 = quantile(fullSlices, 0.99);
    ok = targets.check(p99 < kSliceBudgetUs);
    std::printf("TARGET slice of %u units under %.0f us of CPU (99th percentile of %zu full slices): %.0f us "
                "(median %.0f, largest %.0f)  %s\n",
                kUnitsPerPeriod, kSliceBudgetUs, fullSlices.size(), p99, quantile(fullSlices, 0.5), largestSlice,
                ok ? "PASS" : "FAIL");
    ok = targets.check(agreed == compared);
    std::printf("TARGET exhaustive reference: cheapest consistent selection equal on every plan: %zu of %zu (%zu "
                "selections judged)  %s\n",
                agreed, compared, selections, ok ? "PASS" : "FAIL");
    return targets.finish();
}
