// The worker processes of rse-montecarlo (sim_stub/montecarlo/worker_pool.hpp):
// every seed answered once whatever the number of workers, a worker that dies
// mid-seed leaves a "crashed" row for that seed and is replaced, and a mission
// run in a worker gives the row it gives in-process. Host only (fork() under
// qemu-user is not what this tests).
#include <cstdint>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/montecarlo/worker_pool.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim::mc;

namespace {

// A stand-in for a mission: the row names the seed and the worker's pid.
SeedRun fake(std::uint64_t seed) {
    Row r;
    r.seed = seed;
    r.outcome = "goal_reached";
    r.plans = static_cast<std::uint32_t>(seed * 3);
    return SeedRun{formatRow(r), "T seed=" + std::to_string(seed) + " wall_s=0 cpu_s=0 plan_host_ms=-"};
}

std::vector<std::uint64_t> range(std::uint64_t first, std::uint64_t count) {
    std::vector<std::uint64_t> v;
    for (std::uint64_t s = first; s < first + count; ++s) {
        v.push_back(s);
    }
    return v;
}

}  // namespace

TEST_GROUP(WorkerPool) {
    std::map<std::uint64_t, SeedRun> got;
    std::string error;
    std::size_t answers = 0;
    std::function<void(std::uint64_t, const SeedRun&)> collect = [this](std::uint64_t seed, const SeedRun& r) {
        got[seed] = r;
        ++answers;
    };
};

TEST(WorkerPool, EverySeedIsAnsweredOnceWhateverTheWorkers) {
    for (int jobs : {1, 2, 3, 40}) {
        got.clear();
        answers = 0;
        CHECK_TRUE(runOnWorkers(range(100, 25), jobs, fake, collect, &error));
        LONGS_EQUAL(25, answers);
        LONGS_EQUAL(25, got.size());
        for (std::uint64_t s = 100; s < 125; ++s) {
            STRCMP_EQUAL(fake(s).row.c_str(), got[s].row.c_str());
            STRCMP_EQUAL(fake(s).timing.c_str(), got[s].timing.c_str());
        }
    }
    got.clear();
    CHECK_TRUE(runOnWorkers({}, 2, fake, collect, &error));
    LONGS_EQUAL(0, got.size());
}

TEST(WorkerPool, AWorkerThatDiesLeavesACrashedRowAndIsReplaced) {
    const auto dies = [](std::uint64_t seed) {
        if (seed == 7) {
            std::abort();
        }
        if (seed == 9) {
            _Exit(5);
        }
        return fake(seed);
    };
    CHECK_TRUE(runOnWorkers(range(1, 12), 2, dies, collect, &error));
    LONGS_EQUAL(12, got.size());
    Row r;
    CHECK_TRUE(parseRow(got[7].row, &r, &error));
    STRCMP_EQUAL("crashed", r.outcome.c_str());
    STRCMP_EQUAL("signal_6", r.reason.c_str());
    CHECK_TRUE(parseRow(got[9].row, &r, &error));
    STRCMP_EQUAL("exit_5", r.reason.c_str());
    STRCMP_EQUAL("", got[7].timing.c_str());
    STRCMP_EQUAL(fake(12).row.c_str(), got[12].row.c_str());  // the seeds after the deaths ran
}

TEST(WorkerPool, AMissionInAWorkerGivesTheRowItGivesInProcess) {
    CampaignSpec spec;
    CHECK_TRUE(prepareCampaign({}, &spec, &error));
    const auto mission = [&spec](std::uint64_t seed) { return runSeed(spec, seed); };
    CHECK_TRUE(runOnWorkers({11}, 1, mission, collect, &error));
    STRCMP_EQUAL(runSeed(spec, 11).row.c_str(), got[11].row.c_str());
}
