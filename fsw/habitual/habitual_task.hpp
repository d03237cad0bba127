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
//           A run whose start lies in a seen hazard's disc grown by the
//           footprint, or off the site, first backs out (kDriving on a
//           two-point trajectory; reached, the session plans again from there).
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
// to the point as always and cut where it first comes within legStopShortM()
// of it (planning_session.hpp): the rover stops on the way in, the goal
// tolerance deep inside the region, instead of driving to the centre.
//
// This task is the state machine above; the work is done by its parts (one
// concept each, docs/habitual.md "Parts of the task"):
//   input_checks.hpp         what a message must be to count; why a leg is refused
//   hazard_memory.hpp        sightings remembered, the maps built from them, the check map
//   planning_session.hpp     a session's planning runs: margins, straight line, RRT* slices, completion
//   escape_search.hpp        where to back out to (out of a disc, back onto the site)
//   candidate_evaluator.hpp  the constraints: figures, power check, least violating candidate
//   drive_supervisor.hpp     odometry, remaining path, blocked path, power factors, follower
//   habitual_outputs.hpp     TrajectoryMsg, LegReportMsg, KnownHazardsMsg
//   leg_events.hpp           the events this state machine raises (texts, throttling)
// Inputs come through two core::InputPipe (input_pipe.hpp): a message that
// fails its checks is refused whole, counted in malformedInputs and evented (813).
//
// Hazard memory (map_builder.hpp): kept for the whole mission, oldest replaced
// when full; the local map is rebuilt from it when a planning run starts and
// whenever it changes while driving.
//
// Time bound per run: at most kRrtIterationsPerRun RRT* iterations, or one
// plan completion (shortcutting at most kMaxRawPathPoints points), plus the
// inputs (bounded by the pipe depths) and a map rebuild (16 polygons + 32 discs).
// No heap: the planner, maps and buffers are members of the parts, the parts
// members of the task (the object is large: make it static). Every loop is
// bounded by a constant.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/habitual/drive_supervisor.hpp"
#include "fsw/habitual/escape_search.hpp"
#include "fsw/habitual/habitual_outputs.hpp"
#include "fsw/habitual/hazard_memory.hpp"
#include "fsw/habitual/leg_events.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/habitual/planning_session.hpp"
#include "fsw/habitual/rrt_star.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::habitual {

// Pipes: poses come at 100 Hz (10 per run; 20 survive one skipped run), the rest
// at 10 Hz or on change.
constexpr std::uint16_t kPosePipeDepth = 20;
constexpr std::uint16_t kInputPipeDepth = 12;
constexpr std::uint32_t kReportPeriodRuns = 10;  // 1 Hz
// A pose older than this cannot be planned from.
constexpr core::TimeNs kPoseMaxAgeNs = 500 * core::kNsPerMs;

// What the task has done: its own figures, and its parts' (planning session,
// drive supervisor, outputs, hazard memory, input pipes) gathered at the end
// of every run.
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
    std::uint32_t backoffWaits = 0;     // planning runs that waited for the follower's back-off from a contact
    std::uint32_t malformedInputs = 0;  // messages refused by either pipe, plus hazard sightings rejected
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
    // siteMap: the site map in force (site mode: its rocks near each leg join
    // the local map; docs/habitual.md), or null.
    HabitualTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
                 const site_map::SiteMap* siteMap = nullptr);

    // Pipes "habitual_pose" (depth kPosePipeDepth: PoseEstimateMsg) and
    // "habitual" (kInputPipeDepth: leg, hazards, drive modes, follower status, contact,
    // mode, mission hold). A refusal is evented (819) and returned; run() then does nothing.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    msg::HabitualState state() const { return state_; }
    const msg::LegReportMsg& latestReport() const { return outputs_.latestReport(); }
    // As of the end of the last run.
    const HabitualCounters& counters() const { return counters_; }
    const PlannerQueryStats& lastQuery() const { return session_.lastQuery(); }
    // The trajectory last sent (count 0 after a stop).
    const msg::TrajectoryMsg& trajectory() const { return outputs_.trajectory(); }
    const MapBuilder& mapBuilder() const { return memory_.builder(); }
    // The map the remaining path is checked on (bare footprint, latest hazards).
    const LocalMap& checkMap() const { return memory_.checkMap(); }
    const RrtStar& planner() const { return session_.planner(); }
    double drivenLengthM() const { return supervisor_.drivenLengthM(); }
    double drivenEnergyJ() const { return supervisor_.drivenEnergyJ(); }
    bool autonomous() const { return autonomous_; }
    bool held() const { return held_; }
    bool escaping() const { return outputs_.escaping(); }

private:
    // Inputs (routed on the pipes; a refusal is counted and evented by the pipe).
    core::Status takePose(const msg::PoseEstimateMsg& pose);
    core::Status takeMode(const msg::ModeMsg& mode);
    void takeLeg(const msg::LegCommandMsg& leg);
    core::Status takeHazards(const msg::HazardMsg& hazards);
    core::Status takeDriveModes(const msg::DriveModesMsg& modes);
    core::Status takeFollower(const msg::FollowerStatusMsg& status);
    // A contact the follower felt: remembered where it was (hazard_memory.hpp);
    // the follower's kCannotFollow (kContact) after its back-off replans the leg.
    core::Status takeContact(const msg::ContactMsg& contact);
    core::Status takeHold(const msg::MissionHoldMsg& hold);
    bool poseUsable(core::TimeNs now) const;
    double meanFactor() const;
    LegProgress progress() const;

    // The leg.
    void cancelLeg(core::TimeNs now);
    void refuseLeg(const msg::LegCommandMsg& leg, const char* why, core::TimeNs now);
    void acceptLeg(const msg::LegCommandMsg& leg, core::TimeNs now);
    // The leg done: kAchieved, counted and evented; alreadyInside: a region
    // leg whose rover stood within its region (nothing driven).
    void achieveLeg(bool alreadyInside, core::TimeNs now);
    void failUp(msg::LegConstraint reason, const Evaluation& evaluation, core::TimeNs now);

    // Planning.
    void beginSession(PlanTrigger trigger, std::uint8_t firstAttempt, core::TimeNs now);
    void stepPlanning(core::TimeNs now);
    // Before a planning run: a region leg whose rover stands within its region
    // is achieved, a power bound that no longer holds fails up, a moving rover
    // is waited for (false: no run now).
    bool readyToPlan(core::TimeNs now);
    void takePlanStep(PlanStep step, core::TimeNs now);
    void sendEscape(core::TimeNs now);
    // count 0: no usable path this run.
    void finishAttempt(std::size_t count, const Evaluation& evaluation, core::TimeNs now);
    void acceptPlan(std::size_t count, const Evaluation& evaluation, core::TimeNs now);

    // Driving.
    void superviseDriving(core::TimeNs now);
    void onPowerFactors(core::TimeNs now);

    // Outputs.
    void sendStop(core::TimeNs now);
    void setState(msg::HabitualState state, core::TimeNs now);
    void publishReport(core::TimeNs now);
    ReportCounts reportCounts() const;
    // counters_'s fields the parts count, copied from them.
    void collectCounters();

    core::EventLog& events_;
    const tables::TableService& tables_;
    core::InputPipe posePipe_;
    core::InputPipe inputPipe_;
    bool initialised_ = false;
    core::TimeNs now_ = 0;  // the run's start, for the input handlers

    // Latest inputs.
    bool autonomous_ = false;
    msg::PoseEstimateMsg pose_{};
    bool poseSeen_ = false;
    msg::DriveModesMsg modes_{};
    bool modesChanged_ = false;
    bool held_ = false;
    // The follower is backing off a contact (FollowerState::kBackingOff):
    // no planning run starts until it has ended (bounded by the follower's
    // back-off timeout), so the plan starts from where the back-off left the
    // rover, clear of the contact, and no new path cuts the back-off short.
    bool followerBackingOff_ = false;

    // The leg.
    msg::HabitualState state_ = msg::HabitualState::kIdle;
    msg::LegCommandMsg leg_{};
    bool legActive_ = false;  // planning, repairing or driving
    std::uint32_t runs_ = 0;
    HabitualCounters counters_{};  // the task's own figures; the parts' copied in by collectCounters()

    // The parts (the planning session, about 1 MB, last).
    LegEvents legEvents_;
    HazardMemory memory_;
    CandidateEvaluator evaluator_;
    DriveSupervisor supervisor_;
    HabitualOutputs outputs_;
    PlanningSession session_;
};

}  // namespace rse::habitual
