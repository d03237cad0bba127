// The habitual layer (10 Hz): the RSE behavioural policy between the
// deliberative layer's legs and the reflexive layer's trajectory follower.
//
//   in:  LegCommandMsg (a waypoint and its not-to-exceed length, energy and power),
//        PoseEstimateMsg, HazardMsg, DriveModesMsg, FollowerStatusMsg, ModeMsg,
//        MissionHoldMsg (fault protection)
//   out: TrajectoryMsg (a plan, or count 0 = stop), LegReportMsg (on every state
//        change and at 1 Hz), KnownHazardsMsg (the remembered hazard discs, when
//        they change and at 1 Hz: the deliberative layer plans round them)
//
// State machine (HabitualState, habitual_msgs.hpp):
//   any     --leg refused-----------> (unchanged; a one-off report: kIdle + kBadLeg)
//   any     --legId 0 (cancel)------> stop, kIdle
//   any     --mode left AUTONOMOUS--> stop, leg dropped, kIdle
//   any     --new leg---------------> stop, kPlanning
//   kPlanning/kRepairing: a region leg whose rover stands (at rest) within its
//           region -> kAchieved at once (below); else the leg's power bound
//           first: the drives' power at the cruise speed above it -> stop,
//           kFailedUp (kPower) at once (a new path cannot lower it); else
//           wait for a usable pose and the rover at rest, then one planning
//           run (RRT* sliced over frames); its plan is checked against the
//           constraints:
//             both hold -----------------------------> trajectory sent, kDriving
//             violated or no path, repairs left -----> kRepairing, next run (new seed)
//             violated or no path, no repairs left --> stop, kFailedUp (reason, figures)
//   kDriving: every run the hazards seen so far are put on the map:
//             remaining path blocked ----------------> stop, kRepairing (replan;
//                                                       success = minor anomaly)
//             new power factors, power now violated --> stop, kFailedUp (kPower) at once
//             new power factors, energy now violated -> stop, kRepairing (repairs only)
//             follower kCannotFollow ----------------> stop, kRepairing once per leg,
//                                                       then kFailedUp (drives held: at once)
//             follower kReached ---------------------> kAchieved
//   kFailedUp / kAchieved: wait for the next leg.
//   held (MissionHoldMsg reasons != 0, any state): stop sent once, the leg and
//           the state kept, no planning, no supervision, no fail-up; hazards are
//           still remembered. Released (reasons 0): a session in planning goes
//           on; a leg being driven waits stopped for the deliberative layer to
//           re-send it from the current pose (a new leg).
//
// A goal region (LegCommandMsg.arriveWithinM above HABITUAL.goal_tolerance_m,
// a goal's last leg): a rover at rest within the region achieves the leg at
// once, before the power check (nothing driven); otherwise the path is planned
// to the point as always (RRT*'s goal tolerance the region's radius) and cut
// where it first comes within stopShortM() of it (path_shortcut.hpp
// cutPathAtDisc): the rover stops on the way in, the goal tolerance deep
// inside the region, instead of driving to the centre.
//
// Planning run: if the straight segment to the goal is free it is the shortest
// path and is taken without sampling; otherwise RRT* (rrt_star.hpp) from the
// estimated position, at most kRrtIterationsPerRun iterations per task run and
// HABITUAL.rrt_iterations in all (a local replan - any session not started by a
// new leg, and every repair run - at most HABITUAL.replan_budget_ms x
// kRrtIterationsPerMs of them), stopping early once the cost is within 1 % of
// the straight-line distance; then line-of-sight shortcutting, the exact goal
// appended when the path ends within the goal tolerance, at most
// kMaxTrajectoryPoints points (else it counts as no path). Plans keep
// kPlanMarginM more than the footprint from every obstacle: pure pursuit cuts
// corners, and a remembered disc grows as more of its obstacle comes into view;
// without it a fresh plan grazing a disc is "blocked" again by the next
// sighting. For a run whose start or goal lies inside it the margin is halved,
// and dropped (bare footprint) only if they lie inside that too; it is dropped
// for the runs after one that found no path with it. Paths
// are checked while driving against the bare footprint. A planning run whose
// start lies inside a seen hazard's disc grown by the footprint (the disc grew
// as more of the rock came into view after the rover stopped) first backs out:
// a straight trajectory directly away from that disc's centre (or turned by up
// to 90 degrees either way when that runs towards another obstacle) to the
// first point clear of that disc by footprint + kPlanMarginM + kEscapeExtraM
// and of everything else by footprint + kPlanMarginM (kEscapeSteps of
// kEscapeStepM further out, at most kMaxEscapeM away), the way there clear of
// the mapped rocks, not checked against the disc it leaves; reached, the session plans again from
// there. A start off the site (outside the COARSE_MAP bounds: the rover slid or
// was driven off the map) backs in the same way: straight to the nearest point
// footprint + kPlanMarginM + kEscapeExtraM inside the site (or one slid along
// the edge by kEscapeStepM steps when that is blocked), at most kMaxReentryM
// away. At most kMaxEscapesPerLeg per leg; then RRT* refuses the start and the
// leg fails up (no path).
//
// Constraints (step 3 of the policy), re-evaluated for the remaining leg:
//   allowed length = (maxPathLengthM - driven length) * (1 - distance_margin_frac)
//   allowed energy = (maxEnergyJ - driven energy) * (1 - power_margin_frac)
// driven length: sum of pose displacements (each step >= kOdometryStepM, so
// pose jitter at rest adds nothing); driven energy: the power model on it with
// the power factors of the moment. Predicted energy: fsw/rover_model/power_model.hpp.
// Among failed attempts the least violating (smallest relative excess) is kept
// for the fail-up report.
//
// Hazard memory (map_builder.hpp): kept for the whole mission, oldest replaced
// when full; the local map is rebuilt from it when a planning run starts and
// whenever it changes while driving.
//
// Time bound per run: at most kRrtIterationsPerRun RRT* iterations, or one
// plan completion (shortcutting at most kMaxRawPathPoints points), plus the
// inputs (bounded by the pipe depths) and a map rebuild (16 polygons + 32 discs).
// No heap: the planner, maps and buffers are members (the object is large:
// make it static). Every loop is bounded by a constant.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/habitual/rrt_star.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_service.hpp"

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
// Pipes: poses come at 100 Hz (10 per run; 20 survive one skipped run), the rest
// at 10 Hz or on change.
constexpr std::uint16_t kPosePipeDepth = 20;
constexpr std::uint16_t kInputPipeDepth = 12;
constexpr std::uint32_t kReportPeriodRuns = 10;  // 1 Hz
// A pose older than this cannot be planned from.
constexpr core::TimeNs kPoseMaxAgeNs = 500 * core::kNsPerMs;
// Before planning the rover must be at rest (estimated |v| and |w| below these),
// or kMaxRestWaitRuns must have passed since the stop was sent.
constexpr double kAtRestSpeedMS = 0.02;
constexpr double kAtRestYawRateRadS = 0.02;
constexpr std::uint32_t kMaxRestWaitRuns = 30;
// Driven-distance and heading accumulation steps (filter pose jitter at rest).
constexpr double kOdometryStepM = 0.05;
constexpr double kOdometryStepRad = 0.05;
// Backing out of a seen hazard's footprint (see the file comment).
constexpr double kEscapeExtraM = 0.05;
constexpr double kEscapeStepM = 0.25;
constexpr std::uint32_t kEscapeSteps = 8;
constexpr double kMaxEscapeM = 3.0;
// The longest drive back onto the site. A slide or a wander off the orbital map
// is metres, not tens of metres; a pose farther off is more likely wrong than
// the rover there, and driving that far over unmapped ground on it is not a
// recovery: the leg fails up (no path) and fault protection's tries end in a
// call home.
constexpr double kMaxReentryM = 10.0;
constexpr std::uint32_t kMaxEscapesPerLeg = 3;
// Points checked along the way out against the mapped rocks (3 m / 30: 0.1 m apart).
constexpr std::uint32_t kEscapeChecks = 30;

// Why a planning session started.
enum class PlanTrigger : std::uint8_t {
    kNewLeg = 0,
    kPathBlocked = 1,   // a remembered hazard blocks the remaining path
    kEnergy = 2,        // new power factors: the remaining path's energy is violated
    kCannotFollow = 3,  // the follower gave up
};

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

struct HabitualCounters {
    std::uint32_t legsAccepted = 0;
    std::uint32_t legsRefused = 0;
    std::uint32_t legsCancelled = 0;
    std::uint32_t legsAchieved = 0;
    std::uint32_t failUps = 0;
    std::uint32_t replans = 0;          // sessions started while a leg was under way, plus every repair run
    std::uint32_t minorAnomalies = 0;   // replans that ended within the constraints
    std::uint32_t repairAttempts = 0;
    std::uint32_t planningRuns = 0;     // planning runs completed (queries and straight lines)
    std::uint32_t noPathRuns = 0;       // planning runs without a usable path
    std::uint32_t plannerRefused = 0;   // RRT* refused the query
    std::uint32_t plansSent = 0;
    std::uint32_t stopsSent = 0;
    std::uint32_t pathBlocked = 0;
    std::uint32_t energyViolations = 0;
    std::uint32_t cannotFollow = 0;
    std::uint32_t leftAutonomous = 0;
    std::uint32_t poseWaits = 0;        // planning runs that waited for a usable pose
    std::uint32_t malformedInputs = 0;
    std::uint32_t hazardsUnplaced = 0;  // hazard messages with no usable pose to place them
    std::uint32_t mapRefused = 0;       // local map refusals while building
    std::uint32_t hazardMapsSent = 0;   // KnownHazardsMsg published
    std::uint32_t escapes = 0;          // back-outs of a seen hazard's footprint
    std::uint32_t holds = 0;            // holds begun
    std::uint32_t releases = 0;         // holds released
    std::uint32_t heldRuns = 0;         // runs spent held
};

class HabitualTask final : public core::Task {
public:
    HabitualTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables);

    // Pipes "habitual_pose" (depth kPosePipeDepth: PoseEstimateMsg) and
    // "habitual" (kInputPipeDepth: leg, hazards, drive modes, follower status,
    // mode, mission hold). A refusal is evented (819) and returned; run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    msg::HabitualState state() const { return state_; }
    const msg::LegReportMsg& latestReport() const { return report_; }
    const HabitualCounters& counters() const { return counters_; }
    const PlannerQueryStats& lastQuery() const { return lastQuery_; }
    // The trajectory last sent (count 0 after a stop).
    const msg::TrajectoryMsg& trajectory() const { return trajectory_; }
    const MapBuilder& mapBuilder() const { return mapBuilder_; }
    // The map the remaining path is checked on (bare footprint, latest hazards).
    const LocalMap& checkMap() const { return checkMap_; }
    const RrtStar& planner() const { return rrt_; }
    double drivenLengthM() const { return drivenLengthM_; }
    double drivenEnergyJ() const { return drivenEnergyJ_; }
    bool autonomous() const { return autonomous_; }
    bool held() const { return held_; }
    bool escaping() const { return escaping_; }

private:
    struct Evaluation {
        double lengthM;
        double energyJ;
        double allowedLengthM;
        double allowedEnergyJ;
        msg::LegConstraint violated;  // kNone when every bound holds
        double excess;                // of the violated one
        double score;                 // largest relative excess (<= 0: every bound holds)
        double powerW;                // the drives' power at the cruise speed, now
        double allowedPowerW;         // 0: the leg has no power bound
    };

    // Inputs.
    void drainPoses();
    void drainInputs(core::TimeNs now);
    void onMode(const msg::ModeMsg& mode, core::TimeNs now);
    void onLeg(const msg::LegCommandMsg& leg, core::TimeNs now);
    void onHazards(const msg::HazardMsg& hazards, core::TimeNs now);
    void onDriveModes(const msg::DriveModesMsg& modes);
    void onFollower(const msg::FollowerStatusMsg& status, core::TimeNs now);
    void onHold(const msg::MissionHoldMsg& hold, core::TimeNs now);
    void malformed(const char* what, core::MsgId id);
    bool poseUsable(core::TimeNs now) const;
    double meanFactor() const;

    // Leg and planning.
    void refuseLeg(const msg::LegCommandMsg& leg, const char* why, core::TimeNs now);
    // How near the leg's point the rover must stop: max(HABITUAL.goal_tolerance_m,
    // the leg's arriveWithinM).
    double arrivalM() const;
    // How far short of the leg's point a trajectory ends: arrivalM() less the
    // table's tolerance (a region is reached to the tolerance as a point is:
    // the trajectory ends that deep inside it); 0 for a point leg.
    double stopShortM() const;
    // The leg done: kAchieved, counted and evented; alreadyInside: a region
    // leg whose rover stood within its region (nothing driven).
    void achieveLeg(bool alreadyInside, core::TimeNs now);
    void beginSession(PlanTrigger trigger, std::uint8_t firstAttempt, core::TimeNs now);
    void stepPlanning(core::TimeNs now);
    bool startQuery(core::TimeNs now);
    // RRT* iterations the planning run may take (see the file comment).
    std::uint32_t queryBudget() const;
    // queryStart_ inside a seen hazard's inflated disc (planMap_ at the bare
    // footprint): the point to back out to; false when there is none.
    bool findEscape(double footprint, geometry::Point2* exit) const;
    // queryStart_ off the site: the point on it to drive back to; false when none within kMaxReentryM.
    bool findReentry(double footprint, geometry::Point2* exit) const;
    void sendEscape(geometry::Point2 exit, bool offMap, core::TimeNs now);
    bool escapeClear(const tables::CoarseMapTable& coarse, geometry::Point2 exit, double keep,
                     const RememberedHazard* leaving) const;
    void finishQuery(core::TimeNs now);
    // rawPath_[0..count) is the planning run's path (count < 2: none).
    void completePlan(std::size_t count, core::TimeNs now);
    // count 0: no usable path this run.
    void finishAttempt(std::size_t count, const Evaluation& evaluation, core::TimeNs now);
    void acceptPlan(std::size_t count, const Evaluation& evaluation, core::TimeNs now);
    void failUp(msg::LegConstraint reason, const Evaluation& evaluation, core::TimeNs now);
    Evaluation evaluate(const geometry::Point2* path, std::size_t count, double headingRad) const;
    // The leg's power bound against the drives' power at the cruise speed with
    // the power factors of the moment (no path involved): the evaluation of
    // plan_'s path with the power figures refreshed; violated kPower when the
    // bound no longer holds.
    Evaluation powerCheck() const;
    void keepCandidate(const geometry::Point2* path, std::size_t count, const Evaluation& evaluation);
    bool rebuildMap(LocalMap* map, double clearanceM, const MapRelief* relief = nullptr);
    // A fresh trajectory_ for the leg in force: id, time, cruise speed; no points yet.
    void beginTrajectory(core::TimeNs now);

    // Driving.
    void updateOdometry();
    void superviseDriving(core::TimeNs now);
    std::size_t remainingPath(geometry::Point2* out);
    void onCannotFollow(const msg::FollowerStatusMsg& status, core::TimeNs now);

    // Outputs.
    void sendStop(core::TimeNs now);
    void setState(msg::HabitualState state, core::TimeNs now);
    void publishReport(core::TimeNs now);
    void publishHazards(core::TimeNs now);

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::PipeId posePipe_ = 0;
    core::PipeId inputPipe_ = 0;
    bool initialised_ = false;
    core::Message inbox_{};

    // Latest inputs.
    bool autonomous_ = false;
    msg::PoseEstimateMsg pose_{};
    bool poseSeen_ = false;
    msg::DriveModesMsg modes_{};
    bool modesChanged_ = false;
    bool held_ = false;

    // The leg.
    msg::HabitualState state_ = msg::HabitualState::kIdle;
    msg::LegCommandMsg leg_{};
    bool legActive_ = false;  // planning, repairing or driving
    double drivenLengthM_ = 0.0;
    double drivenEnergyJ_ = 0.0;
    geometry::Point2 anchor_{0.0, 0.0};
    double anchorHeading_ = 0.0;
    bool anchorSet_ = false;
    std::uint32_t cannotFollowReplans_ = 0;
    std::uint32_t escapesThisLeg_ = 0;
    bool escaping_ = false;  // the trajectory in force backs out of a seen hazard

    // The planning session.
    PlanTrigger trigger_ = PlanTrigger::kNewLeg;
    std::uint8_t attempt_ = 0;
    std::uint8_t lastAttempt_ = 0;
    bool queryActive_ = false;
    bool bareFootprint_ = false;  // plan without kPlanMarginM for the rest of the session
    std::uint32_t restWaitRuns_ = 0;
    std::uint32_t queryCount_ = 0;
    geometry::Point2 queryStart_{0.0, 0.0};
    double queryHeading_ = 0.0;
    bool haveCandidate_ = false;
    Evaluation candidate_{};
    geometry::Point2 candidatePath_[msg::kMaxTrajectoryPoints] = {};
    std::size_t candidateCount_ = 0;
    PlannerQueryStats lastQuery_{};

    // The trajectory being followed.
    msg::TrajectoryMsg trajectory_{};
    std::uint32_t nextTrajectoryId_ = 1;
    std::size_t progressIndex_ = 0;
    std::uint32_t checkedRevision_ = 0;
    double predictedFactor_ = 1.0;
    Evaluation plan_{};

    // Reporting.
    msg::LegReportMsg report_{};
    msg::LegConstraint reportViolated_ = msg::LegConstraint::kNone;
    double reportExcess_ = 0.0;
    std::uint32_t runs_ = 0;
    std::uint32_t hazardsRevision_ = 0;  // map revision last published in KnownHazardsMsg
    HabitualCounters counters_{};

    // Large members last.
    geometry::Point2 rawPath_[kMaxRawPathPoints] = {};
    MapBuilder mapBuilder_;
    LocalMap planMap_;
    LocalMap checkMap_;
    RrtStar rrt_;
};

}  // namespace rse::habitual
