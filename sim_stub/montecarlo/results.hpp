// Monte Carlo result files and the campaign table (docs/montecarlo.md).
//
// A result file is text, one record a line, fields `key=value` separated by
// single spaces (no value holds a space):
//   # ...                 comment
//   C format=3 ...        the campaign (identical in every file of a campaign)
//   B first=.. count=..   the block of seeds this file holds, and where it ran
//   R seed=.. ...         one seed's result row: the same for the same campaign and seed
//   T seed=.. ...         that seed's host figures (wall and CPU time, planner time)
//   E rows=N              the end: a file without it (or with another count) was cut short
// The table is computed from R lines only, so a campaign run on one machine
// and the same seeds run in blocks anywhere and merged give the same table,
// byte for byte; the T lines give the host-timing section printed after it.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace rse::sim::mc {

// The result file format (docs/montecarlo.md, "Result files"); bumped when a
// line changes meaning: 2, rows carry field= (a generated field's seed); 3,
// rows carry look_aheads= and plan_s lists only the plans the rover waited
// for (not the next horizon planned while it drove).
constexpr int kFormatVersion = 3;

// One seed's result (an R line).
struct Row {
    std::uint64_t seed = 0;
    std::string outcome = "setup_failed";  // goal_reached, called_home, timed_out, setup_failed, crashed
    std::string reason = "-";      // the call home's reason (called_home), the worker's end (crashed), else "-"
    double outcomeS = 0.0;         // simulated time of the outcome (timed out: the end)
    double distanceM = 0.0;        // driven (truth)
    double energyWh = 0.0;         // drawn from the battery (truth)
    double goalDistanceM = 0.0;    // final position to the goal (truth)
    double clearanceM = 0.0;       // least clearance to any rock, hidden ones included (truth)
    std::uint32_t collisions = 0;  // contacts (truth)
    std::uint32_t plans = 0;       // plans made (PLAN telemetry)
    std::uint32_t legsSent = 0;
    std::uint32_t legsAchieved = 0;
    std::uint32_t failUps = 0;
    std::uint32_t replans = 0;
    std::uint32_t boundRelaxations = 0;
    std::uint32_t riskRelaxations = 0;
    std::uint32_t callHomes = 0;
    std::uint32_t habitualReplans = 0;
    std::uint32_t lookAheads = 0;    // site mode: next horizons planned while driving (restarts too), not in plan_s
    double riskBound = 0.0;        // the operator's
    double riskInForce = 0.0;      // after relaxations
    double riskUsed = 0.0;         // by the last plan
    std::vector<double> planLatencyS;          // per plan, simulated s (PlanRecord)
    std::vector<std::uint32_t> planSlices;     // per plan
    std::vector<std::uint8_t> planFound;       // per plan, 1 found / 0 none
    std::string field = "-";       // the generated field's seed (a field per seed), "-" for none
    std::string rocks = "-";       // hidden rocks' shifts "dx,dy;dx,dy" (m), "-" for none
    std::string faults = "-";      // the faults' drawn times "t1,t2" (s, scenario order), "-" for none

    // Every plan within the operator's risk bound: no risk relaxation.
    bool withinRiskBound() const { return riskRelaxations == 0 && riskInForce <= riskBound; }
};

// One seed's host figures (a T line).
struct Timing {
    std::uint64_t seed = 0;
    double wallS = 0.0;                 // the mission's wall time
    double cpuS = 0.0;                  // the worker's CPU time for it
    std::vector<double> planHostMs;     // per plan: host wall time of the planner's runs
};

std::string formatRow(const Row& row);
bool parseRow(const std::string& line, Row* row, std::string* error);
std::string formatTiming(const Timing& timing);
bool parseTiming(const std::string& line, Timing* timing, std::string* error);

// "B ..." for a block of seeds; task is the array task (-1: a local run).
std::string blockLine(std::uint64_t first, std::uint64_t count, long task, int jobs);

// What a campaign's files hold, merged.
struct ResultSet {
    std::string campaign;                   // the C line ("" before the first file)
    std::map<std::string, std::string> fields;  // its key=value fields
    std::uint64_t firstSeed = 0;
    std::uint64_t seedCount = 0;
    std::map<std::uint64_t, Row> rows;
    std::map<std::uint64_t, std::string> rowText;  // as read, for the duplicate check
    std::map<std::uint64_t, Timing> timings;
    std::size_t files = 0;
};

// Adds one result file (whole, checked: its C line equals the set's, its E
// line counts its R lines, a seed twice only with the same row).
bool addResultFile(const std::string& path, ResultSet* set, std::string* error);
// Adds the lines of a result file from memory (path names it in errors).
bool addResultText(const std::string& text, const std::string& path, ResultSet* set, std::string* error);
// The campaign's seeds no file held.
std::vector<std::uint64_t> missingSeeds(const ResultSet& set);
// Seeds outside the campaign's range.
std::vector<std::uint64_t> strangerSeeds(const ResultSet& set);

// Writes a result file atomically (a temporary beside it, then renamed).
bool writeResultFile(const std::string& path, const std::string& campaign, const std::string& block,
                     const std::vector<std::pair<std::string, std::string>>& rowAndTiming, std::string* error);

// The table: from R lines only, byte for byte the same for the same rows.
// It ends with the checks (CHECK ... PASS/FAIL).
std::string formatTable(const ResultSet& set);
// How many checks of the table failed (0: all pass).
int failedChecks(const ResultSet& set);
// The host-timing section (T lines): planner and mission times on the hosts that ran them.
std::string formatHostTiming(const ResultSet& set);

// Nearest-rank percentile (q in (0, 1]) of a sorted, non-empty vector.
double percentile(const std::vector<double>& sorted, double q);

}  // namespace rse::sim::mc
