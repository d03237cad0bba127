// The deliberative layer (10 Hz, its own frame offset): turns the operator's
// goals into chance-constrained plans and hands them to the habitual layer one
// leg at a time, taking exactly the risk the operator allows.
//
//   in:  PlanGoalMsg (the plan executive's drive activities: a goal, its region
//        and the risk bound), PoseEstimateMsg (start mean and covariance),
//        LegReportMsg, KnownHazardsMsg (hazards the habitual layer has seen),
//        DriveModesMsg (power factors, failed drives), DriveStatusMsg (the
//        drive interlock), ModeMsg, MissionHoldMsg (fault protection),
//        FaultStatusMsg (pose uncertainty), ReplanRequestMsg (fault protection:
//        off the map)
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
//              site mode, a horizon short of the goal: the next horizon is planned
//                                            while driving its end (horizon_look_ahead.hpp);
//                                            at its last leg a finished look-ahead's first
//                                            leg is sent at once (kExecuting), one still
//                                            planning finishes (kPlanning), none: kWaiting
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
// Parts (docs/deliberative.md, "Parts of the task"): the task is the shell
// that holds the state above (goals, mode, hold, pose) and the order of a run;
// each part owns its state and reports its own events:
//   deliberative_inputs  the two pipes (core::InputPipe) and each input's checks
//   drive_health         drive modes and status: failed drives, mobility, power factor
//   plan_maker           the map problem, the planner sliced over runs, the wide search, PLAN_PATH
//   leg_sequencer        the legs, the leg in force, sending and re-sending, goal claims
//   leg_end_clearance    a leg end too near a seen hazard or the coarse map
//   mission_hold         fault protection's hold: held, released (events 920, 921)
//   replan_policy        fail-ups: relax or replan; replan requests; risk relaxation
//   back_up              the driven track and the back-up manoeuvre
//   publisher            publishing with the refusals counted (event 918)
//   route_horizons       site mode: the global route over the site map and the
//                        horizons along it (events 993, 994)
//   horizon_look_ahead   site mode: the next horizon planned while the rover
//                        drives the end of this one (events 995, 996, 997)
// Inputs are bounded by the pipe depths; a run's planning by plan_maker.hpp's
// slice, and site mode's route search by its slice. No heap: the planner,
// problem, plan, legs and the route search are members (about 3.3 MB, 2.8 MB
// of it the route search: make the task static).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/back_up.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/deliberative_inputs.hpp"
#include "fsw/deliberative/drive_health.hpp"
#include "fsw/deliberative/horizon_look_ahead.hpp"
#include "fsw/deliberative/leg_end_clearance.hpp"
#include "fsw/deliberative/leg_sequencer.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/deliberative/mission_hold.hpp"
#include "fsw/deliberative/plan_legs.hpp"
#include "fsw/deliberative/plan_maker.hpp"
#include "fsw/deliberative/publisher.hpp"
#include "fsw/deliberative/replan_policy.hpp"
#include "fsw/deliberative/route_horizons.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::deliberative {

constexpr std::uint32_t kStatusPeriodRuns = 10;  // 1 Hz
constexpr core::TimeNs kPoseMaxAgeNs = 500 * core::kNsPerMs;

// Assembled from the parts' counters at the end of every run (they change only
// within a run); PLAN telemetry shows the main ones.
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
    std::uint32_t routesFound = 0;       // site mode: global routes found (event 993)
    std::uint32_t routesFailed = 0;      // ... refused, none, or the budget spent (event 994)
    std::uint32_t horizonsReached = 0;   // ... horizons driven to their end (the next one planned)
    std::uint32_t siteRocksAdded = 0;    // ... rocks near a plan made candidates before its check
    std::uint32_t lookAheadsStarted = 0; // ... next horizons planned while driving (event 995)
    std::uint32_t lookAheadsDropped = 0; // ... dropped before their horizon's end (event 996)
    std::uint32_t horizonsDrivenThrough = 0;  // ... horizon ends whose next leg went at once (event 997)
    std::uint32_t horizonStops = 0;      // ... horizon ends the rover stopped at to plan (event 997)
};

class DeliberativeTask final : public core::Task, private DeliberativeInputs::Receiver {
public:
    // siteMap: the site map in force (docs/site_map.md), or null. While it
    // holds a map the layer is in site mode: a global route to each goal,
    // then horizons along it (route_horizons.hpp).
    DeliberativeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
                     const site_map::SiteMap* siteMap = nullptr);

    // Pipes "delib_fast" and "deliberative" (deliberative_inputs.hpp). A
    // refusal is evented (917) and returned; run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    msg::DeliberativeState state() const { return status_.state; }
    const msg::PlanStatusMsg& status() const { return status_; }
    const DeliberativeCounters& counters() const { return counters_; }
    const CcPlanner& planner() const { return maker_.planner(); }
    const CcProblem& problem() const { return maker_.problem(); }
    const CcPlan& plan() const { return maker_.plan(); }
    const PlanMaker& planMaker() const { return maker_; }
    const LegPlan& legs() const { return legs_.legs(); }
    const msg::LegCommandMsg& lastLeg() const { return legs_.legInForce(); }
    std::uint32_t plannerSlices() const { return maker_.slices(); }
    bool held() const { return hold_.held(); }
    bool backingUp() const { return backUp_.active(); }
    const ReplanRequest& lastReplanRequest() const { return policy_.request(); }
    const msg::KnownHazardsMsg& hazards() const { return hazards_; }
    // Site mode: the route and the horizon in hand.
    bool siteMode() const { return siteMap_ != nullptr && siteMap_->loaded(); }
    const RouteHorizons& route() const { return horizons_; }
    const Horizon& horizon() const { return horizon_; }
    bool routing() const { return routing_; }
    const HorizonLookAhead& lookAhead() const { return lookAhead_; }

private:
    // The shell's own counts (the parts keep theirs).
    struct MissionCounters {
        std::uint32_t goalListsAdopted = 0;
        std::uint32_t failUps = 0;
        std::uint32_t callHomes = 0;
        std::uint32_t hazardMaps = 0;
        std::uint32_t failUpsWhileHeld = 0;
        std::uint32_t offMapReplans = 0;
        std::uint32_t offMapIgnored = 0;
    };

    // Inputs (DeliberativeInputs::Receiver), each at the run's time now_.
    void takePose(const msg::PoseEstimateMsg& pose) override;
    void takeDriveStatus(const msg::DriveStatusMsg& drives) override;
    void takeGoals(const msg::PlanGoalMsg& goal) override;
    void takeLegReport(const msg::LegReportMsg& report) override;
    void takeDriveModes(const msg::DriveModesMsg& modes) override;
    void takeMode(const msg::ModeMsg& mode) override;
    void takeHazards(const msg::KnownHazardsMsg& hazards) override;
    void takeHold(const msg::MissionHoldMsg& hold) override;
    void takeFaults(const msg::FaultStatusMsg& faults) override;
    void takeReplanRequest(const msg::ReplanRequestMsg& request) override;

    // Executing.
    void onFailUp(const msg::LegReportMsg& report);
    void backedUp();
    void lastLegReached();
    void nextGoal();
    void replan(msg::LegConstraint why);
    bool startBackUp();
    void sendLeg();
    void sendBackUpLeg();
    void resendFromPose();
    void cancelLeg();
    void callHome(msg::CallHomeReason reason, const char* detail);

    // Planning.
    void startPlan();
    void onPlanFinished();
    // Site mode: the route to the goal in hand, sliced over runs.
    void startRoute(double fromX, double fromY, const msg::Goal& goal);
    void onRouted();
    bool planHorizon(double fromX, double fromY, PlanStart* start);
    // Site mode's receding horizon (horizon_look_ahead.hpp).
    bool lookAheadDue() const;
    void startLookAhead();
    void dropLookAhead(const char* why, bool stale = false);
    void adoptLookAhead();

    // What the parts are given.
    bool active() const;
    bool poseUsable() const;
    bool poseUncertain() const;
    double meanFactor() const;
    LegParams legParams() const;
    LegEndClearance clearance() const;
    ReplanFrom replanFrom() const;
    HorizonReach horizonReach() const;   // PLANNER.site_horizon_m, site_last_horizon_factor
    GoalArrival arrival() const;
    // The goal in hand as the operator numbers it: its index in the operator's
    // goal list (PlanGoalMsg.listIndex) plus the index in the list given.
    std::size_t goalNumber() const { return static_cast<std::size_t>(listIndex_) + goalIndex_; }
    // The goal in hand's region (0: the point, or no goal in hand).
    double goalRadiusM() const;

    void setState(msg::DeliberativeState state);
    void publishStatus();
    // counters_ from the parts' counters and the shell's.
    void collectCounters();

    core::EventLog& events_;
    const tables::TableService& tables_;
    Publisher out_;
    DeliberativeInputs inputs_;
    bool initialised_ = false;
    core::TimeNs now_ = 0;  // the run's time (frame start): what the inputs are handled at

    bool autonomous_ = false;
    msg::PoseEstimateMsg pose_{};
    bool poseSeen_ = false;
    msg::FaultStatusMsg faults_{};
    msg::KnownHazardsMsg hazards_{};
    MissionHold hold_;

    // Goals.
    msg::GoalListMsg goals_{};
    std::uint8_t listIndex_ = 0;
    bool goalsSeen_ = false;
    std::uint8_t goalIndex_ = 0;

    bool changed_ = false;  // publish the status this run
    std::uint32_t runs_ = 0;
    msg::PlanStatusMsg status_{};
    MissionCounters mission_{};
    DeliberativeCounters counters_{};

    // Site mode.
    const site_map::SiteMap* siteMap_ = nullptr;
    site_map::SiteQuery siteQuery_{};
    Horizon horizon_{};
    bool routing_ = false;       // the route search is under way (kPlanning)
    bool horizonLast_ = true;    // the plan in hand goes to the goal itself (not a horizon short of it)
    std::uint32_t hazardRevisionAtPlan_ = 0;  // the known hazards' revision when the plan in hand was started
    std::uint32_t routesFound_ = 0;
    std::uint32_t routesFailed_ = 0;
    std::uint32_t horizonsReached_ = 0;
    RouteHorizons horizons_;
    HorizonLookAhead lookAhead_;
    bool planFromLookAhead_ = false;  // the plan being finished is a look-ahead's (from a horizon's end)

    // The parts.
    DriveHealthView drives_;
    ReplanPolicy policy_;
    BackUpManoeuvre backUp_;
    LegSequencer legs_;
    PlanMaker maker_;
};

}  // namespace rse::deliberative
