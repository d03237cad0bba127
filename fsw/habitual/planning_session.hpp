// A planning session of the habitual task: the planning runs for one leg (or
// one replan of it) until a path is found or the repairs run out. This part
// owns the planner and its map and answers "what path from here"; the task
// judges the path (candidate_evaluator.hpp) and decides what to send.
//
// Planning run: if the straight segment to the goal is free it is the shortest
// path and is taken without sampling; otherwise RRT* (rrt_star.hpp) from the
// estimated position, at most kRrtIterationsPerRun iterations per task run and
// HABITUAL.rrt_iterations in all (a local replan - any session not started by a
// new leg, and every repair run - at most HABITUAL.replan_budget_ms x
// kRrtIterationsPerMs of them), stopping early once the cost is within 1 % of
// the straight-line distance; then line-of-sight shortcutting, the exact goal
// appended when the path ends within the goal tolerance, the path cut where it
// first comes within stopShortM() of a goal region's point (path_shortcut.hpp
// cutPathAtDisc), at most kMaxTrajectoryPoints points and free on the check
// map of the moment (sightings may have come in while RRT* ran on its frozen
// map); else it counts as no path.
//
// Margins: plans keep kPlanMarginM more than the footprint from every obstacle:
// pure pursuit cuts corners, and a remembered disc grows as more of its
// obstacle comes into view; without it a fresh plan grazing a disc is "blocked"
// again by the next sighting. For a run whose start or goal lies inside it the
// margin is first taken off only the seen hazards they lie in (MapRelief), then
// halved, and dropped (bare footprint) only if they lie inside that too; it is
// dropped for the runs after one that found no path with it.
//
// Backing out: a run whose start lies inside a seen hazard's disc grown by the
// footprint, or off the site, first backs out (escape_search.hpp) and plans
// again from there; at most kMaxEscapesPerLeg per leg, then RRT* refuses the
// start and the run finds no path.
//
// Time bound per run: at most kRrtIterationsPerRun RRT* iterations, or one plan
// completion (shortcutting at most kMaxRawPathPoints points), plus two map
// builds. No heap: the planner (about 1 MB), its map and the raw path are
// members. Events: 818 (RRT* refused the query, throttled); 817 through the
// hazard memory.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/hazard_memory.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/rrt_star.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// RRT* iterations per 10 Hz run. Measured on the development host (x86_64, -O2)
// on the 35 m x 20 m site with 16 polygons and 32 discs, step 1.5 m, k cap 12:
// 0.7-0.9 ms per 1000 iterations up to 1000 nodes, 0.9-1.3 ms near 7000 nodes,
// so a run stays within about 2 ms (docs/habitual.md, "Time per run"); the
// default 2000 iterations take two runs.
constexpr std::uint32_t kRrtIterationsPerRun = 1000;
// RRT* iterations per millisecond of HABITUAL.replan_budget_ms: the slowest of
// the figures above (1.3 ms per 1000 near 7000 nodes), rounded down, so a
// replan of N ms stays within about N ms on the development host. Recalibrate
// on the flight computer.
constexpr std::uint32_t kRrtIterationsPerMs = 750;
// Raw RRT* path points taken (a path needing more counts as no path). Bounds the
// shortcutting work at one plan completion: < kMaxRawPathPoints^2 / 2 checks.
constexpr std::size_t kMaxRawPathPoints = 128;
// Extra clearance planned beyond the footprint (see the file comment): about the
// corner cutting of pure pursuit with the follower table's 0.8 m look-ahead.
constexpr double kPlanMarginM = 0.25;
// Anytime early stop: the cost is within this factor of the straight line.
constexpr double kEarlyStopCostRatio = 1.01;
// Before planning the rover must be at rest (estimated |v| and |w| below these),
// or kMaxRestWaitRuns must have passed since the stop was sent.
constexpr double kAtRestSpeedMS = 0.02;
constexpr double kAtRestYawRateRadS = 0.02;
constexpr std::uint32_t kMaxRestWaitRuns = 30;
// Back-outs (escape_search.hpp) per leg.
constexpr std::uint32_t kMaxEscapesPerLeg = 3;

// Why a planning session started.
enum class PlanTrigger : std::uint8_t {
    kNewLeg = 0,
    kPathBlocked = 1,   // a remembered hazard blocks the remaining path
    kEnergy = 2,        // new power factors: the remaining path's energy is violated
    kCannotFollow = 3,  // the follower gave up
};

// "new leg", "path blocked", ...: the words of the events.
const char* triggerName(PlanTrigger trigger);

struct PlannerQueryStats {
    std::uint32_t iterations = 0;     // RRT* iterations of the last planning run (0: straight line)
    std::size_t nodes = 0;
    std::uint32_t taskRuns = 0;       // task runs it spanned
    double rawCostM = 0.0;            // RRT* best cost (or the straight line); +inf if none
    double lengthM = 0.0;             // after shortcutting (0 if no path)
    std::size_t points = 0;           // trajectory points (0 if no path)
    std::uint8_t attempt = 0;         // 0: first run of the session, n: n-th repair
    bool straightLine = false;        // the straight segment was free: no sampling
    bool earlyStop = false;           // stopped within kEarlyStopCostRatio of the straight line
    bool poolFull = false;
    bool marginDropped = false;       // planned at the bare footprint (see the file comment)
};

// How near the leg's point the rover must stop: max(HABITUAL.goal_tolerance_m,
// the leg's arriveWithinM).
double legArrivalM(const tables::HabitualTable& habitual, const msg::LegCommandMsg& leg);
// How far short of the leg's point a trajectory ends: legArrivalM() less the
// table's tolerance (a region is reached to the tolerance as a point is: the
// trajectory ends that deep inside it); 0 for a point leg.
double legStopShortM(const tables::HabitualTable& habitual, const msg::LegCommandMsg& leg);

enum class PlanStep : std::uint8_t {
    kQuerying = 0,  // RRT* runs on: the next run goes on with it
    kEscape = 1,    // back out to escapeExit() first (counted in escapesThisLeg())
    kFinished = 2,  // the run is over: path()[0..pathCount()) (pathCount() < 2: no path)
};

struct SessionCounters {
    std::uint32_t planningRuns = 0;    // planning runs completed (queries and straight lines)
    std::uint32_t noPathRuns = 0;      // planning runs without a usable path
    std::uint32_t plannerRefused = 0;  // RRT* refused the query
    std::uint32_t escapes = 0;         // back-outs of a seen hazard's footprint or onto the site
};

class PlanningSession {
public:
    PlanningSession(HazardMemory& memory, core::EventLog& events, const tables::HabitualTable& habitual,
                    const tables::CoarseMapTable& coarse, const tables::RoverGeometryTable& geometry)
        : memory_(memory), events_(events), habitual_(habitual), coarse_(coarse), geometry_(geometry) {}

    // A new leg: its back-outs start again.
    void beginLeg() { escapesThisLeg_ = 0; }
    // A session: repairs from firstAttempt up to HABITUAL.repair_attempts,
    // the margin allowed again, the rest wait restarted.
    void begin(PlanTrigger trigger, std::uint8_t firstAttempt);
    // Drops a running query (a hold, a cancel, a fail-up): the next run starts afresh.
    void stopQuery() { queryActive_ = false; }
    bool querying() const { return queryActive_; }

    // The rover still moving and not yet waited kMaxRestWaitRuns for.
    bool settling(const msg::PoseEstimateMsg& pose) const;
    void waitForRest() { ++restWaitRuns_; }
    void restartRestWait() { restWaitRuns_ = 0; }

    // A planning run from pose towards the leg's point: kQuerying (call
    // iterate() in this run too), kEscape or kFinished.
    PlanStep start(const msg::LegCommandMsg& leg, const msg::PoseEstimateMsg& pose);
    // One slice of RRT* (at most kRrtIterationsPerRun): kQuerying or kFinished.
    PlanStep iterate(const msg::LegCommandMsg& leg);

    const geometry::Point2* path() const { return rawPath_; }
    std::size_t pathCount() const { return pathCount_; }
    geometry::Point2 queryStart() const { return queryStart_; }
    double queryHeading() const { return queryHeading_; }
    geometry::Point2 escapeExit() const { return escapeExit_; }
    bool escapeOffSite() const { return escapeOffSite_; }
    std::uint32_t escapesThisLeg() const { return escapesThisLeg_; }

    PlanTrigger trigger() const { return trigger_; }
    std::uint8_t attempt() const { return attempt_; }
    std::uint8_t lastAttempt() const { return lastAttempt_; }
    bool repairLeft() const { return attempt_ < lastAttempt_; }
    // The next run is a repair (a new seed).
    void nextAttempt() { ++attempt_; }
    // RRT* iterations the planning run may take (see the file comment).
    std::uint32_t queryBudget() const;

    const PlannerQueryStats& lastQuery() const { return lastQuery_; }
    const RrtStar& planner() const { return rrt_; }
    const LocalMap& planMap() const { return planMap_; }
    const SessionCounters& counters() const { return counters_; }

private:
    double footprintM() const;
    // planMap_ for a run from queryStart_ to goal with as much margin as the
    // start and goal allow (see the file comment). Whether the map is usable.
    bool buildPlanMap(const msg::LegCommandMsg& leg, geometry::Point2 goal, double footprint);
    // A back-out is needed and found: escapeExit_ set.
    bool needsEscape(double footprint);
    PlanStep startRrt(const msg::LegCommandMsg& leg, geometry::Point2 goal);
    PlanStep finishQuery(const msg::LegCommandMsg& leg);
    // rawPath_[0..count) is the run's raw path (count < 2: none): shortcut,
    // complete, cut and check it.
    PlanStep completePlan(std::size_t count, const msg::LegCommandMsg& leg);

    HazardMemory& memory_;
    core::EventLog& events_;
    const tables::HabitualTable& habitual_;
    const tables::CoarseMapTable& coarse_;
    const tables::RoverGeometryTable& geometry_;

    PlanTrigger trigger_ = PlanTrigger::kNewLeg;
    std::uint8_t attempt_ = 0;
    std::uint8_t lastAttempt_ = 0;
    bool queryActive_ = false;
    bool bareFootprint_ = false;  // plan without kPlanMarginM for the rest of the session
    std::uint32_t restWaitRuns_ = 0;
    std::uint32_t queryCount_ = 0;
    std::uint32_t escapesThisLeg_ = 0;
    geometry::Point2 queryStart_{0.0, 0.0};
    double queryHeading_ = 0.0;
    geometry::Point2 escapeExit_{0.0, 0.0};
    bool escapeOffSite_ = false;
    std::size_t pathCount_ = 0;
    PlannerQueryStats lastQuery_{};
    SessionCounters counters_{};

    // Large members last.
    geometry::Point2 rawPath_[kMaxRawPathPoints] = {};
    LocalMap planMap_;
    RrtStar rrt_;
};

}  // namespace rse::habitual
