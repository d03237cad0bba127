// The deliberative layer (10 Hz, its own frame offset): turns the operator's
// goals into chance-constrained plans and hands them to the habitual layer one
// leg at a time, taking exactly the risk the operator allows.
//
//   in:  GoalListMsg (goals and the risk bound: GOTO, ADD_TARGET, CLEAR_GOALS,
//        SET_RISK_BOUND), PoseEstimateMsg (start mean and covariance),
//        LegReportMsg, KnownHazardsMsg (hazards the habitual layer has seen),
//        DriveModesMsg (power factors, failed drives), DriveStatusMsg (the
//        drive interlock), ModeMsg, MissionHoldMsg (fault protection),
//        FaultStatusMsg (pose uncertainty)
//   out: LegCommandMsg, PlanStatusMsg (PLAN telemetry), SafeRequestMsg (call home)
//
// States (DeliberativeState, deliberative_msgs.hpp):
//   any        --new goal list (revision)--> goals adopted, risk relaxation and replans
//                                            reset, current leg cancelled; kWaiting (or
//                                            kIdle when the list is empty)
//   any        --mode left AUTONOMOUS------> plan dropped (leg cancelled): kWaiting
//   kWaiting   --AUTONOMOUS, usable pose---> problem built from the pose (map_problem.hpp):
//                                            kPlanning; refused (goal off site or inside an
//                                            obstacle) -> call home kGoalUnreachable
//   kPlanning  --planner sliced over runs--> a plan: legs cut (plan_legs.hpp), first leg
//                                            sent, kExecuting
//                                            no plan: risk bound relaxed x10, at most to
//                                            Delta x PLANNER.risk_relax_limit (and < 0.5),
//                                            plan again; at the limit -> call home
//                                            kNoPlanWithinRisk
//   kExecuting --leg achieved--------------> next leg; after the goal's last leg the next
//                                            goal is planned from the pose (kWaiting), or
//                                            kComplete after the last goal
//              --fail-up (length / energy)-> the leg's violated bound grows by what the
//                                            habitual layer predicted it needs (+5 %) and
//                                            the leg is resent, while the growth stays
//                                            within PLANNER.bound_relax_limit; else replan
//              --fail-up (no path, cannot
//                follow, bad leg)----------> replan from the current estimate
//              replan: at most PLANNER.replan_limit per goal, then call home
//                                            (kInsufficientPower when it was energy or power,
//                                            kReplansExhausted otherwise)
//   any active --the interlock tripped   --> call home kMobilityLost (the interlock holds
//                (not during a hold)         every drive and latches: fault protection leaves
//                                            it latched once it gives a drive up), unless
//                                            every drive it trips on is one the drive mode
//                                            estimator declares failed (not unknown): then the layer goes
//                                            on deciding (re-sent leg, fail-ups, replans) with
//                                            the failed drives in its model, and calls home
//                                            kMobilityLost only when a plan is found (no
//                                            drive is isolated yet), or with the reason no
//                                            plan was. Every plan made while drives are
//                                            declared failed or unknown takes them at
//                                            HABITUAL.failed_drive_power_factor and its motion
//                                            noise x PLANNER.failed_drive_noise_factor (event
//                                            990 when that set changes)
//              --fail-up (power)---------> every leg's power bound (for the rest of the plan)
//                                            grows by what the habitual layer predicted (+5 %)
//                                            and the leg is resent, while the growth stays
//                                            within PLANNER.bound_relax_limit; else replan
//   kExecuting --goal's last leg reached, --> no goal claimed: waits (kExecuting, no leg) until
//                pose uncertain (fault 19  the pose is certain, then claims the goal if the pose
//                or sigma > pose_fault_     is within HABITUAL.goal_tolerance_m of it (or within
//                sigma_m)                   the goal's region when larger), else re-sends the
//                                           last leg from the pose
//   a goal's region (PlanGoalMsg radius, a plan's `within R`): its last leg carries
//              it (LegCommandMsg.arriveWithinM), so the habitual layer stops on the
//              way in; every other leg, and a back-up, carries 0 (the point)
//   held (MissionHoldMsg reasons != 0): no leg sent, no plan started, fail-ups
//              and mobility loss ignored (fault protection owns the response);
//              planning already under way finishes and its first leg waits.
//              Released (reasons 0, resumeCount grown): when executing, the
//              current leg is re-sent from the current pose (new legId, bounds
//              recomputed: plan_legs.hpp legBoundsFrom).
//   seen hazards (KnownHazardsMsg): every plan includes them as obstacles
//              (map_problem.hpp); a leg end inside one, or near a coarse-map
//              polygon (within the footprint and kLegEndMarginM), is merged into
//              the next leg, also for the leg in force on a new sighting
//              (re-sent as a new leg).
//   no path the replans cannot fix (a kNoPath fail-up with PLANNER.replan_limit
//              replans spent): back up PLANNER.no_path_backup_m along the driven
//              track (recorded every kTrackStepM, kTrackPoints deep; not while
//              backing up, and cut back to the back-up's end when reached), to the
//              first point there clear of seen hazards, as a leg of its own;
//              reached, a replan from there (not counted against replan_limit);
//              at most PLANNER.no_path_backup_limit per goal, then call home
//              kReplansExhausted. No track to back along, or no clear point
//              within twice the distance: call home. A back-up leg that fails
//              up calls home.
//   replan: a ReplanRequest records the unfinished goals, the time and the
//              position (and covariance) at the fail-up; the plan starts from
//              that position (refreshed from the pose if that position is older
//              than kReplanMaxAgeNs when planning starts) and event 911 gives them.
//   off the map (ReplanRequestMsg from fault protection, fault 46): the
//              waypoint is cancelled (the habitual layer stops) and the
//              unfinished goals replanned from the pose at once (not counted
//              against replan_limit: fault protection's attempts bound it).
//              A start off the site shrunk by the footprint (an off-map rover,
//              or one that slid against the edge) is planned from the nearest
//              point kReentryInsetM inside that site (event 928); the first
//              leg's bounds are those from the rover itself, and the habitual
//              layer drives back on the straight way (its escape).
//   call home: leg cancelled (legId 0: the habitual layer stops and holds),
//   SafeRequestMsg (the mode owner goes to SAFE), CRITICAL event 912, PLAN
//   telemetry shows kCalledHome and the reason; the layer then waits for new goals.
//
// Time bound per run: at most kMaxUnitsPerRun planner units and stops after the
// unit that takes the run's planner work past kSliceWork (one unit does at most
// CcPlanner::kMaxUnitWork work units: docs/deliberative.md), so a run costs
// at most kSliceWork + kMaxUnitWork work units; a whole plan is bounded
// by PLANNER.node_budget LPs and PLANNER.time_budget_ms x kWorkKUnitsPerMs
// thousand work units. Inputs are bounded by the pipe depths. No heap: the
// planner, problem, plan and legs are members (about 460 KB: make it static).
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/deliberative/plan_legs.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
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
// Poses and drive status come at 100 Hz: 20 per run, 40 survive one skipped run.
constexpr std::uint16_t kFastPipeDepth = 40;
constexpr std::uint16_t kInputPipeDepth = 16;
constexpr std::uint32_t kStatusPeriodRuns = 10;  // 1 Hz
constexpr core::TimeNs kPoseMaxAgeNs = 500 * core::kNsPerMs;
constexpr double kRiskRelaxStep = 10.0;          // each relaxation multiplies the risk bound by this
// Before relaxing: the same problem once more with the planner's search at
// this many times Boole's budget, its plan certified within the risk in force
// (CcPlannerParams::searchRiskScale; optimised allocation only): a narrow
// passage the even split refuses may be certified within the bound.
constexpr double kWideSearchScale = 8.0;
constexpr double kMaxRiskInForce = 0.49;         // the planner needs Delta < 0.5
constexpr double kBoundRelaxHeadroom = 1.05;     // a relaxed bound: what was predicted + 5 %
// A leg end must clear a seen hazard's disc by the footprint and this: the
// habitual layer plans with habitual::kPlanMarginM beyond the footprint, and a
// disc grows as more of its rock comes into view.
constexpr double kLegEndMarginM = 0.25;
// How far inside the planning site (the site shrunk by the footprint) the
// re-entry point of an off-site start lies: the planner's start must be on the
// site, and a point on its very edge would sit at the wall of the habitual
// layer's planning margin.
constexpr double kReentryInsetM = 0.3;
// A replan request's position older than this when planning starts is
// refreshed from the pose (the pose was stale at the fail-up, or the rover
// moved while planning waited for a usable pose).
constexpr core::TimeNs kReplanMaxAgeNs = 1000 * core::kNsPerMs;
// The driven track kept for backing up: a point every kTrackStepM, the last kTrackPoints.
constexpr double kTrackStepM = 0.25;
constexpr std::size_t kTrackPoints = 64;
// Largest hazard radius believed (the habitual layer merges no disc beyond 2 m).
constexpr float kMaxHazardRadiusM = 10.0F;

// What a replan starts from: the unfinished goals, the time and the position.
struct ReplanRequest {
    core::TimeNs timeNs = 0;         // when the replan was asked for
    core::TimeNs poseTimeNs = 0;     // when the rover was at (xM, yM)
    double xM = 0.0, yM = 0.0, headingRad = 0.0;
    double cov[4] = {};              // (x, y) covariance at that time
    std::uint8_t firstGoal = 0;      // goals_[firstGoal .. firstGoal + unfinished) remain
    std::uint8_t unfinished = 0;
    msg::LegConstraint why = msg::LegConstraint::kNone;
    bool pending = false;            // consumed when the plan starts
};

struct DeliberativeCounters {
    std::uint32_t goalListsAdopted = 0;
    std::uint32_t plansStarted = 0;
    std::uint32_t plansFound = 0;
    std::uint32_t noPlans = 0;
    std::uint32_t riskRelaxations = 0;
    std::uint32_t legsSent = 0;
    std::uint32_t legsAchieved = 0;
    std::uint32_t goalsReached = 0;
    std::uint32_t failUps = 0;
    std::uint32_t boundRelaxations = 0;
    std::uint32_t replans = 0;
    std::uint32_t callHomes = 0;
    std::uint32_t problemsRefused = 0;
    std::uint32_t obstaclesDropped = 0;  // plans that left coarse-map obstacles out
    std::uint32_t malformedInputs = 0;
    std::uint32_t publishFailures = 0;
    std::uint32_t planningRuns = 0;      // task runs that stepped the planner
    std::uint32_t hazardMaps = 0;        // KnownHazardsMsg adopted
    std::uint32_t legEndsSkipped = 0;    // leg ends inside a seen hazard, merged into the next leg
    std::uint32_t holds = 0;             // holds begun
    std::uint32_t resumes = 0;           // holds released
    std::uint32_t failUpsWhileHeld = 0;
    std::uint32_t goalsUnconfirmed = 0;  // goal's last leg reached with the pose uncertain
    std::uint32_t goalLegsResent = 0;    // ... and then re-sent from a certain pose off the goal
    std::uint32_t backUps = 0;           // back-ups along the track after "no path"
    std::uint32_t offMapReplans = 0;     // fault protection's off-map replan requests acted on
    std::uint32_t offMapIgnored = 0;     // ... that came with no mission to replan (counted, evented)
    std::uint32_t reentryPlans = 0;      // plans started from the re-entry point of an off-site start
    std::uint32_t seededPlans = 0;       // plans seeded with the last plan's faces (same goal and obstacles)
    std::uint32_t budgetPlans = 0;       // plans found but not proven optimal: the work budget ran out first
    std::uint32_t wideSearches = 0;      // no plan, so the same problem searched at kWideSearchScale
    std::uint32_t wideSearchPlans = 0;   // ... which found a plan certified within the risk in force
    std::uint32_t powerRelaxations = 0;  // power bounds relaxed (also counted in boundRelaxations)
    std::uint32_t failedDriveModels = 0; // plans started with a new set of drives taken as failed (event 990)
    std::uint64_t maxRunWork = 0;        // most planner work one run did (work units)
    std::uint32_t maxRunUnits = 0;
};

class DeliberativeTask final : public core::Task {
public:
    DeliberativeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables);

    // Pipes "delib_fast" (kFastPipeDepth: PoseEstimateMsg, DriveStatusMsg) and "deliberative"
    // (kInputPipeDepth: goals (the plan executive's PlanGoalMsg only), leg reports, known hazards, drive modes, mode,
    // mission hold, fault status, replan requests). A refusal is
    // evented (917) and returned; run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    msg::DeliberativeState state() const { return status_.state; }
    const msg::PlanStatusMsg& status() const { return status_; }
    const DeliberativeCounters& counters() const { return counters_; }
    const CcPlanner& planner() const { return planner_; }
    const CcProblem& problem() const { return problem_; }
    const CcPlan& plan() const { return plan_; }
    const LegPlan& legs() const { return legs_; }
    const msg::LegCommandMsg& lastLeg() const { return leg_; }
    std::uint32_t plannerSlices() const { return slices_; }
    bool held() const { return held_; }
    bool backingUp() const { return backingUp_; }
    const ReplanRequest& lastReplanRequest() const { return replanRequest_; }
    const msg::KnownHazardsMsg& hazards() const { return hazards_; }

private:
    void drainFast();
    void drainInputs(core::TimeNs now);
    void malformed(const char* what, core::MsgId id);
    bool poseUsable(core::TimeNs now) const;
    double meanFactor() const;
    // Wheels the drive mode estimator declares failed (and unknown, withUnknown) (bit per wheel).
    std::uint8_t failedDrives(bool withUnknown) const;
    void noteFailedSince(core::TimeNs now);
    // Drives declared failed or unknown for PLANNER.failed_drive_confirm_s or more.
    std::uint8_t confirmedFailedDrives(core::TimeNs now) const;
    bool mobilityLost() const;

    void onGoals(const msg::PlanGoalMsg& goal, core::TimeNs now);
    // The goal in hand as the operator numbers it: its index in the operator's
    // goal list (PlanGoalMsg.listIndex) plus the index in the list given.
    std::size_t goalNumber() const { return static_cast<std::size_t>(listIndex_) + goalIndex_; }
    void onMode(const msg::ModeMsg& mode, core::TimeNs now);
    void onLegReport(const msg::LegReportMsg& report, core::TimeNs now);
    void onFailUp(const msg::LegReportMsg& report, core::TimeNs now);
    void onHazards(const msg::KnownHazardsMsg& hazards, core::TimeNs now);
    void onHold(const msg::MissionHoldMsg& hold, core::TimeNs now);
    void onReplanRequest(const msg::ReplanRequestMsg& request, core::TimeNs now);
    bool poseUncertain() const;
    bool legEndTooClose(const msg::PlanLeg& leg) const;
    // A leg end within the footprint + kLegEndMarginM of a seen hazard's disc or
    // a coarse-map polygon.
    // Merges such leg ends into their next leg, from legIndex_ on
    // while they are not the last leg; true when legIndex_ moved.
    bool skipLegEndsInHazards();
    void goalReached();
    // How near the goal in hand the rover must stand for it to be reached:
    // its region (PlanGoalMsg's radius, a plan's `within R`), never less
    // than HABITUAL.goal_tolerance_m. The goal's last leg carries the region.
    double goalArrivalM() const;
    void checkUnconfirmedGoal(core::TimeNs now);
    void resendFromPose(core::TimeNs now);
    LegParams legParams() const;
    void captureReplanRequest(msg::LegConstraint why, core::TimeNs now);
    void recordTrack();
    // The point no_path_backup_m back along the track from the pose, clear of
    // seen hazards; false when there is none.
    // *keep: the track points older than the target.
    bool backUpTarget(double distanceM, msg::PlanLeg* out, std::size_t* keep) const;
    bool startBackUp(core::TimeNs now);
    void sendBackUpLeg(core::TimeNs now);

    void startPlan(core::TimeNs now);
    // The operator's Delta x riskFactor_, below kMaxRiskInForce: what a plan uses.
    double riskInForce() const;
    // The planner's budgets from the planner table.
    deliberative::CcPlannerParams plannerParams() const;
    void stepPlanner(core::TimeNs now);
    void onPlanFinished(core::TimeNs now);
    void widenFirstLegFromPose(const LegParams& params);
    void sendLeg(core::TimeNs now);
    void replan(msg::LegConstraint why, core::TimeNs now);
    void callHome(msg::CallHomeReason reason, const char* detail, core::TimeNs now);
    void cancelLeg(core::TimeNs now);

    void setState(msg::DeliberativeState state);
    void publishStatus(core::TimeNs now);
    // The plan just made (plan_, problem_) as PlanPathMsg numbered
    // counters_.plansFound: call right after counting it.
    void publishPlanPath(core::TimeNs now);
    void published(core::Status status, const char* what);

    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    core::PipeId fastPipe_ = 0;
    core::PipeId inputPipe_ = 0;
    bool initialised_ = false;
    core::Message inbox_{};

    bool autonomous_ = false;
    msg::PoseEstimateMsg pose_{};
    bool poseSeen_ = false;
    msg::DriveModesMsg modes_{};
    bool modesSeen_ = false;
    bool interlockTripped_ = false;
    msg::DriveHealth driveHealth_[msg::kWheelCount] = {};  // DriveStatusMsg last seen
    msg::FaultStatusMsg faults_{};
    msg::KnownHazardsMsg hazards_{};
    bool held_ = false;
    std::uint32_t holdReasons_ = 0;
    std::uint32_t resumeCount_ = 0;
    bool goalUnconfirmed_ = false;   // the goal's last leg reached, pose uncertain: waiting
    ReplanRequest replanRequest_{};
    // The driven track: track_[(trackHead_ + k) % kTrackPoints], k < trackCount_, oldest first.
    double trackX_[kTrackPoints] = {};
    double trackY_[kTrackPoints] = {};
    std::size_t trackHead_ = 0;
    std::size_t trackCount_ = 0;
    bool backingUp_ = false;         // the leg in force is a back-up
    bool fromReentry_ = false;       // the plan being made starts at the re-entry point, not at the rover
    msg::PlanLeg backUpLeg_{};
    std::size_t backUpKeep_ = 0;     // track points kept when the back-up is reached
    std::uint32_t goalBackUps_ = 0;  // back-ups of the current goal

    // Goals.
    msg::GoalListMsg goals_{};
    std::uint8_t listIndex_ = 0;
    bool goalsSeen_ = false;
    std::uint8_t goalIndex_ = 0;
    double riskFactor_ = 1.0;        // risk in force = Delta x riskFactor_
    std::uint32_t goalReplans_ = 0;  // replans of the current goal

    // The plan and its legs.
    CcProblem problem_{};
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
    LastPlan last_{};
    double planGap_ = 1.0;  // PlanStatusMsg.planGap of plan_
    bool seededPlan_ = false;  // the plan under way was seeded with last_
    bool wideSearch_ = false;  // the plan under way is the wide search (kWideSearchScale)
    CcPlan plan_{};
    LegPlan legs_{};
    std::size_t legIndex_ = 0;
    double legBoundFactor_ = 1.0;    // growth of the current leg's bounds by relaxation
    double legEnergyFactor_ = 1.0;   // ... of its energy bound alone (kept when the leg is re-sent after a hold)
    double legLengthFactor_ = 1.0;   // ... of its length bound alone
    // Growth of every leg's power bound by relaxation, for the rest of the
    // plan: the drives' power is the same on every leg (reset by a new plan,
    // whose legs are bounded at the power factors of the moment).
    double powerRelax_ = 1.0;
    // Drives the last plan started with took as failed (bit per wheel:
    // declared failed or unknown by the drive mode estimator): event 990 when it changes.
    std::uint8_t plannedFailedMask_ = 0;
    core::TimeNs failedSinceNs_[msg::kWheelCount] = {};  // declared failed or unknown since (0: not)
    msg::LegCommandMsg leg_{};       // the leg in force (legId 0: none)
    std::uint32_t nextLegId_ = 1;
    std::uint32_t slices_ = 0;       // runs the current plan has taken
    bool changed_ = false;           // publish the status this run
    std::uint32_t runs_ = 0;
    msg::PlanStatusMsg status_{};
    DeliberativeCounters counters_{};

    CcPlanner planner_;
};

}  // namespace rse::deliberative
