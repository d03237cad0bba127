// Monte Carlo campaigns of the lockstep mission (rse-montecarlo, `make
// montecarlo`, docs/montecarlo.md): one mission run per seed through the
// mission runner (runMission, the same as `make demo`), each seed varying the
// scenario's sensor noise, the placement of its hidden rocks and the times of
// its faults within the limits below. A run gives one result row (an `R` line)
// that depends only on the campaign and the seed, and one host-timing line (a
// `T` line) that does not.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim::mc {

// The result file format: kFormatVersion (results.hpp).
// What a seed varies and how (the limits below); bumped when a seed would give
// a different scenario than before, so files of two variations never merge.
constexpr int kVariationVersion = 2;   // 2: a [field] drawn afresh for each seed

// The variation limits (docs/montecarlo.md, "What a seed varies").
// Sensor noise: Scenario::seed = the run's seed (every device's noise stream,
// the drives' reports and the wheel slip).
// A generated field ([field], field_rocks.hpp): a field per seed. Its rocks
// are drawn afresh from the field's model with a seed of the run seed's own
// stream (the campaign's k, diameters and orbital resolution), cleared round
// the start and the flown goal; the site map the rover is told of is the new
// field's known rocks. The field's rocks are not moved (below).
// Hidden rocks: each rock of the file's own (not a field's) the orbital map does not show is moved by (dx, dy),
// uniform in [-kRockShiftXM, kRockShiftXM] x [-kRockShiftYM, kRockShiftYM]
// (rounded to the millimetre), drawn again (up to kRockDraws times) while the
// moved rock leaves the map or comes closer than kRockEndClearanceM to the
// rover's footprint at the start or at the goal; if no draw fits, it stays put.
constexpr double kRockShiftXM = 4.0;
constexpr double kRockShiftYM = 2.0;
constexpr double kRockEndClearanceM = 1.0;
constexpr int kRockDraws = 100;
// Faults: each scheduled fault's time is drawn uniformly in
// [max(at - kFaultWindowS, kEarliestFaultS), at + kFaultWindowS] (rounded to
// the millisecond; an interval fault's end moves with it), then the schedule
// is put back in time order.
constexpr double kFaultWindowS = 10.0;
constexpr double kEarliestFaultS = 5.0;

// Seeds FIRST..FIRST+COUNT-1 of a campaign over one mission.
struct CampaignSpec {
    MissionOptions mission;     // scenario, goal, risk bound, duration, --no-faults (parseMissionArgs)
    std::vector<std::string> missionArgs;  // the rse-demo options that made it (recorded in the C line)
    std::uint64_t firstSeed = 1;
    std::uint64_t seedCount = 200;
    std::string scenarioHash;   // FNV-1a 64 of the scenario file's bytes, hex
};

// Fills spec.mission from rse-demo's options (--scenario, --goto, --duration,
// --no-faults) and hashes the scenario file; false with *error when they are
// not valid or the file cannot be read.
bool prepareCampaign(const std::vector<std::string>& missionArgs, CampaignSpec* spec, std::string* error);

// The campaign line ("C ...") every result file of the campaign starts with:
// two files merge only when theirs are equal.
std::string campaignLine(const CampaignSpec& spec);

// A small, portable random stream (SplitMix64): the same numbers on every
// machine and library, one stream per seed and purpose.
class SeedStream {
public:
    SeedStream(std::uint64_t seed, std::uint64_t purpose);
    std::uint64_t next();
    double uniform(double lo, double hi);  // [lo, hi)

private:
    std::uint64_t state_;
};

// What a seed changed in the scenario.
struct Variation {
    std::uint64_t noiseSeed = 0;
    bool field = false;               // a [field] drawn afresh
    std::uint64_t fieldSeed = 0;      // ... with this seed (RockFieldParams::seed)
    std::vector<Vec2> rockShifts;     // per hidden rock of the file's own, in the scenario's order
    std::vector<double> faultTimesS;  // per fault, in the scenario's order (before re-sorting)
};

// Applies the seed's variation to a loaded scenario (goal: the mission's).
// Throws ScenarioError when a field drawn afresh does not fit (as loading would).
Variation varyScenario(Scenario* scenario, std::uint64_t seed, double goalX, double goalY);

// One plan the deliberative layer made, as seen from the ground side of the
// lockstep: how long the rover waited for it and how much the planner ran.
struct PlanRecord {
    double latencyS = 0.0;       // simulated time from its start event (901) to its end (902 found, 903 none, ...)
    bool lookAhead = false;      // the next horizon, planned while the rover drove (not waited for)
    std::uint32_t slices = 0;    // deliberative runs that stepped the planner for it
    double hostMs = 0.0;         // host wall time of those runs (not reproducible)
    bool found = false;
};

// One seed's run: its result row and its host-timing line (no newline).
struct SeedRun {
    std::string row;     // "R seed=... ": reproducible (same campaign and seed, same text)
    std::string timing;  // "T seed=... ": host figures
};
// out: the mission's console and summary as rse-demo prints them (nullptr:
// nothing, the campaign's way).
SeedRun runSeed(const CampaignSpec& spec, std::uint64_t seed, std::FILE* out = nullptr);

// The row written for a seed whose worker died (signal or exit status) before
// it gave one.
std::string crashedRow(std::uint64_t seed, const std::string& why);

}  // namespace rse::sim::mc
