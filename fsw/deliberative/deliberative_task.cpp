#include "fsw/deliberative/deliberative_task.hpp"

#include "fsw/geometry/rover_footprint.hpp"

#include <cmath>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::deliberative {

namespace {

static_assert(msg::kPlanPathMeans == kMaxPlanSteps + 1, "PlanPathMsg holds mu_0 .. mu_N of the longest plan");

constexpr std::uint8_t kLargestHabitualState = static_cast<std::uint8_t>(msg::HabitualState::kAchieved);
constexpr std::uint8_t kLargestConstraint = static_cast<std::uint8_t>(msg::LegConstraint::kPower);

const char* constraintName(msg::LegConstraint c) {
    switch (c) {
        case msg::LegConstraint::kNone: return "none";
        case msg::LegConstraint::kPathLength: return "path length";
        case msg::LegConstraint::kEnergy: return "energy";
        case msg::LegConstraint::kNoPath: return "no path";
        case msg::LegConstraint::kCannotFollow: return "cannot follow";
        case msg::LegConstraint::kBadLeg: return "leg refused";
        case msg::LegConstraint::kPower: return "power";
    }
    return "?";
}

const char* reasonName(msg::CallHomeReason r) {
    switch (r) {
        case msg::CallHomeReason::kNone: return "none";
        case msg::CallHomeReason::kNoPlanWithinRisk: return "no plan within the risk limit";
        case msg::CallHomeReason::kGoalUnreachable: return "goal unreachable";
        case msg::CallHomeReason::kReplansExhausted: return "replans exhausted";
        case msg::CallHomeReason::kInsufficientPower: return "insufficient power";
        case msg::CallHomeReason::kMobilityLost: return "mobility lost";
        case msg::CallHomeReason::kFaultUnrecovered: return "fault unrecovered";
        case msg::CallHomeReason::kPlanNoMethod: return "no plan method remains";
    }
    return "?";
}

bool unhealthy(msg::DriveHealth h) {
    return h == msg::DriveHealth::kFaulted || h == msg::DriveHealth::kFailed || h == msg::DriveHealth::kLost;
}

// "FL ML" for a wheel mask (the wheels' names, space separated).
void wheelNames(std::uint8_t mask, char* out, std::size_t size) {
    std::size_t used = 0;
    out[0] = '\0';
    for (std::size_t w = 0; w < msg::kWheelCount && used + 4 < size; ++w) {
        if (((mask >> w) & 1U) != 0U) {
            const char* name = msg::wheelName(w);
            if (used > 0) {
                out[used++] = ' ';
            }
            for (std::size_t i = 0; name[i] != '\0' && used + 1 < size; ++i) {
                out[used++] = name[i];
            }
            out[used] = '\0';
        }
    }
}

bool hazardsUsable(const msg::KnownHazardsMsg& h) {
    if (h.count > msg::kMaxKnownHazards) {
        return false;
    }
    for (std::size_t i = 0; i < h.count; ++i) {
        const msg::KnownHazard& k = h.hazards[i];
        if (!std::isfinite(k.xM) || !std::isfinite(k.yM) || !std::isfinite(k.radiusM) || !(k.radiusM > 0.0F) ||
            k.radiusM > kMaxHazardRadiusM || k.obstacleId == 0) {
            return false;
        }
    }
    return true;
}

}  // namespace

DeliberativeTask::DeliberativeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables)
    : bus_(bus), events_(events), tables_(tables) {}

core::Status DeliberativeTask::init() {
    core::Status status = bus_.createPipe("delib_fast", kFastPipeDepth, &fastPipe_);
    if (core::isOk(status)) {
        status = bus_.subscribe(fastPipe_, msg::ids::kPoseEstimate);
    }
    if (core::isOk(status)) {
        status = bus_.subscribe(fastPipe_, msg::ids::kDriveStatus);
    }
    if (core::isOk(status)) {
        status = bus_.createPipe("deliberative", kInputPipeDepth, &inputPipe_);
    }
    // Goals come only from the plan executive (PlanGoalMsg): GOTO and the goal
    // list are plans of drive activities it runs (docs/plan_executive.md).
    const core::MsgId inputs[] = {msg::ids::kPlanGoal,    msg::ids::kLegReport,
                                  msg::ids::kDriveModes,
                                  msg::ids::kMode,        msg::ids::kKnownHazards, msg::ids::kMissionHold,
                                  msg::ids::kFaultStatus, msg::ids::kReplanRequest};
    for (const core::MsgId id : inputs) {
        if (core::isOk(status)) {
            status = bus_.subscribe(inputPipe_, id);
        }
    }
    if (!core::isOk(status)) {
        events_.report(events::kInitFailed, core::Severity::kError, "deliberative: init failed (%s): task disabled",
                       core::toString(status));
        return status;
    }
    status_.riskBound = tables_.planner().default_risk_bound;
    status_.riskInForce = status_.riskBound;
    status_.planStatus = static_cast<std::uint8_t>(CcStatus::kNoPlan);
    initialised_ = true;
    return status;
}

void DeliberativeTask::run(const core::FrameContext& frame) {
    if (!initialised_) {
        return;
    }
    const core::TimeNs now = frame.actualStart;
    drainFast();
    recordTrack();
    drainInputs(now);
    const msg::DeliberativeState s = status_.state;
    const bool active = s == msg::DeliberativeState::kWaiting || s == msg::DeliberativeState::kPlanning ||
                        s == msg::DeliberativeState::kExecuting;
    // A hold is fault protection's: a drive under recovery trips the interlock
    // on purpose, and what the hold stops must not count against the mission.
    if (active && autonomous_ && !held_ && mobilityLost()) {
        callHome(msg::CallHomeReason::kMobilityLost, "the drive interlock holds every drive", now);
    } else if (s == msg::DeliberativeState::kWaiting && autonomous_ && !held_ && goalIndex_ < goals_.count &&
               poseUsable(now)) {
        startPlan(now);
    } else if (s == msg::DeliberativeState::kPlanning) {
        stepPlanner(now);
    } else if (s == msg::DeliberativeState::kExecuting && goalUnconfirmed_ && !held_) {
        checkUnconfirmedGoal(now);
    }
    ++runs_;
    if (changed_ || runs_ % kStatusPeriodRuns == 0) {
        publishStatus(now);
    }
}

// ---------------------------------------------------------------------------
// Inputs

void DeliberativeTask::malformed(const char* what, core::MsgId id) {
    ++counters_.malformedInputs;
    if (core::isReportableOccurrence(counters_.malformedInputs)) {
        events_.report(events::kMalformedInput, core::Severity::kError,
                       "deliberative: malformed %s (msg 0x%04x) ignored (%u so far)", what, static_cast<unsigned>(id),
                       static_cast<unsigned>(counters_.malformedInputs));
    }
}

void DeliberativeTask::drainFast() {
    for (std::uint16_t i = 0; i < kFastPipeDepth && core::isOk(bus_.receive(fastPipe_, &inbox_)); ++i) {
        if (inbox_.header.id == msg::ids::kDriveStatus) {
            msg::DriveStatusMsg drives{};
            if (core::isOk(inbox_.decode(&drives))) {
                interlockTripped_ = drives.interlockTripped != 0;
                for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
                    driveHealth_[w] = drives.wheels[w].health;
                }
            } else {
                malformed("drive status", inbox_.header.id);
            }
            continue;
        }
        msg::PoseEstimateMsg pose{};
        bool ok = core::isOk(inbox_.decode(&pose)) && std::isfinite(pose.xM) && std::isfinite(pose.yM) &&
                  std::isfinite(pose.headingRad);
        for (double c : pose.covariance) {
            ok = ok && std::isfinite(c);
        }
        if (!ok) {
            malformed("pose estimate", inbox_.header.id);
            continue;
        }
        pose_ = pose;
        poseSeen_ = true;
    }
}

void DeliberativeTask::drainInputs(core::TimeNs now) {
    for (std::uint16_t i = 0; i < kInputPipeDepth && core::isOk(bus_.receive(inputPipe_, &inbox_)); ++i) {
        switch (inbox_.header.id) {
            case msg::ids::kMode: {
                msg::ModeMsg mode{};
                if (core::isOk(inbox_.decode(&mode)) && mode.mode < msg::mode::kCount) {
                    onMode(mode, now);
                } else {
                    malformed("mode", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kPlanGoal: {
                // The plan executive's drive activity: the goal list in force
                // (docs/plan_executive.md "Dispatch to the devices").
                msg::PlanGoalMsg goal{};
                if (core::isOk(inbox_.decode(&goal)) && msg::goalListUsable(goal.goals) &&
                    goal.listIndex < msg::kMaxGoals) {
                    onGoals(goal, now);
                } else {
                    malformed("plan goal", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kLegReport: {
                msg::LegReportMsg report{};
                if (core::isOk(inbox_.decode(&report)) &&
                    static_cast<std::uint8_t>(report.state) <= kLargestHabitualState &&
                    static_cast<std::uint8_t>(report.violated) <= kLargestConstraint) {
                    onLegReport(report, now);
                } else {
                    malformed("leg report", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kDriveModes: {
                msg::DriveModesMsg modes{};
                if (core::isOk(inbox_.decode(&modes))) {
                    modes_ = modes;
                    modesSeen_ = true;
                    noteFailedSince(now);
                } else {
                    malformed("drive modes", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kKnownHazards: {
                msg::KnownHazardsMsg hazards{};
                if (core::isOk(inbox_.decode(&hazards)) && hazardsUsable(hazards)) {
                    onHazards(hazards, now);
                } else {
                    malformed("known hazards", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kMissionHold: {
                msg::MissionHoldMsg hold{};
                if (core::isOk(inbox_.decode(&hold)) && msg::holdUsable(hold)) {
                    onHold(hold, now);
                } else {
                    malformed("mission hold", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kFaultStatus: {
                msg::FaultStatusMsg faults{};
                if (core::isOk(inbox_.decode(&faults))) {
                    faults_ = faults;
                } else {
                    malformed("fault status", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kReplanRequest: {
                msg::ReplanRequestMsg request{};
                if (core::isOk(inbox_.decode(&request)) && request.faultId == msg::fault::kOffMap &&
                    request.attempt >= 1) {
                    onReplanRequest(request, now);
                } else {
                    malformed("replan request", inbox_.header.id);
                }
                break;
            }
            default:
                malformed("message", inbox_.header.id);
                break;
        }
    }
}

bool DeliberativeTask::poseUsable(core::TimeNs now) const {
    return poseSeen_ && pose_.initialised != 0 && now - pose_.timeNs <= kPoseMaxAgeNs;
}

double DeliberativeTask::meanFactor() const {
    if (!modesSeen_) {
        return 1.0;
    }
    return rover_model::meanPowerFactor(modes_, static_cast<double>(tables_.habitual().failed_drive_power_factor));
}

std::uint8_t DeliberativeTask::failedDrives(bool withUnknown) const {
    std::uint8_t mask = 0;
    for (std::size_t w = 0; modesSeen_ && w < msg::kWheelCount; ++w) {
        const msg::DriveMode m = modes_.drives[w].declared;
        if (m == msg::DriveMode::kFailed || (withUnknown && m == msg::DriveMode::kUnknown)) {
            mask = static_cast<std::uint8_t>(mask | (1U << w));
        }
    }
    return mask;
}

// Only a latched interlock stops every wheel. A drive the mode estimator
// declares failed while its wheels are free (a locked wheel dragged, or a
// fault report fault protection has already reset) is planned with
// HABITUAL.failed_drive_power_factor: the legs' energy and power bounds grow,
// and a leg that cannot meet them fails up and is relaxed or replanned as any
// other. An interlock latched only on drives the estimator declares failed
// (fault protection gave them up) is the layer's to decide: it goes on with
// them failed in its model, and calls home with the reason its planning gives
// (mobility lost when a plan is found: no drive is isolated yet). A drive the
// estimator cannot tell (unknown) is planned as failed but leaves mobility
// lost: nothing says its wheel has stopped.
// Since when each drive has been declared failed or unknown without a break
// (0: it is not). A resettable drive fault reads as failed for an update or
// two after its reset (the window held the fault report); the plans' failed
// drive model waits PLANNER.failed_drive_confirm_s for a declaration to last.
void DeliberativeTask::noteFailedSince(core::TimeNs now) {
    const std::uint8_t failed = failedDrives(true);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (((failed >> w) & 1U) == 0U) {
            failedSinceNs_[w] = 0;
        } else if (failedSinceNs_[w] == 0) {
            failedSinceNs_[w] = now > 0 ? now : 1;
        }
    }
}

std::uint8_t DeliberativeTask::confirmedFailedDrives(core::TimeNs now) const {
    const auto confirm =
        static_cast<core::TimeNs>(static_cast<double>(tables_.planner().failed_drive_confirm_s) * 1e9);
    std::uint8_t mask = 0;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (failedSinceNs_[w] != 0 && now - failedSinceNs_[w] >= confirm) {
            mask = static_cast<std::uint8_t>(mask | (1U << w));
        }
    }
    return mask;
}

bool DeliberativeTask::mobilityLost() const {
    if (!interlockTripped_) {
        return false;
    }
    const std::uint8_t failed = failedDrives(false);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (unhealthy(driveHealth_[w]) && ((failed >> w) & 1U) == 0U) {
            return true;
        }
    }
    return failed == 0;
}

void DeliberativeTask::onGoals(const msg::PlanGoalMsg& goal, core::TimeNs now) {
    const msg::GoalListMsg& goals = goal.goals;
    if (goalsSeen_ && goals.revision == goals_.revision) {
        return;
    }
    goals_ = goals;
    listIndex_ = goal.listIndex;
    goalsSeen_ = true;
    changed_ = true;  // PlanStatusMsg.goalRevision: the new list is in force
    goalIndex_ = 0;
    riskFactor_ = 1.0;
    goalReplans_ = 0;
    goalUnconfirmed_ = false;
    powerRelax_ = 1.0;
    replanRequest_.pending = false;
    backingUp_ = false;
    goalBackUps_ = 0;
    ++counters_.goalListsAdopted;
    cancelLeg(now);
    status_.callHome = msg::CallHomeReason::kNone;
    status_.riskInForce = goals.riskBound;
    plan_ = CcPlan{};  // PLAN shows "no plan" until the new goal is planned
    planGap_ = 1.0;
    legs_ = LegPlan{};
    legIndex_ = 0;
    setState(goals.count == 0 ? msg::DeliberativeState::kIdle : msg::DeliberativeState::kWaiting);
    events_.report(events::kGoalsChanged, core::Severity::kInfo,
                   "deliberative: goal list rev %u: %u goal(s), risk bound %.3g: %s", static_cast<unsigned>(goals.revision),
                   static_cast<unsigned>(goals.count), goals.riskBound,
                   goals.count == 0 ? "idle" : (autonomous_ ? "planning" : "planning once AUTONOMOUS"));
}

void DeliberativeTask::onMode(const msg::ModeMsg& mode, core::TimeNs now) {
    const bool was = autonomous_;
    autonomous_ = mode.mode == msg::mode::kAutonomous;
    if (!was || autonomous_) {
        return;
    }
    const msg::DeliberativeState s = status_.state;
    goalUnconfirmed_ = false;
    backingUp_ = false;
    if (s == msg::DeliberativeState::kPlanning || s == msg::DeliberativeState::kExecuting) {
        cancelLeg(now);
        setState(msg::DeliberativeState::kWaiting);
        events_.report(events::kLeftAutonomous, core::Severity::kInfo,
                       "deliberative: left AUTONOMOUS (mode %u): plan dropped, goal %u replanned when back",
                       static_cast<unsigned>(mode.mode), static_cast<unsigned>(goalNumber()));
    }
}

void DeliberativeTask::onLegReport(const msg::LegReportMsg& report, core::TimeNs now) {
    if (status_.state != msg::DeliberativeState::kExecuting || leg_.legId == 0 || report.legId != leg_.legId) {
        return;  // about an older leg, or the 1 Hz repeat of one already handled
    }
    if (report.state == msg::HabitualState::kAchieved && backingUp_) {
        backingUp_ = false;
        // The track now ends where the back-up did: a further back-up goes on
        // back, not over the ground just reversed along.
        trackCount_ = backUpKeep_ < trackCount_ ? backUpKeep_ : trackCount_;
        recordTrack();
        leg_.legId = 0;
        changed_ = true;
        events_.report(events::kBackedUp, core::Severity::kInfo,
                       "deliberative: backed up to (%.2f, %.2f) (%u of %u): replanning goal %u from there", pose_.xM,
                       pose_.yM, static_cast<unsigned>(goalBackUps_),
                       static_cast<unsigned>(tables_.planner().no_path_backup_limit),
                       static_cast<unsigned>(goalNumber()));
        captureReplanRequest(msg::LegConstraint::kNoPath, now);
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    if (report.state == msg::HabitualState::kAchieved) {
        ++counters_.legsAchieved;
        events_.report(events::kLegAchieved, core::Severity::kInfo, "deliberative: leg %u reached (%u of %u)",
                       static_cast<unsigned>(leg_.legId), static_cast<unsigned>(legIndex_ + 1),
                       static_cast<unsigned>(legs_.count));
        leg_.legId = 0;
        ++legIndex_;
        legBoundFactor_ = legEnergyFactor_ = legLengthFactor_ = 1.0;
        changed_ = true;
        if (legIndex_ < legs_.count) {
            sendLeg(now);
            return;
        }
        goalReached();
        return;
    }
    const bool refused = report.state == msg::HabitualState::kIdle && report.violated == msg::LegConstraint::kBadLeg;
    if (report.state == msg::HabitualState::kFailedUp || refused) {
        if (held_) {
            ++counters_.failUpsWhileHeld;
            events_.report(events::kFailUpWhileHeld, core::Severity::kInfo,
                           "deliberative: leg %u failed up (%s) during a hold (reasons 0x%x): ignored, re-sent on release",
                           static_cast<unsigned>(report.legId), constraintName(report.violated),
                           static_cast<unsigned>(holdReasons_));
            return;
        }
        onFailUp(report, now);
    }
}

bool DeliberativeTask::poseUncertain() const {
    const bool faulted = ((faults_.activeMask >> msg::fault::kPoseUncertain) & 1U) != 0U;
    const double limit = static_cast<double>(tables_.estimatorNoise().pose_fault_sigma_m);
    return faulted || !poseSeen_ || pose_.initialised == 0 || !(pose_.positionSigmaM <= limit);
}

void DeliberativeTask::goalReached() {
    const msg::Goal& goal = goals_.goals[goalIndex_];
    if (poseUncertain()) {
        if (!goalUnconfirmed_) {
            ++counters_.goalsUnconfirmed;
            events_.report(events::kGoalUnconfirmed, core::Severity::kWarning,
                           "deliberative: goal %u (%.2f, %.2f): last leg reached but the pose is uncertain (sigma "
                           "%.2f m%s): not claimed, waiting",
                           static_cast<unsigned>(goalNumber()), goal.xM, goal.yM, pose_.positionSigmaM,
                           ((faults_.activeMask >> msg::fault::kPoseUncertain) & 1U) != 0U ? ", fault 19" : "");
        }
        goalUnconfirmed_ = true;
        changed_ = true;
        return;
    }
    goalUnconfirmed_ = false;
    ++counters_.goalsReached;
    if (goal.radiusM > 0.0F) {
        events_.report(events::kGoalReached, core::Severity::kInfo,
                       "deliberative: goal %u (%.2f, %.2f) reached within %.2f m (%.2f m off)",
                       static_cast<unsigned>(goalNumber()), goal.xM, goal.yM, goalArrivalM(),
                       std::hypot(pose_.xM - goal.xM, pose_.yM - goal.yM));
    } else {
        events_.report(events::kGoalReached, core::Severity::kInfo, "deliberative: goal %u (%.2f, %.2f) reached",
                       static_cast<unsigned>(goalNumber()), goal.xM, goal.yM);
    }
    ++goalIndex_;
    goalReplans_ = 0;
    goalBackUps_ = 0;
    riskFactor_ = 1.0;
    if (goalIndex_ < goals_.count) {
        setState(msg::DeliberativeState::kWaiting);
    } else {
        setState(msg::DeliberativeState::kComplete);
        events_.report(events::kMissionComplete, core::Severity::kInfo, "deliberative: every goal reached (%u)",
                       static_cast<unsigned>(goals_.count));
    }
}

void DeliberativeTask::checkUnconfirmedGoal(core::TimeNs now) {
    if (poseUncertain()) {
        return;
    }
    const msg::Goal& goal = goals_.goals[goalIndex_];
    const double off = std::hypot(pose_.xM - goal.xM, pose_.yM - goal.yM);
    if (off <= goalArrivalM()) {
        goalReached();
        return;
    }
    goalUnconfirmed_ = false;
    ++counters_.goalLegsResent;
    events_.report(events::kGoalLegResent, core::Severity::kWarning,
                   "deliberative: goal %u: pose certain again %.2f m from the goal: last leg re-sent from (%.2f, %.2f)",
                   static_cast<unsigned>(goalNumber()), off, pose_.xM, pose_.yM);
    legIndex_ = legs_.count > 0 ? legs_.count - 1 : 0;
    resendFromPose(now);
}

double DeliberativeTask::goalArrivalM() const {
    const double radius = goalIndex_ < goals_.count ? static_cast<double>(goals_.goals[goalIndex_].radiusM) : 0.0;
    return msg::arrivalRadiusM(static_cast<double>(tables_.habitual().goal_tolerance_m), radius);
}

LegParams DeliberativeTask::legParams() const {
    const tables::HabitualTable& habitual = tables_.habitual();
    const tables::PlannerTable& planner = tables_.planner();
    LegParams params;
    params.spacingM = static_cast<double>(planner.waypoint_spacing_m);
    params.slackFrac = static_cast<double>(planner.leg_slack_frac);
    params.distanceMarginFrac = static_cast<double>(habitual.distance_margin_frac);
    params.powerMarginFrac = static_cast<double>(habitual.power_margin_frac);
    params.powerSlackFrac = static_cast<double>(planner.leg_power_slack_frac);
    params.cruiseSpeedMS = static_cast<double>(habitual.cruise_speed_m_s);
    params.power = rover_model::powerModelFrom(habitual);
    params.meanPowerFactor = meanFactor();
    params.headingRad = pose_.headingRad;
    return params;
}

void DeliberativeTask::resendFromPose(core::TimeNs now) {
    if (status_.state == msg::DeliberativeState::kExecuting && backingUp_) {
        sendBackUpLeg(now);
        return;
    }
    if (status_.state != msg::DeliberativeState::kExecuting || legIndex_ >= legs_.count) {
        return;
    }
    msg::PlanLeg& leg = legs_.legs[legIndex_];
    (void)legBoundsFrom(pose_.xM, pose_.yM, pose_.headingRad, legParams(), &leg);
    // The bounds are new (from here), the relaxation the leg earned is not:
    // losing it fails the re-sent leg up again at once.
    leg.energyJ *= legEnergyFactor_;
    leg.lengthM *= legLengthFactor_;
    leg_.legId = 0;
    sendLeg(now);
}

bool DeliberativeTask::legEndTooClose(const msg::PlanLeg& leg) const {
    const double clearance = rse::geometry::clearanceRadiusM(tables_.roverGeometry()) + kLegEndMarginM;
    // The plan keeps its means off the grown polygons only with the chance
    // margin of the moment, and a polygon grown less for a close start keeps
    // less: an end the habitual layer could reach only without its planning
    // margin is not handed to it.
    if (geometry::distanceToCoarseMap(tables_.coarseMap(), geometry::Point2{leg.xM, leg.yM}) < clearance) {
        return true;
    }
    for (std::size_t i = 0; i < hazards_.count && i < msg::kMaxKnownHazards; ++i) {
        const msg::KnownHazard& h = hazards_.hazards[i];
        const double reach = static_cast<double>(h.radiusM) + clearance;
        const double dx = leg.xM - static_cast<double>(h.xM);
        const double dy = leg.yM - static_cast<double>(h.yM);
        if (dx * dx + dy * dy < reach * reach) {
            return true;
        }
    }
    return false;
}

bool DeliberativeTask::skipLegEndsInHazards() {
    bool moved = false;
    while (legIndex_ + 1 < legs_.count && legEndTooClose(legs_.legs[legIndex_])) {
        const msg::PlanLeg skipped = legs_.legs[legIndex_];
        msg::PlanLeg& next = legs_.legs[legIndex_ + 1];
        next.lengthM += skipped.lengthM;
        next.energyJ += skipped.energyJ;
        next.risk += skipped.risk;
        legs_.plannedLengthM[legIndex_ + 1] += legs_.plannedLengthM[legIndex_];
        ++legIndex_;
        ++counters_.legEndsSkipped;
        moved = true;
        events_.report(events::kLegEndSkipped, core::Severity::kWarning,
                       "deliberative: leg end (%.2f, %.2f) too near a rock: merged into leg %u of %u (to (%.2f, %.2f))",
                       skipped.xM, skipped.yM, static_cast<unsigned>(legIndex_ + 1), static_cast<unsigned>(legs_.count),
                       next.xM, next.yM);
    }
    return moved;
}

void DeliberativeTask::onHazards(const msg::KnownHazardsMsg& hazards, core::TimeNs now) {
    hazards_ = hazards;
    ++counters_.hazardMaps;
    // The leg in force may end inside what was just seen: the habitual layer
    // could only fail up on it, so move on to the next leg end now.
    if (status_.state == msg::DeliberativeState::kExecuting && leg_.legId != 0 && !held_ && !backingUp_ &&
        legIndex_ + 1 < legs_.count && legEndTooClose(legs_.legs[legIndex_])) {
        leg_.legId = 0;
        sendLeg(now);
    }
}

void DeliberativeTask::onHold(const msg::MissionHoldMsg& hold, core::TimeNs now) {
    holdReasons_ = hold.reasons;
    if (hold.reasons != 0U) {
        if (!held_) {
            held_ = true;
            ++counters_.holds;
            changed_ = true;
            events_.report(events::kMissionHeld, core::Severity::kWarning,
                           "deliberative: mission held (reasons 0x%x%s): no new legs, leg %u kept",
                           static_cast<unsigned>(hold.reasons), hold.estop != 0 ? ", e-stop" : "",
                           static_cast<unsigned>(leg_.legId));
        }
        resumeCount_ = hold.resumeCount;
        return;
    }
    // Reasons 0 is the release whether or not resumeCount moved: a lost or
    // inconsistent count must not leave the mission held for good.
    const bool wasHeld = held_;
    held_ = false;
    resumeCount_ = hold.resumeCount;
    if (!wasHeld) {
        return;
    }
    ++counters_.resumes;
    changed_ = true;
    const bool driving = status_.state == msg::DeliberativeState::kExecuting && !goalUnconfirmed_ &&
                         legIndex_ < legs_.count;
    events_.report(events::kMissionResumed, core::Severity::kInfo,
                   "deliberative: hold released (resume %u): %s", static_cast<unsigned>(hold.resumeCount),
                   driving ? "current leg re-sent from the current pose" : "nothing to re-send");
    if (driving) {
        resendFromPose(now);
    }
}

void DeliberativeTask::onReplanRequest(const msg::ReplanRequestMsg& request, core::TimeNs now) {
    const msg::DeliberativeState s = status_.state;
    const bool active = s == msg::DeliberativeState::kWaiting || s == msg::DeliberativeState::kPlanning ||
                        s == msg::DeliberativeState::kExecuting;
    if (!active || !autonomous_ || goalIndex_ >= goals_.count) {
        ++counters_.offMapIgnored;
        events_.report(events::kOffMapReplan, core::Severity::kWarning,
                       "deliberative: off the map at (%.2f, %.2f), try %u: no mission to replan (state %u%s)",
                       pose_.xM, pose_.yM, static_cast<unsigned>(request.attempt), static_cast<unsigned>(s),
                       autonomous_ ? "" : ", not AUTONOMOUS");
        return;
    }
    ++counters_.offMapReplans;
    ++counters_.replans;  // a replan in PLAN telemetry; not one of the goal's replan_limit
    // The waypoint in force led off the map (or the rover was carried off):
    // it is dropped, whatever the leg was doing, and the goals planned again
    // from where the rover stands. A plan under way started from elsewhere.
    cancelLeg(now);
    backingUp_ = false;
    goalUnconfirmed_ = false;
    captureReplanRequest(msg::LegConstraint::kNone, now);
    setState(msg::DeliberativeState::kWaiting);
    changed_ = true;
    const ReplanRequest& rr = replanRequest_;
    events_.report(events::kOffMapReplan, core::Severity::kWarning,
                   "deliberative: off the map at (%.2f, %.2f), try %u: waypoint cancelled, replan %s",
                   rr.xM, rr.yM, static_cast<unsigned>(request.attempt), held_ ? "after hold" : "from here");
}

void DeliberativeTask::onFailUp(const msg::LegReportMsg& report, core::TimeNs now) {
    ++counters_.failUps;
    if (backingUp_) {
        backingUp_ = false;
        callHome(msg::CallHomeReason::kReplansExhausted, "the back-up failed up", now);
        return;
    }
    const bool power = report.violated == msg::LegConstraint::kPower;
    const bool energy = report.violated == msg::LegConstraint::kEnergy;
    const double predictedFigure =
        power ? report.predictedPowerW : (energy ? report.predictedEnergyJ : report.predictedLengthM);
    const double allowedFigure = power ? report.allowedPowerW : (energy ? report.allowedEnergyJ : report.allowedLengthM);
    events_.report(events::kFailUpReceived, core::Severity::kWarning,
                   "deliberative: leg %u failed up: %s (predicted %.1f, allowed %.1f, excess %.1f)",
                   static_cast<unsigned>(report.legId), constraintName(report.violated), predictedFigure,
                   allowedFigure, report.excess);
    if (power) {
        // The drives' power is the same on every leg: the bound grows for the
        // rest of the plan, within the same limit as a leg's other bounds.
        const double needed = predictedFigure / allowedFigure * kBoundRelaxHeadroom;
        const double grown = powerRelax_ * needed;
        const double limit = static_cast<double>(tables_.planner().bound_relax_limit);
        if (std::isfinite(needed) && allowedFigure > 0.0 && needed > 1.0 && grown <= limit) {
            powerRelax_ = grown;
            ++counters_.boundRelaxations;
            ++counters_.powerRelaxations;
            events_.report(events::kBoundRelaxed, core::Severity::kWarning,
                           "deliberative: leg %u power bound relaxed x%.3f to %.0f W (x%.3f of planned, limit x%.2f): "
                           "resent",
                           static_cast<unsigned>(leg_.legId), needed, legs_.legs[legIndex_].powerW * powerRelax_,
                           grown, limit);
            leg_.legId = 0;
            sendLeg(now);
            return;
        }
        replan(report.violated, now);
        return;
    }
    if (energy || report.violated == msg::LegConstraint::kPathLength) {
        const double predicted = energy ? report.predictedEnergyJ : report.predictedLengthM;
        const double allowed = energy ? report.allowedEnergyJ : report.allowedLengthM;
        const double needed = predicted / allowed * kBoundRelaxHeadroom;
        const double grown = legBoundFactor_ * needed;
        const double limit = static_cast<double>(tables_.planner().bound_relax_limit);
        if (std::isfinite(needed) && allowed > 0.0 && needed > 1.0 && grown <= limit) {
            msg::PlanLeg& leg = legs_.legs[legIndex_];
            (energy ? leg.energyJ : leg.lengthM) *= needed;
            (energy ? legEnergyFactor_ : legLengthFactor_) *= needed;
            legBoundFactor_ = grown;
            ++counters_.boundRelaxations;
            events_.report(events::kBoundRelaxed, core::Severity::kWarning,
                           "deliberative: leg %u %s bound relaxed x%.3f (x%.3f of planned, limit x%.2f): resent",
                           static_cast<unsigned>(leg_.legId), constraintName(report.violated), needed, grown, limit);
            leg_.legId = 0;
            sendLeg(now);
            return;
        }
    }
    replan(report.violated, now);
}

// ---------------------------------------------------------------------------
// Planning

void DeliberativeTask::startPlan(core::TimeNs now) {
    const tables::PlannerTable& planner = tables_.planner();
    const msg::Goal& goal = goals_.goals[goalIndex_];
    PlanRequest request;
    ReplanRequest& rr = replanRequest_;
    const bool replanning = rr.pending;
    if (replanning && now - rr.poseTimeNs > kReplanMaxAgeNs) {
        // Too old to start from: the rover may stand elsewhere now.
        rr.poseTimeNs = pose_.timeNs;
        rr.xM = pose_.xM;
        rr.yM = pose_.yM;
        rr.headingRad = pose_.headingRad;
        rr.cov[0] = pose_.covariance[0];
        rr.cov[1] = pose_.covariance[1];
        rr.cov[2] = pose_.covariance[3];
        rr.cov[3] = pose_.covariance[4];
    }
    rr.pending = false;
    request.startX = replanning ? rr.xM : pose_.xM;
    request.startY = replanning ? rr.yM : pose_.yM;
    request.startCov[0] = replanning ? rr.cov[0] : pose_.covariance[0];
    request.startCov[1] = replanning ? rr.cov[1] : pose_.covariance[1];
    request.startCov[2] = replanning ? rr.cov[2] : pose_.covariance[3];
    request.startCov[3] = replanning ? rr.cov[3] : pose_.covariance[4];
    // A start off the planning site (off the map, or pushed against its edge)
    // has no plan: plan from the nearest point well on it instead; the
    // habitual layer drives the rover there on the first leg.
    const geometry::SiteBox planSite = planningSite(tables_.coarseMap(), tables_.roverGeometry());
    const geometry::SiteBox reentrySite =
        geometry::siteBox(tables_.coarseMap(), rse::geometry::clearanceRadiusM(tables_.roverGeometry()) + kReentryInsetM);
    double inX = request.startX;
    double inY = request.startY;
    fromReentry_ = geometry::outsideBy(planSite, request.startX, request.startY) > 0.0 &&
                   geometry::nearestInside(reentrySite, request.startX, request.startY, &inX, &inY);
    if (fromReentry_) {
        ++counters_.reentryPlans;
        events_.report(events::kPlannedFromReentry, core::Severity::kWarning,
                       "deliberative: start (%.2f, %.2f) off the site: planned from (%.2f, %.2f) (%.2f m)",
                       request.startX, request.startY, inX, inY, std::hypot(inX - request.startX, inY - request.startY));
        request.startX = inX;
        request.startY = inY;
    }
    request.hazards = hazards_.hazards;
    request.hazardCount = hazards_.count;
    request.goalX = goal.xM;
    request.goalY = goal.yM;
    request.riskBound = riskInForce();
    // The motor loss in the state estimate: a drive the mode estimator
    // declares failed (or cannot tell) is planned as failed - its power factor
    // in the legs' bounds (legParams) and, once the declaration has lasted
    // PLANNER.failed_drive_confirm_s, a rover that tracks its path worse.
    const std::uint8_t failed = confirmedFailedDrives(now);
    request.noiseFactor = failed != 0U ? static_cast<double>(planner.failed_drive_noise_factor) : 1.0;
    MapProblemReport report;
    if (!core::isOk(buildMapProblem(tables_.coarseMap(), planner, tables_.roverGeometry(), request, &problem_,
                                    &report))) {
        ++counters_.problemsRefused;
        events_.report(events::kProblemRefused, core::Severity::kError,
                       "deliberative: goal %u (%.2f, %.2f) from (%.2f, %.2f): %s", static_cast<unsigned>(goalNumber()),
                       goal.xM, goal.yM, request.startX, request.startY, toString(report.error));
        callHome(msg::CallHomeReason::kGoalUnreachable, toString(report.error), now);
        return;
    }
    if (report.obstaclesDropped > 0) {
        ++counters_.obstaclesDropped;
        events_.report(events::kDroppedObstacles, core::Severity::kWarning,
                       "deliberative: %u of %u coarse-map obstacles left out (farthest from the line; the habitual "
                       "layer still avoids them)",
                       static_cast<unsigned>(report.obstaclesDropped), static_cast<unsigned>(report.obstaclesOnMap));
    }
    if (!core::isOk(planner_.start(problem_, plannerParams()))) {
        ++counters_.problemsRefused;
        events_.report(events::kProblemRefused, core::Severity::kError,
                       "deliberative: planner refused the problem of goal %u", static_cast<unsigned>(goalNumber()));
        callHome(msg::CallHomeReason::kGoalUnreachable, "planner refused the problem", now);
        return;
    }
    // The last plan found is a seed for this one when it went to the same goal
    // among the same obstacles: a replan, or the operator's bound changed
    // (issue 15 item 5: a tighter bound's search cut short by the budget gave
    // a route 1 m longer than the looser bound's). The planner re-solves its
    // faces at this problem's margins and keeps it only if it verifies.
    bool seeded = last_.valid && last_.goalX == problem_.goalX && last_.goalY == problem_.goalY &&
                  last_.obstacleCount == problem_.obstacleCount;
    for (std::size_t i = 0; i < problem_.obstacleCount && seeded; ++i) {
        seeded = problem_.obstacles[i].id == last_.obstacleIds[i];
    }
    seeded = seeded && core::isOk(planner_.setSeedHint(last_.plan));
    counters_.seededPlans += seeded ? 1U : 0U;
    seededPlan_ = seeded;
    wideSearch_ = false;
    ++counters_.plansStarted;
    slices_ = 0;
    status_.riskInForce = request.riskBound;
    setState(msg::DeliberativeState::kPlanning);
    if (failed != plannedFailedMask_) {
        plannedFailedMask_ = failed;
        ++counters_.failedDriveModels;
        char names[32];
        wheelNames(failed, names, sizeof names);
        events_.report(events::kFailedDriveModel, core::Severity::kWarning,
                       "deliberative: drive estimate: %s%s: plans at power factor %.2f, noise %.3f m/step",
                       failed != 0U ? names : "every drive", failed != 0U ? " failed" : " back", meanFactor(),
                       problem_.processSigmaM);
    }
    events_.report(events::kPlanStarted, core::Severity::kInfo,
                   "deliberative: plan goal %u (%.2f, %.2f) from (%.2f, %.2f), risk %.3g, %u obstacles, %u seen%s",
                   static_cast<unsigned>(goalNumber()), goal.xM, goal.yM, request.startX, request.startY,
                   request.riskBound, static_cast<unsigned>(problem_.obstacleCount),
                   static_cast<unsigned>(report.hazardsUsed), report.startInObstacle ? ", start inside one" : "");
}

CcPlannerParams DeliberativeTask::plannerParams() const {
    const tables::PlannerTable& planner = tables_.planner();
    CcPlannerParams params;
    params.nodeBudget = planner.node_budget;
    params.workBudget = static_cast<std::uint32_t>(planner.time_budget_ms) * kWorkKUnitsPerMs;
    return params;
}

double DeliberativeTask::riskInForce() const {
    const double risk = goals_.riskBound * riskFactor_;
    return risk < kMaxRiskInForce ? risk : kMaxRiskInForce;
}

void DeliberativeTask::stepPlanner(core::TimeNs now) {
    const std::uint64_t work0 = planner_.work();
    std::uint32_t units = 0;
    while (!planner_.finished() && units < kMaxUnitsPerRun && planner_.work() - work0 < kSliceWork) {
        (void)planner_.step(1);
        ++units;
    }
    const std::uint64_t work = planner_.work() - work0;
    counters_.maxRunWork = work > counters_.maxRunWork ? work : counters_.maxRunWork;
    counters_.maxRunUnits = units > counters_.maxRunUnits ? units : counters_.maxRunUnits;
    ++counters_.planningRuns;
    ++slices_;
    if (planner_.finished()) {
        onPlanFinished(now);
    }
}

void DeliberativeTask::onPlanFinished(core::TimeNs now) {
    plan_ = planner_.plan();
    planGap_ = 1.0;
    const bool hasPath = plan_.status == CcStatus::kOptimal || plan_.status == CcStatus::kFeasible;
    if (hasPath) {
        last_.valid = true;
        last_.plan = plan_;
        last_.goalX = problem_.goalX;
        last_.goalY = problem_.goalY;
        last_.obstacleCount = problem_.obstacleCount;
        for (std::size_t i = 0; i < problem_.obstacleCount; ++i) {
            last_.obstacleIds[i] = problem_.obstacles[i].id;
        }
    }
    if (hasPath && interlockTripped_) {
        // Only drives declared failed hold the interlock (else mobilityLost()
        // called home already): a plan fits with them failed, but the rover
        // cannot drive on the others until they are isolated, which no layer
        // does yet.
        ++counters_.plansFound;
        publishPlanPath(now);
        callHome(msg::CallHomeReason::kMobilityLost, "a plan fits, but the interlock holds every drive", now);
        return;
    }
    if (hasPath) {
        const LegParams params = legParams();
        if (core::isOk(splitPlanIntoLegs(plan_, params, &legs_)) && legs_.count > 0) {
            ++counters_.plansFound;
            publishPlanPath(now);
            // A budget plan is not an optimum: say how far it may be off
            // (issue 15 item 5), from the search's proven lower bound.
            const double best = planner_.evenSplitCost();
            const double gap = std::isfinite(best) && best > 0.0 ? (best - planner_.lowerBound()) / best : 1.0;
            planGap_ = gap < 0.0 ? 0.0 : (gap > 1.0 ? 1.0 : gap);
            const bool budget = plan_.status != CcStatus::kOptimal;
            counters_.budgetPlans += budget ? 1U : 0U;
            counters_.wideSearchPlans += wideSearch_ ? 1U : 0U;
            // Most important first: kEventTextSize keeps 95 characters.
            events_.report(events::kPlanFound, core::Severity::kInfo,
                           "deliberative: %s plan%s, gap %.1f%%: %.2f m, risk %.3g/%.3g, %u legs, %u nodes",
                           budget ? "BUDGET" : "optimal", seededPlan_ ? ", seeded" : "", 100.0 * planGap_,
                           plan_.euclideanLengthM, plan_.riskUsed, problem_.riskBound,
                           static_cast<unsigned>(legs_.count), static_cast<unsigned>(planner_.nodes()));
            legIndex_ = 0;
            legBoundFactor_ = legEnergyFactor_ = legLengthFactor_ = 1.0;
            powerRelax_ = 1.0;  // the new legs are bounded at the power factors of the moment
            if (fromReentry_) {
                widenFirstLegFromPose(params);
            }
            setState(msg::DeliberativeState::kExecuting);
            sendLeg(now);
            return;
        }
    }
    if (!wideSearch_ && problem_.allocation == RiskAllocation::kOptimised && problem_.obstacleCount > 0) {
        // Boole's even split refused it; a plan may still certify within the
        // bound (cc_planner.hpp, "Risk allocation"): one wider search first.
        const bool proven = planner_.searchExhausted();
        CcPlannerParams params = plannerParams();
        params.searchRiskScale = kWideSearchScale;
        if (core::isOk(planner_.start(problem_, params))) {
            wideSearch_ = true;
            ++counters_.wideSearches;
            events_.report(events::kWideSearch, core::Severity::kInfo,
                           "deliberative: no plan within Boole's bound at %.3g (%s): search x%.0f, certify at %.3g",
                           problem_.riskBound, proven ? "proven" : "budget spent", kWideSearchScale,
                           problem_.riskBound);
            return;
        }
    }
    ++counters_.noPlans;
    events_.report(events::kNoPlan, core::Severity::kWarning,
                   "deliberative: no plan for goal %u within risk %.3g (%s, %u nodes)",
                   static_cast<unsigned>(goalNumber()), problem_.riskBound,
                   planner_.searchExhausted() ? "proven" : "budget spent", static_cast<unsigned>(planner_.nodes()));
    const double limit = static_cast<double>(tables_.planner().risk_relax_limit);
    if (riskFactor_ < limit && problem_.riskBound < kMaxRiskInForce) {
        const double next = riskFactor_ * kRiskRelaxStep;
        riskFactor_ = next < limit ? next : limit;
        ++counters_.riskRelaxations;
        // The value the next plan uses, cap included (it said "relaxed to 1"
        // for an operator's 0.1 while 0.49 was planned to).
        const double relaxed = riskInForce();
        const bool capped = goals_.riskBound * riskFactor_ > relaxed;
        events_.report(events::kRiskRelaxed, core::Severity::kWarning,
                       "deliberative: risk bound relaxed to %.3g (the operator's %.3g x%.3g%s, limit x%.3g)", relaxed,
                       goals_.riskBound, relaxed / goals_.riskBound, capped ? ", capped below 0.5" : "", limit);
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    callHome(msg::CallHomeReason::kNoPlanWithinRisk, "no plan at the relaxed risk limit", now);
}

void DeliberativeTask::widenFirstLegFromPose(const LegParams& params) {
    // The plan starts at the re-entry point; the rover drives there first, so
    // the first leg gets the bounds from where it stands when they are larger.
    msg::PlanLeg& first = legs_.legs[0];
    msg::PlanLeg fromRover = first;
    if (core::isOk(legBoundsFrom(pose_.xM, pose_.yM, pose_.headingRad, params, &fromRover))) {
        first.lengthM = fromRover.lengthM > first.lengthM ? fromRover.lengthM : first.lengthM;
        first.energyJ = fromRover.energyJ > first.energyJ ? fromRover.energyJ : first.energyJ;
    }
}

void DeliberativeTask::replan(msg::LegConstraint why, core::TimeNs now) {
    leg_.legId = 0;
    const std::uint32_t limit = tables_.planner().replan_limit;
    if (goalReplans_ >= limit) {
        if (why == msg::LegConstraint::kNoPath && startBackUp(now)) {
            return;
        }
        callHome(why == msg::LegConstraint::kEnergy || why == msg::LegConstraint::kPower
                     ? msg::CallHomeReason::kInsufficientPower
                     : msg::CallHomeReason::kReplansExhausted,
                 constraintName(why), now);
        return;
    }
    ++goalReplans_;
    ++counters_.replans;
    captureReplanRequest(why, now);
    const ReplanRequest& rr = replanRequest_;
    events_.report(events::kReplan, core::Severity::kWarning,
                   "deliberative: replan %u/%u (%s) t=%.2f s from (%.2f, %.2f): goals %u..%u left, %u hazards",
                   static_cast<unsigned>(goalReplans_), static_cast<unsigned>(limit), constraintName(why),
                   static_cast<double>(now) / static_cast<double>(core::kNsPerSec), rr.xM, rr.yM,
                   static_cast<unsigned>(rr.firstGoal), static_cast<unsigned>(rr.firstGoal + rr.unfinished - 1),
                   static_cast<unsigned>(hazards_.count));
    setState(msg::DeliberativeState::kWaiting);
}

void DeliberativeTask::captureReplanRequest(msg::LegConstraint why, core::TimeNs now) {
    ReplanRequest& rr = replanRequest_;
    rr.timeNs = now;
    rr.poseTimeNs = pose_.timeNs;
    rr.xM = pose_.xM;
    rr.yM = pose_.yM;
    rr.headingRad = pose_.headingRad;
    rr.cov[0] = pose_.covariance[0];
    rr.cov[1] = pose_.covariance[1];
    rr.cov[2] = pose_.covariance[3];
    rr.cov[3] = pose_.covariance[4];
    rr.firstGoal = goalIndex_;
    rr.unfinished = static_cast<std::uint8_t>(goals_.count > goalIndex_ ? goals_.count - goalIndex_ : 0);
    rr.why = why;
    rr.pending = true;
}

void DeliberativeTask::recordTrack() {
    if (backingUp_ || !poseSeen_ || pose_.initialised == 0 || !std::isfinite(pose_.xM) || !std::isfinite(pose_.yM)) {
        return;
    }
    if (trackCount_ > 0) {
        const std::size_t newest = (trackHead_ + trackCount_ - 1) % kTrackPoints;
        if (std::hypot(pose_.xM - trackX_[newest], pose_.yM - trackY_[newest]) < kTrackStepM) {
            return;
        }
    }
    const std::size_t slot = (trackHead_ + trackCount_) % kTrackPoints;
    trackX_[slot] = pose_.xM;
    trackY_[slot] = pose_.yM;
    if (trackCount_ < kTrackPoints) {
        ++trackCount_;
    } else {
        trackHead_ = (trackHead_ + 1) % kTrackPoints;
    }
}

bool DeliberativeTask::backUpTarget(double distanceM, msg::PlanLeg* out, std::size_t* keep) const {
    // Walk back from the pose through the track, newest first; the first point
    // at or beyond distanceM (then every kTrackStepM, up to twice it) that is
    // clear of every seen hazard.
    double fromX = pose_.xM;
    double fromY = pose_.yM;
    double walked = 0.0;
    double want = distanceM;
    const double farthest = 2.0 * distanceM;
    for (std::size_t k = 0; k < trackCount_; ++k) {
        const std::size_t i = (trackHead_ + trackCount_ - 1 - k) % kTrackPoints;
        const double seg = std::hypot(trackX_[i] - fromX, trackY_[i] - fromY);
        // At most farthest / kTrackStepM candidates in all (80 for 10 m).
        for (std::uint32_t c = 0; c < 100 && seg > 0.0 && walked + seg >= want; ++c) {
            const double f = (want - walked) / seg;
            msg::PlanLeg p{};
            p.xM = fromX + f * (trackX_[i] - fromX);
            p.yM = fromY + f * (trackY_[i] - fromY);
            if (!legEndTooClose(p)) {
                *out = p;
                *keep = trackCount_ - 1 - k;  // the points beyond the target are driven back over
                return true;
            }
            want += kTrackStepM;
            if (want > farthest) {
                return false;
            }
        }
        walked += seg;
        fromX = trackX_[i];
        fromY = trackY_[i];
    }
    return false;
}

bool DeliberativeTask::startBackUp(core::TimeNs now) {
    const tables::PlannerTable& planner = tables_.planner();
    const double distance = static_cast<double>(planner.no_path_backup_m);
    msg::PlanLeg target{};
    std::size_t keep = 0;
    if (goalBackUps_ >= planner.no_path_backup_limit || !(distance > 0.0) ||
        !backUpTarget(distance, &target, &keep)) {
        return false;
    }
    backUpKeep_ = keep;
    ++goalBackUps_;
    ++counters_.backUps;
    backingUp_ = true;
    backUpLeg_ = target;
    events_.report(events::kBackingUp, core::Severity::kWarning,
                   "deliberative: no path after %u replans: backing up %.1f m along the track to (%.2f, %.2f), %u of %u",
                   static_cast<unsigned>(goalReplans_), std::hypot(target.xM - pose_.xM, target.yM - pose_.yM),
                   target.xM, target.yM, static_cast<unsigned>(goalBackUps_),
                   static_cast<unsigned>(planner.no_path_backup_limit));
    setState(msg::DeliberativeState::kExecuting);
    sendBackUpLeg(now);
    return true;
}

void DeliberativeTask::sendBackUpLeg(core::TimeNs now) {
    if (held_) {
        leg_ = msg::LegCommandMsg{};
        changed_ = true;
        return;
    }
    (void)legBoundsFrom(pose_.xM, pose_.yM, pose_.headingRad, legParams(), &backUpLeg_);
    leg_ = msg::LegCommandMsg{};
    leg_.timeNs = now;
    leg_.legId = nextLegId_;
    nextLegId_ = nextLegId_ == UINT32_MAX ? 1 : nextLegId_ + 1;
    leg_.finalLeg = 0;
    leg_.goalXM = backUpLeg_.xM;
    leg_.goalYM = backUpLeg_.yM;
    leg_.maxPathLengthM = backUpLeg_.lengthM;
    leg_.maxEnergyJ = backUpLeg_.energyJ;
    // The drives' power is the same on every leg: the plan's power bound.
    leg_.maxPowerW = legs_.count > 0 ? legs_.legs[legIndex_ < legs_.count ? legIndex_ : 0].powerW * powerRelax_ : 0.0;
    published(bus_.publish(leg_), "back-up leg");
    ++counters_.legsSent;
    changed_ = true;
    events_.report(events::kLegSent, core::Severity::kInfo,
                   "deliberative: leg %u (back-up) to (%.2f, %.2f): <= %.2f m, <= %.0f J",
                   static_cast<unsigned>(leg_.legId), backUpLeg_.xM, backUpLeg_.yM, backUpLeg_.lengthM,
                   backUpLeg_.energyJ);
}

// ---------------------------------------------------------------------------
// Outputs

void DeliberativeTask::sendLeg(core::TimeNs now) {
    (void)skipLegEndsInHazards();
    if (held_) {
        // Sent from the pose of the moment when the hold is released.
        leg_ = msg::LegCommandMsg{};
        changed_ = true;
        return;
    }
    const msg::PlanLeg& leg = legs_.legs[legIndex_];
    leg_ = msg::LegCommandMsg{};
    leg_.timeNs = now;
    leg_.legId = nextLegId_;
    nextLegId_ = nextLegId_ == UINT32_MAX ? 1 : nextLegId_ + 1;
    leg_.finalLeg = legIndex_ + 1 == legs_.count ? 1 : 0;
    leg_.goalXM = leg.xM;
    leg_.goalYM = leg.yM;
    leg_.maxPathLengthM = leg.lengthM;
    leg_.maxEnergyJ = leg.energyJ;
    leg_.maxPowerW = leg.powerW * powerRelax_;
    // The goal's last leg ends at the goal: the habitual layer may stop
    // anywhere in its region. Earlier legs end at waypoints, reached as points.
    leg_.arriveWithinM =
        leg_.finalLeg != 0 && goalIndex_ < goals_.count ? static_cast<double>(goals_.goals[goalIndex_].radiusM) : 0.0;
    published(bus_.publish(leg_), "leg");
    ++counters_.legsSent;
    changed_ = true;
    events_.report(events::kLegSent, core::Severity::kInfo,
                   "deliberative: leg %u (%u of %u) to (%.2f, %.2f): <= %.2f m, <= %.0f J, <= %.0f W, risk %.3g",
                   static_cast<unsigned>(leg_.legId), static_cast<unsigned>(legIndex_ + 1),
                   static_cast<unsigned>(legs_.count), leg.xM, leg.yM, leg.lengthM, leg.energyJ, leg_.maxPowerW,
                   leg.risk);
}

void DeliberativeTask::cancelLeg(core::TimeNs now) {
    if (leg_.legId == 0 && status_.state != msg::DeliberativeState::kExecuting) {
        return;
    }
    msg::LegCommandMsg cancel{};
    cancel.timeNs = now;
    published(bus_.publish(cancel), "leg cancel");
    leg_.legId = 0;
}

void DeliberativeTask::callHome(msg::CallHomeReason reason, const char* detail, core::TimeNs now) {
    msg::LegCommandMsg cancel{};
    cancel.timeNs = now;
    published(bus_.publish(cancel), "leg cancel");
    leg_.legId = 0;
    msg::SafeRequestMsg safe{};
    safe.timeNs = now;
    safe.reason = reason;
    published(bus_.publish(safe), "safe request");
    ++counters_.callHomes;
    status_.callHome = reason;
    setState(msg::DeliberativeState::kCalledHome);
    events_.report(events::kCallHome, core::Severity::kCritical,
                   "deliberative: CALL HOME: %s (%s), goal %u, risk bound %.3g: rover safed, waiting for goals",
                   reasonName(reason), detail, static_cast<unsigned>(goalNumber()), goals_.riskBound);
}

void DeliberativeTask::setState(msg::DeliberativeState state) {
    if (status_.state != state) {
        status_.state = state;
        changed_ = true;
    }
}

void DeliberativeTask::published(core::Status status, const char* what) {
    if (core::isOk(status)) {
        return;
    }
    ++counters_.publishFailures;
    if (core::isReportableOccurrence(counters_.publishFailures)) {
        events_.report(events::kPublishFailed, core::Severity::kError, "deliberative: %s not published (%s), %u so far",
                       what, core::toString(status), static_cast<unsigned>(counters_.publishFailures));
    }
}

void DeliberativeTask::publishPlanPath(core::TimeNs now) {
    msg::PlanPathMsg m{};
    m.timeNs = now;
    m.planNumber = counters_.plansFound;
    m.status = static_cast<std::uint8_t>(plan_.status);
    const std::size_t steps = plan_.steps <= kMaxPlanSteps ? plan_.steps : kMaxPlanSteps;
    m.steps = static_cast<std::uint8_t>(steps);
    m.riskBound = problem_.riskBound;
    m.riskUsed = plan_.riskUsed;
    m.lengthM = plan_.euclideanLengthM;
    m.processSigmaM = problem_.processSigmaM;
    for (std::size_t i = 0; i < 4; ++i) {
        m.startCov[i] = problem_.startCov[i];
    }
    m.goalX = problem_.goalX;
    m.goalY = problem_.goalY;
    for (std::size_t t = 0; t <= steps; ++t) {
        m.meanX[t] = plan_.meanX[t];
        m.meanY[t] = plan_.meanY[t];
    }
    published(bus_.publish(m), "plan path");
}

void DeliberativeTask::publishStatus(core::TimeNs now) {
    msg::PlanStatusMsg& s = status_;
    s.timeNs = now;
    s.planStatus = static_cast<std::uint8_t>(plan_.status);
    s.goalIndex = static_cast<std::uint8_t>(goalNumber());
    s.goalCount = goals_.count;
    s.legIndex = static_cast<std::uint8_t>(legIndex_);
    s.legCount = static_cast<std::uint8_t>(legs_.count);
    s.riskBound = goalsSeen_ ? goals_.riskBound : static_cast<double>(tables_.planner().default_risk_bound);
    s.riskUsed = plan_.riskUsed;
    s.planLengthM = plan_.euclideanLengthM;
    s.planGap = planGap_;
    s.plansMade = counters_.plansFound;
    s.replans = counters_.replans;
    s.riskRelaxations = counters_.riskRelaxations;
    s.boundRelaxations = counters_.boundRelaxations;
    s.callHomes = counters_.callHomes;
    s.currentLegId = leg_.legId;
    s.goalRevision = goals_.revision;
    s.shownLegs = 0;
    for (std::size_t k = legIndex_; k < legs_.count && s.shownLegs < msg::kPlanStatusLegs; ++k) {
        s.legs[s.shownLegs++] = legs_.legs[k];
    }
    for (std::size_t k = s.shownLegs; k < msg::kPlanStatusLegs; ++k) {
        s.legs[k] = msg::PlanLeg{};
    }
    published(bus_.publish(s), "plan status");
    changed_ = false;
}

}  // namespace rse::deliberative
