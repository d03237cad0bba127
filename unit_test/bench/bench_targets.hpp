// A benchmark's targets and its exit status (unit_test/bench/run_benches.sh,
// make bench-check): each target's verdict goes through check(); finish()
// prints how many were checked and missed and gives the exit status, 0 when
// every target was met and kExitTargetMissed (3) when one was missed. Other
// non-zero statuses stay what they were: 1 setup failed, 2 bad command line.
//
// RSE_BENCH_FORCE_MISS=1 in the environment turns every verdict into a miss
// (printed as such): a rehearsal of a missed target, to see make bench-check
// fail without waiting for a slow machine.
#pragma once

#include <cstdio>
#include <cstdlib>
#include <cstring>

namespace rse::bench {

constexpr int kExitTargetMissed = 3;

class Targets {
public:
    Targets() {
        const char* force = std::getenv("RSE_BENCH_FORCE_MISS");
        forceMiss_ = force != nullptr && std::strcmp(force, "") != 0 && std::strcmp(force, "0") != 0;
    }

    // Records one target's verdict; returns it (false when a miss is forced),
    // so the bench prints what is counted.
    bool check(bool met) {
        ++checked_;
        const bool verdict = met && !forceMiss_;
        missed_ += verdict ? 0U : 1U;
        return verdict;
    }

    unsigned checked() const { return checked_; }
    unsigned missed() const { return missed_; }

    // The closing line and the exit status for main().
    int finish() const {
        std::printf("targets: %u checked, %u missed%s\n", checked_, missed_,
                    forceMiss_ ? " (every miss forced by RSE_BENCH_FORCE_MISS)" : "");
        std::fflush(stdout);
        return missed_ == 0 ? 0 : kExitTargetMissed;
    }

private:
    unsigned checked_ = 0;
    unsigned missed_ = 0;
    bool forceMiss_ = false;
};

}  // namespace rse::bench
