// make bench: the plan executive's consistency check and method selection,
// and, in lockstep, its latency from a failure report to the first
// regenerated dispatch (issue 16, "must show" 4).
//
//   build/x86_64/bin/bench_plan_executive [--plans 100] [--latency-runs 10]
//
// Run from the repository's top (make bench does): the latency part reads
// sim_stub/scenarios/two_targets.toml and unit_test/fuzz/corpus/plan/two_targets.plan.
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
//
// Latency, in lockstep: the whole flight software and the simulator
// (unit_test/support/plan_lockstep.hpp: sim::LockstepRig and the
// authenticated in-memory ground; the plan uplinked in PLAN_LOAD chunks and
// PLAN_START), on the two-targets site. A first run without faults finds the
// frame the executive sends sample(target 2) to the grinder; then
// --latency-runs runs with the scenario's own fault, instrument_failure of
// the grinder (code 0x42) kFaultIntoSampleS + k frames later (k = 0, 1, ...):
// the simulated grinder aborts the sample and reports failed on CAN, and k
// moves the report over every phase of the executive's 10 Hz period. In
// 10 ms minor frames, observed from outside the executive (bus messages
// through the rig's probe, and the event log, as the ground sees it):
//   (a) the failure report: the frame whose InstrumentStatusMsg (the CAN I/O
//       task's decoding of the grinder's failure frame, sent by the simulator
//       at that frame's start) first carries a fault code;
//   (b) the first regenerated dispatch: the first frame after the plan is
//       regenerated (event 963) in which a start command is on the bus
//       (InstrumentCommandMsg or PlanGoalMsg): here image(target 2) to the
//       camera, the replacement of the sample that was running (event 956
//       in the same frame; the run is refused as a measurement otherwise).
// Broken down: detect, (a) to the executive's run that sees the grinder
// failed (event 972; the running sample failed, 960, and regeneration
// begun, 962, in that run); regen, to 963, with the sliced selector's runs
// (event 955) and work; dispatch, 963 to (b), the regenerated network's
// sliced check between. The executive runs every 10th frame, so
//   total = detect + 10 x (selection runs + check runs - 1),  detect in 0..9,
// check runs = ceil(events^2 / 4096). Plans: two targets (the example), and
// traverses, the same with 20 or 45 stops after target 2, each a drive and
// a quick image or a cheaper, slower panorama, under deadlines that make the
// choices compete (traversePlan): selection over several runs (traverse 20),
// a network checked over three runs (traverse 45), a selection that runs
// to its budget (traverse 20 tight, reported without a target), and 200
// activities uplinked and run whole (traverse 66 terse, short names).
// Over the same runs, every rate-group row's largest run against its budget
// (BudgetTally): CPU-timed rows (the sliced planners, command ingest) in
// thread CPU time, judged; the others in host wall time, printed only.
// Targets (checked through bench_targets.hpp's Targets):
//   - 200 activities, typical: every selection ends proven optimal within
//     10 deliberative periods;
//   - the 99th percentile of the full slices' CPU is under 1000 us (a fifth
//     of the budget). The largest is printed too: on this shared development
//     host it moves with the other processes (cache, the sibling core; 390 -
//     860 us over runs where the 99th percentile stayed within 310 - 510 us),
//     so it is not the target; on the flight computer it is what counts;
//   - the selector's cost and feasibility equal the exhaustive optimum's on
//     every reference plan;
//   - every CPU-timed task inside its budget on every lockstep run of each
//     targeted plan (issue 16: "with every task run inside its budget");
//   - executive latency from a failure report to the first regenerated
//     dispatch, on every run of each targeted plan: at most
//     kLatencyTargetFrames = 100 frames, 10 deliberative periods (1 s).
//     Issue 16 asks selection within 10 deliberative periods; this holds the
//     whole chain (seen, re-selected, checked, commanded) to the same 10
//     periods. Met when selection and check together take at most 10 runs
//     (detect <= 9); a selection that runs to its budget (10 runs) cannot
//     meet it, whence the tight traverse without a target. Frames are
//     deterministic (work units, not time): the same on every host.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ctime>
#include <exception>
#include <random>
#include <string>
#include <vector>

#include "fsw/app/fsw_app.hpp"
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "fsw/plan_executive/stn.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/bench/bench_targets.hpp"
#include "unit_test/fsw/plan_executive/selection_reference.hpp"
#include "unit_test/fsw/plan_executive/tpn_builders.hpp"
#include "unit_test/support/plan_lockstep.hpp"

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

// ---------------------------------------------------------------------------
// In lockstep: the latency from a failure report to the first regenerated
// dispatch (see the header comment).

using rse::core::TimeNs;
constexpr TimeNs kFrameNs = rse::app::kMinorFramePeriod;
constexpr double kLatencyTargetFrames = 100.0;  // 10 deliberative periods (see the header comment)
constexpr double kFaultIntoSampleS = 5.0;       // the grinder fails this long after sample(target 2) is sent
constexpr const char* kScenarioPath = "sim_stub/scenarios/two_targets.toml";
constexpr const char* kTwoTargetsPath = "unit_test/fuzz/corpus/plan/two_targets.plan";

// The two-targets plan with a traverse after it: `stops` more stops past
// target 2, each a drive and a choice between a quick image ([30, 60] s,
// cost 6 + the option's 2) and a panorama (longer, [120..400, +60] s, cost
// 0..2: cheaper but slower); every fourth stop and the last a deadline from
// done2 that leaves `tightness` of the panoramas' extra time, so the choices
// compete for it (a knapsack: the search needs several runs). The traverse's
// targets (3..) are not on the site: the measurement ends before it; only
// its selection counts. Deterministic from the seed.
// Compact (`compact`): the same stops in short names (a/d/r/v/q/p + the stop's
// number), the option's cost on the choice and no Asks on the traverse's own
// activities, so that 66 stops (200 activities) fit the 16 384-byte plan text;
// the stops past the 62nd have the quick image alone (a plan holds at most 64
// choices, tpn.hpp). The two-targets part keeps its Asks, so the grinder's
// failure still deprecates sample(target 2) and regenerates the whole plan.
constexpr std::size_t kTerseChoiceStops = 62;  // + the two targets' 2 choices = kMaxChoices
std::string traversePlan(const std::string& twoTargets, std::size_t stops, std::uint32_t seed, double tightness,
                         bool compact = false) {
    std::string text;
    std::size_t at = 0;
    while (at < twoTargets.size()) {  // the two-targets plan, renamed, without its end
        std::size_t eol = twoTargets.find('\n', at);
        eol = eol == std::string::npos ? twoTargets.size() : eol;
        const std::string line = twoTargets.substr(at, eol - at);
        at = eol + 1;
        if (line.rfind("plan ", 0) == 0) {
            text += "plan traverse" + std::to_string(stops) + "\n";
        } else if (line != "end" && !line.empty() && line[0] != '#') {
            text += line + "\n";
        }
    }
    std::mt19937 rng(seed);
    const auto uniform = [&](unsigned lo, unsigned hi) { return lo + static_cast<unsigned>(rng() % (hi - lo + 1)); };
    std::string here = "done2";
    unsigned least = 0, extra = 0;  // from done2: the drives' and quick images' least time; the panoramas' extra
    char line[200];
    for (std::size_t i = 1; i <= stops; ++i) {
        const std::size_t n = i + 2;
        const unsigned drive = uniform(60, 300);
        unsigned pan = uniform(120, 400);
        if (compact && i > kTerseChoiceStops) {
            std::snprintf(line, sizeof line,
                          "event a%zu\nevent d%zu\nactivity r%zu drive %s a%zu [%u, %u] cost 5 at %zu %zu\n"
                          "activity q%zu image a%zu d%zu [30, 60] cost 8 target %zu\n",
                          n, n, n, here.c_str(), n, drive, drive * 3 / 2, 20 + 2 * i, 5 + i % 3, n, n, n, n);
            text += line;
            pan = 30;  // no panorama here: no extra time to share
        } else if (compact) {
            std::snprintf(line, sizeof line,
                          "event a%zu\nevent d%zu\nchoice v%zu q cost 8 p\n"
                          "activity r%zu drive %s a%zu [%u, %u] cost 5 at %zu %zu\n"
                          "activity q%zu image a%zu d%zu [30, 60] target %zu when v%zu.q\n",
                          n, n, n, n, here.c_str(), n, drive, drive * 3 / 2, 20 + 2 * i, 5 + i % 3, n, n, n, n, n);
            text += line;
            std::snprintf(line, sizeof line, "activity p%zu image a%zu d%zu [%u, %u] cost %.2f target %zu when v%zu.p\n",
                          n, n, n, pan, pan + 60, 0.25 * uniform(0, 8), n, n);
            text += line;
        } else {
            std::snprintf(line, sizeof line,
                          "event at%zu\nevent done%zu\nchoice view%zu quick cost 2 pan\n"
                          "activity drive%zu drive %s at%zu [%u, %u] cost 5 at %zu %zu ask drive_ML!=failed\n",
                          n, n, n, n, here.c_str(), n, drive, drive * 3 / 2, 20 + 2 * i, 5 + i % 3);
            text += line;
            std::snprintf(line, sizeof line,
                          "activity quick%zu image at%zu done%zu [30, 60] cost 6 target %zu ask camera=ok when view%zu.quick\n"
                          "activity pan%zu image at%zu done%zu [%u, %u] cost %.2f target %zu ask camera=ok when view%zu.pan\n",
                          n, n, n, n, n, n, n, n, pan, pan + 60, 0.25 * uniform(0, 8), n, n);
            text += line;
        }
        least += drive + 30;
        extra += pan - 30;
        if (i % 4 == 0 || i == stops) {
            std::snprintf(line, sizeof line, "constraint done2 %s%zu [0, %u]\n", compact ? "d" : "done", n,
                          least + static_cast<unsigned>(tightness * extra));
            text += line;
        }
        here = (compact ? "d" : "done") + std::to_string(n);
    }
    return text + "end\n";
}

// One run's marks: times (ns) of the first of each, -1 until seen.
struct LatencyMarks {
    TimeNs report = -1;        // the grinder's failure (faultCode != 0) in an InstrumentStatusMsg on the flight bus
    TimeNs detected = -1;      // event 972 "grinder now failed": the executive's run that took the report
    TimeNs sampleFailed = -1;  // event 960 naming sample2: the running activity failed
    TimeNs regenerating = -1;  // event 962
    TimeNs regenerated = -1;   // event 963
    TimeNs dispatched = -1;    // the first Start command (instrument or drive goal) on the bus after 963
    TimeNs started = -1;       // event 956 naming image2 (the replacement started)
    bool operatorCalled = false;
    bool proven = false;         // event 963 says "(selected)": proven optimal, not the budget's best
    unsigned selectionRuns = 0;  // event 955 after 962: "... work units in N runs"
    unsigned long long selectionWork = 0;
    std::uint32_t events = 0, activities = 0, choices = 0;
    const char* what = "none";  // what the first dispatch was
};

struct LatencyRun {
    const char* invalid = nullptr;  // why the run measured nothing (nullptr: it did)
    double detect = 0.0, regenerate = 0.0, dispatch = 0.0, total = 0.0;  // frames
    double selectionRuns = 0.0;
    double selectionWork = 0.0;
    bool proven = false;
};

// Reads what the flight software published this frame (bus messages through
// the rig's probe, and the event log) into the marks.
class LatencyObserver {
public:
    explicit LatencyObserver(rse::sim::LockstepRig& rig) : rig_(rig) {}

    void frame() {
        const TimeNs now = rig_.clock().now();
        rse::core::Event e;
        while (rse::core::isOk(rig_.fsw().events().read(&cursor_, &e))) {
            take(e);
        }
        if (m.report < 0 && rig_.instrumentStatus(rse::msg::Instrument::kGrinder).faultCode != 0) {
            m.report = now;
        }
        const Counts c = counts();
        if (m.regenerated >= 0 && m.dispatched < 0) {
            if (c.camera != base_.camera) {
                const rse::msg::InstrumentCommandMsg& cmd = rig_.instrumentCommand(rse::msg::Instrument::kCamera);
                m.what = cmd.action == rse::msg::InstrumentAction::kImage && cmd.targetId == 2
                             ? "image of target 2 (camera)"
                             : "another camera command";
                m.dispatched = now;
            } else if (c.grinder != base_.grinder || c.goals != base_.goals) {
                m.what = c.grinder != base_.grinder ? "a grinder command" : "a drive goal";
                m.dispatched = now;
            }
        }
        if (m.regenerated < 0) {
            base_ = c;  // the counts before the run that regenerated
        }
    }
    bool done() const { return m.dispatched >= 0 || m.operatorCalled; }

    LatencyMarks m;

private:
    struct Counts {
        std::uint32_t camera = 0, grinder = 0, goals = 0;
    };
    Counts counts() const {
        return Counts{rig_.instrumentCommandCount(rse::msg::Instrument::kCamera),
                      rig_.instrumentCommandCount(rse::msg::Instrument::kGrinder), rig_.planGoalCount()};
    }
    void take(const rse::core::Event& e) {
        namespace ev = rse::plan_executive::events;
        if (e.id == ev::kComponentState && m.detected < 0 && std::strstr(e.text, "grinder now failed") != nullptr) {
            m.detected = e.time;
        } else if (e.id == ev::kActivityFailed && m.sampleFailed < 0 && std::strstr(e.text, " sample2 ") != nullptr) {
            m.sampleFailed = e.time;
        } else if (e.id == ev::kRegenerating && m.detected >= 0 && m.regenerating < 0) {
            m.regenerating = e.time;
        } else if (e.id == ev::kSelectionDone && m.regenerating >= 0 && m.regenerated < 0) {
            const char* cost = std::strstr(e.text, "cost ");
            if (cost == nullptr ||
                std::sscanf(cost, "cost %*f, %llu work units in %u runs", &m.selectionWork, &m.selectionRuns) != 2) {
                m.selectionRuns = 0;
            }
        } else if (e.id == ev::kRegenerated && m.regenerating >= 0 && m.regenerated < 0) {
            m.regenerated = e.time;
            m.proven = std::strstr(e.text, " regenerated (selected):") != nullptr;
        } else if (e.id == ev::kActivityStarted && m.regenerated >= 0 && m.started < 0 &&
                   std::strstr(e.text, " image2 started") != nullptr) {
            m.started = e.time;
        } else if (e.id == ev::kOperatorCalled) {
            m.operatorCalled = true;
        }
    }

    rse::sim::LockstepRig& rig_;
    rse::core::EventLog::Cursor cursor_{};
    Counts base_{};
};

// Every rate-group row's runs against its budget over the lockstep runs of a
// plan. A CPU-timed row (the sliced planners and command ingest, fsw_app.cpp)
// is judged in its thread's CPU time: the executive's clock is simulated in
// lockstep, so its own over-budget count proves nothing here. The other rows
// have only host wall time, printed but not judged (a shared VM's preemption
// is in it).
struct BudgetTally {
    struct Row {
        std::string name;
        std::uint32_t budgetUs = 0;
        bool cpuTimed = false;
        std::uint64_t runs = 0;
        std::uint64_t cpuOver = 0;   // runs whose CPU time exceeded the budget (CPU-timed rows)
        std::uint64_t wallOver = 0;  // runs whose host wall time did (not judged), over the whole run only as max
        TimeNs cpuMax = 0, hostMax = 0;
    };
    std::vector<Row> rows;

    void add(const rse::core::Executive& ex) {
        rows.resize(ex.taskCount());
        for (std::size_t i = 0; i < ex.taskCount(); ++i) {
            const rse::core::RateGroupEntry* e = ex.entry(i);
            const rse::core::TaskStats* t = ex.taskStats(i);
            Row& r = rows[i];
            r.name = e->name;
            r.budgetUs = e->budgetUs;
            r.cpuTimed = e->cpuTimed;
            r.runs += t->runs;
            r.cpuOver += t->cpuOverBudget;
            r.cpuMax = std::max(r.cpuMax, t->cpuMax);
            r.hostMax = std::max(r.hostMax, t->hostMax);
            r.wallOver += t->hostMax > static_cast<TimeNs>(e->budgetUs) * rse::core::kNsPerUs ? 1U : 0U;
        }
    }
    std::uint64_t cpuOver() const {
        std::uint64_t n = 0;
        for (const Row& r : rows) {
            n += r.cpuTimed ? r.cpuOver : 0U;
        }
        return n;
    }
};

// The plan uplinked and run on the scenario (faults as given) until stop()
// holds after a frame, or `limit` of rover time. The observer sees every frame.
template <typename Stop>
const char* runPlan(const rse::sim::Scenario& scenario, const std::string& text, TimeNs limit, Stop stop,
                    LatencyMarks* marks, TimeNs* endedAt, BudgetTally* budgets) {
    rse::test::PlanLockstep session(scenario);
    if (const char* failed = session.start(true)) {
        return failed;
    }
    LatencyObserver observer(session.rig());
    if (!session.uplink(text)) {
        return "the plan could not be sent";
    }
    rse::sim::LockstepRig& rig = session.rig();
    const bool held = rig.runUntil(
        [&] {
            observer.frame();
            return stop(rig, observer);
        },
        limit);
    const rse::plan_executive::Tpn& p = rig.fsw().planExecutive().plan();
    observer.m.events = p.eventCount;
    observer.m.activities = p.activityCount;
    observer.m.choices = p.choiceCount;
    *marks = observer.m;
    *endedAt = rig.clock().now();
    budgets->add(rig.fsw().executive());
    return held ? nullptr : "ran out of time";
}

double frames(TimeNs from, TimeNs to) { return static_cast<double>(to - from) / static_cast<double>(kFrameNs); }

struct LatencyPlan {
    const char* label;
    bool targeted;  // false: reported without a target
    std::string text;
    std::vector<LatencyRun> runs;
    LatencyMarks shape;  // the plan's size, from a run
    BudgetTally budgets;  // every run of the plan, the clean one too
};

// Phase k of `phases`: the grinder fails kFaultIntoSampleS + k frames after
// the executive sent sample(target 2) (found by a run without the fault), so
// the report lands at every offset within the executive's 10 Hz period.
bool measurePlan(const rse::sim::Scenario& site, std::size_t phases, LatencyPlan* lp) {
    rse::sim::Scenario clean = site;
    clean.faults.clear();
    LatencyMarks marks;
    TimeNs sampleSent = 0;
    const char* failed = runPlan(
        clean, lp->text, 600 * rse::core::kNsPerSec,
        [](rse::sim::LockstepRig& rig, const LatencyObserver&) {
            const rse::msg::InstrumentCommandMsg& c = rig.instrumentCommand(rse::msg::Instrument::kGrinder);
            return c.action == rse::msg::InstrumentAction::kSample && c.targetId == 2;
        },
        &marks, &sampleSent, &lp->budgets);
    if (failed != nullptr) {
        std::fprintf(stderr, "bench: %s (%zu B of plan text): sample(target 2) never sent: %s\n", lp->label,
                     lp->text.size(), failed);
        if (std::getenv("BENCH_PLAN_DUMP") != nullptr) {
            std::fputs(lp->text.c_str(), stderr);
        }
        return false;
    }
    lp->shape = marks;
    for (std::size_t k = 0; k < phases; ++k) {
        rse::sim::Scenario s = clean;
        rse::sim::FaultSpec f;
        f.type = rse::sim::FaultType::kInstrumentFailure;
        f.device = rse::sim::SimDevice::kGrinder;
        f.at = sampleSent + static_cast<TimeNs>(kFaultIntoSampleS * 1e9) + static_cast<TimeNs>(k) * kFrameNs;
        f.until = rse::sim::kNever;
        f.faultCode = 0x42;
        s.faults.push_back(f);
        TimeNs ended = 0;
        LatencyRun run;
        const char* why = runPlan(
            s, lp->text, f.at + 60 * rse::core::kNsPerSec,
            [](rse::sim::LockstepRig&, const LatencyObserver& o) { return o.done(); }, &marks, &ended,
            &lp->budgets);
        const LatencyMarks& m = marks;
        if (why != nullptr) {
            run.invalid = why;
        } else if (m.operatorCalled) {
            run.invalid = "the operator was called";
        } else if (m.report < 0 || m.detected < 0 || m.regenerating < 0 || m.regenerated < 0) {
            run.invalid = "no failure report, detection or regeneration";
        } else if (m.sampleFailed != m.detected) {
            run.invalid = "sample2 was not running when the grinder failed";
        } else if (std::strcmp(m.what, "image of target 2 (camera)") != 0 || m.started != m.dispatched) {
            run.invalid = "the first regenerated dispatch was not image2";
        } else if (m.selectionRuns == 0) {
            run.invalid = "no selection event (955) after 962";
        }
        if (run.invalid == nullptr) {
            run.detect = frames(m.report, m.detected);
            run.regenerate = frames(m.detected, m.regenerated);
            run.dispatch = frames(m.regenerated, m.dispatched);
            run.total = frames(m.report, m.dispatched);
            run.selectionRuns = m.selectionRuns;
            run.selectionWork = static_cast<double>(m.selectionWork);
            run.proven = m.proven;
        } else {
            std::printf("  %s, phase %zu: not measured: %s\n", lp->label, k, run.invalid);
        }
        lp->runs.push_back(run);
    }
    return true;
}

std::vector<double> field(const LatencyPlan& p, double LatencyRun::*member) {
    std::vector<double> v;
    for (const LatencyRun& r : p.runs) {
        if (r.invalid == nullptr) {
            v.push_back(r.*member);
        }
    }
    return v;
}

}  // namespace

int main(int argc, char** argv) {
    std::size_t plans = 100;
    std::size_t phases = 10;
    for (int a = 1; a + 1 < argc; a += 2) {
        if (std::string(argv[a]) == "--plans") {
            plans = static_cast<std::size_t>(std::atoi(argv[a + 1]));
        } else if (std::string(argv[a]) == "--latency-runs") {
            phases = static_cast<std::size_t>(std::atoi(argv[a + 1]));
        } else {
            std::fprintf(stderr, "unknown option %s\n", argv[a]);
            return 2;
        }
    }
    if (plans < 1 || plans > 10000) {
        std::fprintf(stderr, "--plans must be in 1..10000\n");
        return 2;
    }
    if (phases < 1 || phases > 100) {
        std::fprintf(stderr, "--latency-runs must be in 1..100\n");
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

    // In lockstep: a failure report to the first regenerated dispatch.
    const std::string twoTargets = rse::test::readTextFile(kTwoTargetsPath);
    if (twoTargets.empty()) {
        std::fprintf(stderr, "bench: cannot read %s (run from the repository's top)\n", kTwoTargetsPath);
        return 1;
    }
    rse::sim::Scenario site;
    try {
        site = rse::sim::loadScenarioFile(kScenarioPath);
    } catch (const std::exception& e) {
        std::fprintf(stderr, "bench: %s: %s\n", kScenarioPath, e.what());
        return 1;
    }
    // Traverse plans: seeds and tightness picked for what each shows (selection
    // over several runs; a network checked over several runs; a selection that
    // runs to its budget, reported without a target, as "200 tight" above).
    LatencyPlan latencyPlans[] = {
        {"two targets", true, twoTargets, {}, {}, {}},
        {"traverse 20", true, traversePlan(twoTargets, 20, 3, 0.6), {}, {}, {}},
        {"traverse 45", true, traversePlan(twoTargets, 45, 7, 0.95), {}, {}, {}},
        {"traverse 20 tight", false, traversePlan(twoTargets, 20, 3, 0.5), {}, {}, {}},
        {"traverse 66 terse", true, traversePlan(twoTargets, 66, 7, 0.95, true), {}, {}, {}},
    };
    std::printf("\nplan executive in lockstep (rse-fsw and rse-sim over the in-memory CAN bus, %s): the grinder "
                "fails %.0f s into sample(target 2) (scenario fault), %zu runs a plan, one at each phase of the "
                "executive's 10 Hz period; 10 ms frames from the failure report on the flight bus:\n",
                kScenarioPath, kFaultIntoSampleS, phases);
    std::printf("%-17s %4s %4s %3s %6s | %6s | %8s %6s %17s %6s | %8s | %17s\n", "plan", "ev", "act", "ch",
                "text B", "detect", "regen", "runs", "selection units", "proven", "dispatch", "total min/med/max");
    const double cpuStart = cpuSeconds();
    for (LatencyPlan& p : latencyPlans) {
        if (!measurePlan(site, phases, &p)) {
            return 1;
        }
        const auto lo = [&](double LatencyRun::*f) { return quantile(field(p, f), 0.0); };
        const auto hi = [&](double LatencyRun::*f) { return quantile(field(p, f), 1.0); };
        std::size_t proven = 0;
        for (const LatencyRun& r : p.runs) {
            proven += r.invalid == nullptr && r.proven ? 1U : 0U;
        }
        std::printf("%-17s %4u %4u %3u %6zu | %2.0f..%-2.0f | %3.0f..%-3.0f %2.0f..%-2.0f %8.0f..%-7.0f %3zu/%-2zu | "
                    "%3.0f..%-3.0f | %5.0f %5.0f %5.0f\n",
                    p.label, p.shape.events, p.shape.activities, p.shape.choices, p.text.size(), lo(&LatencyRun::detect),
                    hi(&LatencyRun::detect), lo(&LatencyRun::regenerate), hi(&LatencyRun::regenerate),
                    lo(&LatencyRun::selectionRuns), hi(&LatencyRun::selectionRuns), lo(&LatencyRun::selectionWork),
                    hi(&LatencyRun::selectionWork), proven, p.runs.size(), lo(&LatencyRun::dispatch),
                    hi(&LatencyRun::dispatch), lo(&LatencyRun::total), quantile(field(p, &LatencyRun::total), 0.5),
                    hi(&LatencyRun::total));
    }
    std::printf("(min..max over the runs, in frames. detect: the report -> the executive's run that sees the grinder "
                "failed (972; sample2 failed, 960, and regeneration begun, 962, in that run); regen: -> plan "
                "regenerated (963), and the sliced selector's runs (%u units a run) and work; proven: ended optimal; "
                "dispatch: 963 -> the regenerated selection's first start on the bus, image(target 2) to the camera "
                "(the network's sliced check, %u rows a run, between); total: report -> that dispatch. %.1f s of "
                "CPU)\n",
                rse::plan_executive::PlanExecutiveTask::kSelectionUnitsPerRun,
                rse::plan_executive::PlanExecutiveTask::kCheckUnitsPerRun, cpuSeconds() - cpuStart);
    std::printf("\ntask budgets over each plan's lockstep runs (the clean run and every failure run), CPU-timed rows "
                "in thread CPU time, max us / budget us (runs over); the other rows' host wall max is printed, not "
                "judged:\n");
    for (const LatencyPlan& p : latencyPlans) {
        std::printf("%-17s", p.label);
        std::size_t wallOverRows = 0;
        double wallWorst = 0.0;
        const char* wallWorstName = "-";
        for (const BudgetTally::Row& r : p.budgets.rows) {
            if (r.cpuTimed) {
                std::printf(" %s %.0f/%u (%llu)", r.name.c_str(), static_cast<double>(r.cpuMax) / 1e3, r.budgetUs,
                            static_cast<unsigned long long>(r.cpuOver));
            } else {
                wallOverRows += r.wallOver > 0 ? 1U : 0U;
                const double share = static_cast<double>(r.hostMax) / (1e3 * r.budgetUs);
                if (share > wallWorst) {
                    wallWorst = share;
                    wallWorstName = r.name.c_str();
                }
            }
        }
        std::printf(" | others: worst wall max %.0f %% of its budget (%s), %zu rows ever over\n", 100.0 * wallWorst,
                    wallWorstName, wallOverRows);
    }
    for (const LatencyPlan& p : latencyPlans) {
        if (!p.targeted) {
            continue;
        }
        ok = targets.check(!p.budgets.rows.empty() && p.budgets.cpuOver() == 0);
        std::printf("TARGET every CPU-timed task (the sliced planners, command ingest) inside its budget on every "
                    "lockstep run, %s: %llu runs over  %s\n",
                    p.label, static_cast<unsigned long long>(p.budgets.cpuOver()), ok ? "PASS" : "FAIL");
    }
    for (const LatencyPlan& p : latencyPlans) {
        const std::vector<double> total = field(p, &LatencyRun::total);
        const double worst = quantile(total, 1.0);
        if (!p.targeted) {
            std::size_t proven = 0;
            for (const LatencyRun& r : p.runs) {
                proven += r.invalid == nullptr && r.proven ? 1U : 0U;
            }
            std::printf("%s (no target): max %.0f frames over %zu of %zu runs; selection up to %.0f runs (the "
                        "selector's budget: 10), proven optimal in %zu\n",
                        p.label, worst, total.size(), p.runs.size(), quantile(field(p, &LatencyRun::selectionRuns), 1.0),
                        proven);
            continue;
        }
        ok = targets.check(total.size() == p.runs.size() && worst <= kLatencyTargetFrames);
        std::printf("TARGET executive latency from a failure report to the first regenerated dispatch, in frames, "
                    "%s: max %.0f over %zu of %zu runs (<= %.0f: 10 deliberative periods)  %s\n",
                    p.label, worst, total.size(), p.runs.size(), kLatencyTargetFrames, ok ? "PASS" : "FAIL");
    }
    return targets.finish();
}
