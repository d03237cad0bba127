// Making the plan of the goal in hand (docs/deliberative.md, "Flight planner"
// and "The deliberative task"): the map problem from the start and the goal
// (map_problem.hpp: the coarse map, the seen hazards, the drives' noise), the
// chance-constrained planner sliced over the task's runs, the wide search
// before the risk is relaxed, and the plan's PLAN_PATH.
//
// - The start: where the ReplanPolicy says (the replan request's position, or
//   the pose); a start off the planning site (the site shrunk by the
//   footprint: an off-map rover, or one pushed against the edge) is planned
//   from the nearest point kReentryInsetM inside it (event 928); the habitual
//   layer drives the rover there on the first leg.
// - The motor loss in the state estimate: drives declared failed (or unknown)
//   for PLANNER.failed_drive_confirm_s are planned with the motion noise x
//   PLANNER.failed_drive_noise_factor (event 990 when that set changes).
// - The seed: the last plan found, when it went to the same goal among the
//   same obstacles (a replan, or the operator's bound changed): the planner
//   re-solves its faces at this problem's margins and keeps it only if it verifies.
// - Time bound per run: at most kMaxUnitsPerRun planner units, stopping after
//   the unit that takes the run's planner work past kSliceWork (one unit does
//   at most CcPlanner::kMaxUnitWork), so a run costs at most kSliceWork +
//   kMaxUnitWork work units; one planner run is bounded by PLANNER.node_budget
//   LPs and PLANNER.time_budget_ms x kWorkKUnitsPerMs thousand work units, and
//   a plan by 1 + kMaxWholeMapRounds planner runs (the whole-map rounds, each
//   with its own budget, and each check at most a unit per candidate), or 2
//   runs with the wide search where nothing is left out.
// - The whole map: when the map and the seen hazards hold more obstacles than
//   the problem, the planner plans to (1 - kLeftOutShare) Delta and each plan
//   it finds is checked against every obstacle (whole_map_check.hpp) before it
//   is taken: the left-out ones' risk is added to its certified risk when it
//   fits in kLeftOutShare Delta; else the obstacles that matter are forced into
//   the problem and it is planned again (event 991), at most
//   kMaxWholeMapRounds times, and then no plan is taken (event 992): a plan
//   whose risk against the whole map is not certified is never sent.
// - No plan at the even split (kOptimised allocation, obstacles in the way):
//   the same problem once more with the search at kWideSearchScale x Boole's
//   budget, its plan certified within the risk in force (event 929).
//
// Owns the planner, the problem, the plan and the last plan (about 500 KB:
// the task is static). Publishes PlanPathMsg (through the Publisher). Events
// 901, 902, 903, 913, 914, 928, 929, 990, 991, 992.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/deliberative/publisher.hpp"
#include "fsw/deliberative/whole_map_check.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::deliberative {

// Planner work per run and per millisecond of PLANNER.time_budget_ms, in the
// planner's work units (CcPlanner::work()): 0.45 - 0.9 ns per unit on the
// development host, so 1000 thousand units is 0.45 - 0.9 ms there and a slice
// of 2.5 M units 1.1 - 2.3 ms. Recalibrate on the flight computer.
constexpr std::uint32_t kWorkKUnitsPerMs = 1000;
constexpr std::uint64_t kSliceWork = 2500000;
// Every planner unit is at most CcPlanner::kMaxUnitWork, so kSliceWork bounds
// a run; this cap only bounds the loop when units do little (an LP slice of
// 16 pivots at small N is ~20 k units): with 64 a plan of such units took
// several times the runs its work needs.
constexpr std::uint32_t kMaxUnitsPerRun = 1024;
// Before relaxing: the same problem once more with the planner's search at
// this many times Boole's budget, its plan certified within the risk in force
// (CcPlannerParams::searchRiskScale; optimised allocation only): a narrow
// passage the even split refuses may be certified within the bound.
constexpr double kWideSearchScale = 8.0;
// How far inside the planning site (the site shrunk by the footprint) the
// re-entry point of an off-site start lies: the planner's start must be on the
// site, and a point on its very edge would sit at the wall of the habitual
// layer's planning margin.
constexpr double kReentryInsetM = 0.3;

// Plans of one goal planned again with obstacles the whole-map check forced
// in: each round forces at least one more left-out obstacle (else the plan is
// refused at once), so kMaxPlanObstacles rounds would hold any forced set;
// four keep a plan within five planner runs' time.
constexpr std::uint32_t kMaxWholeMapRounds = 4;

// What a plan is asked for.
struct PlanStart {
    double xM = 0.0, yM = 0.0;    // the start's mean
    double cov[4] = {};           // its (x, y) covariance, row major
    double goalX = 0.0, goalY = 0.0;
    std::size_t goalNumber = 0;   // as the operator numbers it (events)
    double riskBound = 0.0;       // the risk in force
    std::uint8_t failedDrives = 0;   // confirmed failed or unknown (bit per wheel)
    double meanPowerFactor = 1.0;    // the legs' (event 990)
    const msg::KnownHazardsMsg* hazards = nullptr;  // seen hazards
    SiteCorridor site{};          // site mode (map_problem.hpp) when site.map is set
};

struct PlanCounters {
    std::uint32_t plansStarted = 0;
    std::uint32_t plansFound = 0;
    std::uint32_t noPlans = 0;
    std::uint32_t problemsRefused = 0;
    std::uint32_t obstaclesDropped = 0;  // plans that left coarse-map obstacles out
    std::uint32_t planningRuns = 0;      // task runs that stepped the planner
    std::uint32_t reentryPlans = 0;      // plans started from the re-entry point of an off-site start
    std::uint32_t seededPlans = 0;       // plans seeded with the last plan's faces
    std::uint32_t budgetPlans = 0;       // plans found but not proven optimal
    std::uint32_t wideSearches = 0;      // no plan, so the same problem searched at kWideSearchScale
    std::uint32_t wideSearchPlans = 0;   // ... which found a plan certified within the risk in force
    std::uint32_t failedDriveModels = 0; // plans started with a new set of drives taken as failed (event 990)
    std::uint32_t wholeMapChecks = 0;    // plans checked against the obstacles their problem left out
    std::uint32_t wholeMapReplans = 0;   // ... planned again with obstacles forced in (event 991)
    std::uint32_t wholeMapRefusals = 0;  // ... and not taken: left-out risk beyond kLeftOutShare (event 992)
    std::uint32_t siteRocksAdded = 0;    // site mode: rocks near a plan made candidates before its check
    std::uint32_t siteCrowdedRefusals = 0;  // ... plans not taken: the rocks near them did not fit, a keep-out zone near, or the map changed (event 992)
    std::uint64_t maxRunWork = 0;        // most planner work one run did (work units)
    std::uint32_t maxRunUnits = 0;
};

class PlanMaker {
public:
    PlanMaker(core::EventLog& events, const tables::TableService& tables, Publisher& out)
        : events_(events), tables_(tables), out_(out) {}

    // Builds the problem and starts the planner (events 901, 928, 914, 990).
    // False when the problem is refused (event 913): *refusal says why.
    bool start(const PlanStart& request, const char** refusal);
    // One run's slice of planning and of the whole-map check; true when both
    // have finished.
    bool step();
    // Takes the finished plan; true when it has a path certified against the
    // whole map (it is then the seed of the next plan to the same goal among
    // the same obstacles).
    bool finish();
    // The plan is one the task made (counted in PLAN's plansMade): PLAN_PATH
    // numbered with the count.
    void countPlanFound(core::TimeNs now);
    // Event 902 for a plan cut into legCount legs, with its gap.
    void reportPlanFound(std::size_t legCount);
    // No plan: the wide search of the same problem, if not done yet and it
    // applies; true when it has started (event 929).
    bool startWideSearch();
    // No plan for the goal numbered goalNumber (event 903).
    void reportNoPlan(std::size_t goalNumber);
    // A new goal list: PLAN shows "no plan" until its goal is planned.
    void forgetPlan();

    const CcPlanner& planner() const { return planner_; }
    const CcProblem& problem() const { return problem_; }
    const CcPlan& plan() const { return plan_; }
    // The plan step() finished with has a path (finish() would return true).
    bool hasCandidatePath() const {
        return phase_ == Phase::kDone && (candidate_.status == CcStatus::kOptimal || candidate_.status == CcStatus::kFeasible);
    }
    // The risk in force the plan was asked for (the problem's own bound is
    // less by the left-out share when obstacles are left out).
    double riskBound() const { return riskBound_; }
    // Site mode: the bound of the rocks far from the plan (whole_map_check.hpp),
    // part of leftOutRisk().
    const FarRockBound& farRocks() const { return far_; }
    // Every candidate of the plan's problem: the ones it holds and the ones
    // the whole-map check bounded (site mode: with the rocks near the plan).
    const MapObstacles& candidates() const { return obstacles_; }
    // Obstacles the plan's problem left out, and their share of its risk.
    std::size_t obstaclesLeftOut() const { return leftOutCount_; }
    double leftOutRisk() const { return leftOutRisk_; }
    double planGap() const { return planGap_; }
    bool fromReentry() const { return fromReentry_; }
    std::uint32_t slices() const { return slices_; }
    const PlanCounters& counters() const { return counters_; }

private:
    // The last plan found and what it was for: the seed of the next plan to
    // the same goal among the same obstacles (CcPlanner::setSeedHint).
    struct LastPlan {
        bool valid = false;
        double goalX = 0.0;
        double goalY = 0.0;
        std::uint8_t obstacleCount = 0;
        std::uint8_t obstacleIds[kMaxPlanObstacles] = {};
        CcPlan plan{};
    };

    enum class Phase : std::uint8_t { kPlanning, kChecking, kReplanning, kDone };

    void planFromReentry(PlanRequest* request);
    void stepUnit();
    void onPlannerFinished();
    void onCheckDone();
    void refuseCandidate(double leftOutRisk);
    bool topUpSiteRocks();
    void replanWithForced();
    std::uint64_t work() const { return work_; }
    bool buildProblem(const PlanStart& start, const PlanRequest& request, MapProblemReport* report,
                      const char** refusal);
    void seedFromLastPlan();
    void noteFailedDrives(const PlanStart& start);
    CcPlannerParams plannerParams() const;

    core::EventLog& events_;
    const tables::TableService& tables_;
    Publisher& out_;
    CcProblem problem_{};
    MapObstacles obstacles_{};   // every candidate of the problem (about 20 KB)
    SiteCorridor site_{};        // site mode when site_.map is set
    std::uint32_t siteRevision_ = 0;  // the site map's revision the plan was started on
    FarRockBound far_{};
    WholeMapCheck check_{};
    Phase phase_ = Phase::kDone;
    std::uint64_t work_ = 0;         // work units of every unit stepped (planner, check, restarts)
    std::uint32_t wholeMapRounds_ = 0;
    double riskBound_ = 0.0;
    std::size_t leftOutCount_ = 0;
    double leftOutRisk_ = 0.0;
    LastPlan last_{};
    double planGap_ = 1.0;       // PlanStatusMsg.planGap of plan_
    bool seededPlan_ = false;    // the plan under way was seeded with last_
    bool wideSearch_ = false;    // the plan under way is the wide search (kWideSearchScale)
    bool refusedByWholeMap_ = false;  // this goal's plan was refused by the whole-map check (no wide search)
    bool fromReentry_ = false;   // the plan being made starts at the re-entry point, not at the rover
    // Drives the last plan started with took as failed (bit per wheel): event 990 when it changes.
    std::uint8_t plannedFailedMask_ = 0;
    std::uint32_t slices_ = 0;   // runs the current plan has taken
    CcPlan candidate_{};  // the planner's plan under the whole-map check; plan_ once finished
    CcPlan plan_{};
    PlanCounters counters_{};
    CcPlanner planner_;
};

}  // namespace rse::deliberative
