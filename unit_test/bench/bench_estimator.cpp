// Estimator benchmark (make bench): the flight software and the simulator in
// lockstep over seeded drives, scored against simulator truth (read here only).
//
//   1. Pose EKF: 100 five-minute drives of sim_stub/scenarios/estimator_drive.toml
//      (seeds 1..100): position and heading RMSE, and the NEES consistency check —
//      at each 1 Hz sample time the NEES averaged over the runs must lie within
//      the two-sided 95 % chi-square interval for 3 x runs degrees of freedom.
//   2. Drive mode estimation: the same nominal runs count false alarms (any
//      wheel declared other than nominal, any health fault raised); 100 more
//      runs inject a motor degradation then a failure and time injection ->
//      declared mode.
// The drives keep to the flight software's site (COARSE_MAP bounds; the
// simulated world is larger): off it, fault 46 (off the map) is rightly raised.
// Figures are recorded in docs/performance.md.
//
// Usage: bench_estimator [runs] [seconds]   (defaults 100, 300)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <ctime>
#include <vector>

#include "unit_test/system/lockstep/estimator_runs.hpp"
#include "unit_test/bench/bench_targets.hpp"

namespace {

using rse::test::chiSquareQuantile;
using rse::test::kZ975;

double percentile(std::vector<double> v, double p) {
    if (v.empty()) {
        return -1.0;
    }
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(i, v.size() - 1)];
}

double seconds(const timespec& a, const timespec& b) {
    return static_cast<double>(b.tv_sec - a.tv_sec) + 1e-9 * static_cast<double>(b.tv_nsec - a.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::atoi(argv[1]) : 100;
    const double durationS = argc > 2 ? std::atof(argv[2]) : 300.0;
    if (runs < 2 || durationS < 10.0) {
        std::fprintf(stderr, "usage: bench_estimator [runs >= 2] [seconds >= 10]\n");
        return 2;
    }
    rse::bench::Targets targets;
    const rse::sim::Scenario base = rse::sim::loadScenarioFile("sim_stub/scenarios/estimator_drive.toml");
    timespec t0{};
    timespec t1{};
    clock_gettime(CLOCK_MONOTONIC, &t0);

    // ---- 1. Pose EKF over nominal drives
    std::vector<std::vector<double>> nees;
    std::vector<double> runRmse;
    double sumPos = 0.0;
    double sumHeading = 0.0;
    double worstPos = 0.0;
    double distance = 0.0;
    std::uint64_t frames = 0;
    unsigned modeAlarms = 0;
    unsigned faultAlarms = 0;
    std::uint32_t raisedById[rse::msg::fault::kCount] = {};
    double closestToEdge = INFINITY;
    unsigned siteReturns = 0;
    unsigned runsWithModeAlarm = 0;
    std::uint32_t fixesRejected = 0;
    std::size_t samples = SIZE_MAX;
    double cpuMean[3] = {};
    rse::core::TimeNs cpuMax[3] = {};
    for (int i = 0; i < runs; ++i) {
        const rse::test::NominalRun r = rse::test::runNominal(base, static_cast<std::uint64_t>(i + 1), durationS);
        if (!r.initialised || r.frames == 0) {
            std::printf("run %d: the estimator never initialised\n", i + 1);
            return 1;
        }
        nees.push_back(r.nees);
        samples = std::min(samples, r.nees.size());
        sumPos += r.sumPosErr2;
        sumHeading += r.sumHeadingErr2;
        frames += r.frames;
        runRmse.push_back(std::sqrt(r.sumPosErr2 / static_cast<double>(r.frames)));
        worstPos = std::max(worstPos, r.maxPosErr);
        distance += r.distanceM;
        modeAlarms += r.driveModeAlarms;
        runsWithModeAlarm += r.driveModeAlarms > 0 ? 1U : 0U;
        faultAlarms += r.faultsRaised;
        for (std::size_t id = 0; id < rse::msg::fault::kCount; ++id) {
            raisedById[id] += r.raisedById[id];
        }
        closestToEdge = std::min(closestToEdge, r.closestToEdgeM);
        siteReturns += r.siteReturns;
        fixesRejected += r.fixesRejected;
        for (std::size_t k = 0; k < 3; ++k) {
            cpuMean[k] += static_cast<double>(r.cpuMean[k]) / static_cast<double>(runs);
            cpuMax[k] = std::max(cpuMax[k], r.cpuMax[k]);
        }
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    const double m = static_cast<double>(runs);
    const double lo = chiSquareQuantile(3.0 * m, -kZ975) / m;
    const double hi = chiSquareQuantile(3.0 * m, kZ975) / m;
    std::size_t inside = 0;
    double meanAnees = 0.0;
    double minAnees = 1e300;
    double maxAnees = 0.0;
    for (std::size_t k = 0; k < samples; ++k) {
        double sum = 0.0;
        for (const auto& run : nees) {
            sum += run[k];
        }
        const double anees = sum / m;
        inside += (anees >= lo && anees <= hi) ? 1U : 0U;
        meanAnees += anees;
        minAnees = std::min(minAnees, anees);
        maxAnees = std::max(maxAnees, anees);
    }
    meanAnees /= static_cast<double>(samples);
    const double insideFrac = static_cast<double>(inside) / static_cast<double>(samples);
    std::printf("estimator: pose EKF over %d seeded lockstep runs of %.0f s (%s), %.0f m driven in all, %.1f s\n",
                runs, durationS, base.source.c_str(), distance, seconds(t0, t1));
    std::printf("  position RMSE %.4f m over every frame (per run: median %.4f, worst %.4f); largest error %.4f m\n",
                std::sqrt(sumPos / static_cast<double>(frames)), percentile(runRmse, 0.5), percentile(runRmse, 1.0),
                worstPos);
    std::printf("  heading RMSE %.5f rad\n", std::sqrt(sumHeading / static_cast<double>(frames)));
    std::printf("  NEES (x, y, heading), averaged over the %d runs at each of %zu 1 Hz samples:\n", runs, samples);
    std::printf("    95 %% chi-square interval for %d dof / %d: [%.3f, %.3f]\n", 3 * runs, runs, lo, hi);
    std::printf("    mean %.3f, min %.3f, max %.3f; %zu of %zu samples (%.1f %%) inside\n", meanAnees, minAnees,
                maxAnees, inside, samples, 100.0 * insideFrac);
    const bool consistent = meanAnees >= lo && meanAnees <= hi && insideFrac >= 0.90;
    std::printf("    consistent (mean inside, >= 90 %% of samples inside): %s\n", consistent ? "yes" : "NO");
    std::printf("  the drives kept to the flight site (COARSE_MAP): turned back from its edge %u times; the rover "
                "came within %.2f m of the edge (truth; negative: off the site)\n", siteReturns, closestToEdge);
    std::printf("  position fixes refused by the gate: %u (no outliers injected; 0.1 %% expected of ~%d fixes)\n",
                static_cast<unsigned>(fixesRejected), static_cast<int>(m * durationS));
    for (std::size_t k = 0; k < 3; ++k) {
        std::printf("  task %-12s host CPU per run: mean %.2f us, max %.1f us\n", rse::test::kEstimatorTaskNames[k],
                    cpuMean[k] * 1e-3, static_cast<double>(cpuMax[k]) * 1e-3);
    }

    // ---- 2. Drive mode estimation
    clock_gettime(CLOCK_MONOTONIC, &t0);
    std::vector<double> degradeLatency;
    std::vector<double> failLatency;
    unsigned missedDegrade = 0;
    unsigned missedFail = 0;
    unsigned lateDegrade = 0;
    unsigned otherAlarms = 0;
    double minFactor = 10.0;
    for (int i = 0; i < runs; ++i) {
        const rse::test::FaultRun r = rse::test::runFaulted(base, static_cast<std::uint64_t>(1000 + i));
        minFactor = std::min(minFactor, r.factor);
        if (r.degradeLatencyS < 0.0) {
            ++missedDegrade;
        } else {
            degradeLatency.push_back(r.degradeLatencyS);
            lateDegrade += r.degradedBeforeFail ? 0U : 1U;
        }
        if (r.failLatencyS < 0.0) {
            ++missedFail;
        } else {
            failLatency.push_back(r.failLatencyS);
        }
        otherAlarms += r.otherWheelAlarms;
    }
    clock_gettime(CLOCK_MONOTONIC, &t1);
    std::printf("estimator: drive mode estimation, %d fault runs (degradation x1.3-1.6 at 60-120 s, failure 30-60 s "
                "later), %.1f s\n", runs, seconds(t0, t1));
    std::printf("  degradation -> declared degraded: median %.2f s, 95th pct %.2f s, max %.2f s; missed %u; "
                "declared only after the failure %u\n", percentile(degradeLatency, 0.5),
                percentile(degradeLatency, 0.95), percentile(degradeLatency, 1.0), missedDegrade, lateDegrade);
    std::printf("  failure -> declared failed: median %.2f s, 95th pct %.2f s, max %.2f s; missed %u\n",
                percentile(failLatency, 0.5), percentile(failLatency, 0.95), percentile(failLatency, 1.0), missedFail);
    std::printf("  false alarms: nominal runs %u wheel-frames in %u runs (target 0), faults raised %u", modeAlarms,
                runsWithModeAlarm, faultAlarms);
    for (std::size_t id = 0; id < rse::msg::fault::kCount; ++id) {
        if (raisedById[id] > 0) {
            std::printf(" [fault %zu: %u]", id, static_cast<unsigned>(raisedById[id]));
        }
    }
    std::printf(" (target 0); healthy wheels of the fault runs %u wheel-frames\n", otherAlarms);
    const bool modesOk = missedDegrade == 0 && lateDegrade == 0 && missedFail == 0 && modeAlarms == 0 &&
                         otherAlarms == 0 && faultAlarms == 0;
    std::printf("  every degradation detected before its failure, no false alarm: %s\n", targets.check(modesOk) ? "yes" : "NO");
    return targets.finish();
}
