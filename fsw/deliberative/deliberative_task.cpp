#include "fsw/deliberative/deliberative_task.hpp"

#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::deliberative {

DeliberativeTask::DeliberativeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
                                   const site_map::SiteMap* siteMap)
    : events_(events),
      tables_(tables),
      out_(bus, events),
      inputs_(bus, events, *this),
      hold_(events),
      siteMap_(siteMap),
      lookAhead_(events),
      policy_(events),
      backUp_(events),
      legs_(events, out_),
      maker_(events, tables, out_) {}

core::Status DeliberativeTask::init() {
    const core::Status status = inputs_.init();
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
    now_ = frame.actualStart;
    inputs_.drainFast();
    backUp_.record(pose_, poseSeen_);
    inputs_.drainInputs();
    const msg::DeliberativeState s = status_.state;
    // A hold is fault protection's: a drive under recovery trips the interlock
    // on purpose, and what the hold stops must not count against the mission.
    if (active() && autonomous_ && !hold_.held() && drives_.mobilityLost()) {
        callHome(msg::CallHomeReason::kMobilityLost, "the drive interlock holds every drive");
    } else if (s == msg::DeliberativeState::kWaiting && autonomous_ && !hold_.held() && goalIndex_ < goals_.count &&
               poseUsable()) {
        startPlan();
    } else if (s == msg::DeliberativeState::kPlanning && routing_) {
        if (horizons_.step()) {
            onRouted();
        }
    } else if (s == msg::DeliberativeState::kPlanning) {
        if (maker_.step()) {
            onPlanFinished();
        }
    } else if (s == msg::DeliberativeState::kExecuting && legs_.goalUnconfirmed() && !hold_.held()) {
        const GoalClaim claim = legs_.reclaimGoal(arrival());
        if (claim == GoalClaim::kReached) {
            nextGoal();
        } else if (claim == GoalClaim::kResend) {
            resendFromPose();
        }
    } else if (s == msg::DeliberativeState::kExecuting && lookAhead_.planning()) {
        if (maker_.step()) {
            lookAhead_.planned();
        }
    } else if (s == msg::DeliberativeState::kExecuting && lookAheadDue()) {
        startLookAhead();
    }
    // ROUTE: a route found is told in chunks, a few a run.
    msg::RouteChunkMsg chunk;
    for (std::size_t k = 0; k < kRouteChunksPerRun && horizons_.nextChunk(&chunk); ++k) {
        out_.publish(chunk, "route chunk");
    }
    ++runs_;
    collectCounters();   // before PLAN status, which shows some of them
    if (changed_ || runs_ % kStatusPeriodRuns == 0) {
        publishStatus();
    }
}

void DeliberativeTask::collectCounters() {
    const PlanCounters& plans = maker_.counters();
    const LegCounters& legs = legs_.counters();
    DeliberativeCounters& c = counters_;
    c.goalListsAdopted = mission_.goalListsAdopted;
    c.plansStarted = plans.plansStarted;
    c.plansFound = plans.plansFound;
    c.noPlans = plans.noPlans;
    c.riskRelaxations = policy_.riskRelaxations();
    c.legsSent = legs.legsSent;
    c.legsAchieved = legs.legsAchieved;
    c.goalsReached = legs.goalsReached;
    c.failUps = mission_.failUps;
    c.boundRelaxations = policy_.boundRelaxations();
    c.replans = policy_.replans();
    c.callHomes = mission_.callHomes;
    c.problemsRefused = plans.problemsRefused;
    c.obstaclesDropped = plans.obstaclesDropped;
    c.malformedInputs = inputs_.malformed();
    c.publishFailures = out_.failures();
    c.planningRuns = plans.planningRuns;
    c.hazardMaps = mission_.hazardMaps;
    c.legEndsSkipped = legs.legEndsSkipped;
    c.holds = hold_.holds();
    c.resumes = hold_.resumes();
    c.failUpsWhileHeld = mission_.failUpsWhileHeld;
    c.goalsUnconfirmed = legs.goalsUnconfirmed;
    c.goalLegsResent = legs.goalLegsResent;
    c.backUps = backUp_.backUps();
    c.offMapReplans = mission_.offMapReplans;
    c.offMapIgnored = mission_.offMapIgnored;
    c.reentryPlans = plans.reentryPlans;
    c.seededPlans = plans.seededPlans;
    c.budgetPlans = plans.budgetPlans;
    c.wideSearches = plans.wideSearches;
    c.wideSearchPlans = plans.wideSearchPlans;
    c.powerRelaxations = policy_.powerRelaxations();
    c.failedDriveModels = plans.failedDriveModels;
    c.maxRunWork = plans.maxRunWork;
    c.maxRunUnits = plans.maxRunUnits;
    c.routesFound = routesFound_;
    c.routesFailed = routesFailed_;
    c.horizonsReached = horizonsReached_;
    c.siteRocksAdded = plans.siteRocksAdded;
    const LookAheadCounters& ahead = lookAhead_.counters();
    c.lookAheadsStarted = ahead.started;
    c.lookAheadsDropped = ahead.dropped;
    c.horizonsDrivenThrough = ahead.handedOver;
    c.horizonStops = ahead.finishedStopped + ahead.fromPose;
}

// ---------------------------------------------------------------------------
// Inputs

void DeliberativeTask::takePose(const msg::PoseEstimateMsg& pose) {
    pose_ = pose;
    poseSeen_ = true;
}

void DeliberativeTask::takeDriveStatus(const msg::DriveStatusMsg& drives) { drives_.takeDriveStatus(drives); }

void DeliberativeTask::takeDriveModes(const msg::DriveModesMsg& modes) { drives_.takeDriveModes(modes, now_); }

void DeliberativeTask::takeFaults(const msg::FaultStatusMsg& faults) { faults_ = faults; }

void DeliberativeTask::takeGoals(const msg::PlanGoalMsg& goal) {
    const msg::GoalListMsg& goals = goal.goals;
    if (goalsSeen_ && goals.revision == goals_.revision) {
        return;
    }
    goals_ = goals;
    listIndex_ = goal.listIndex;
    goalsSeen_ = true;
    changed_ = true;  // PlanStatusMsg.goalRevision: the new list is in force
    goalIndex_ = 0;
    policy_.newGoals();
    backUp_.cancel();
    backUp_.nextGoal();
    ++mission_.goalListsAdopted;
    cancelLeg();
    legs_.newGoals();
    status_.callHome = msg::CallHomeReason::kNone;
    status_.riskInForce = goals.riskBound;
    maker_.forgetPlan();  // PLAN shows "no plan" until the new goal is planned
    dropLookAhead("a new goal list");
    planFromLookAhead_ = false;
    horizons_.forget();
    routing_ = false;
    horizonLast_ = true;
    setState(goals.count == 0 ? msg::DeliberativeState::kIdle : msg::DeliberativeState::kWaiting);
    events_.report(events::kGoalsChanged, core::Severity::kInfo,
                   "deliberative: goal list rev %u: %u goal(s), risk bound %.3g: %s", static_cast<unsigned>(goals.revision),
                   static_cast<unsigned>(goals.count), goals.riskBound,
                   goals.count == 0 ? "idle" : (autonomous_ ? "planning" : "planning once AUTONOMOUS"));
}

void DeliberativeTask::takeMode(const msg::ModeMsg& mode) {
    const bool was = autonomous_;
    autonomous_ = mode.mode == msg::mode::kAutonomous;
    if (!was || autonomous_) {
        return;
    }
    const msg::DeliberativeState s = status_.state;
    legs_.dropUnconfirmedGoal();
    backUp_.cancel();
    if (s == msg::DeliberativeState::kPlanning || s == msg::DeliberativeState::kExecuting) {
        cancelLeg();
        dropLookAhead("left AUTONOMOUS");
        planFromLookAhead_ = false;
        routing_ = false;   // a route half searched is searched again (one found is kept)
        setState(msg::DeliberativeState::kWaiting);
        events_.report(events::kLeftAutonomous, core::Severity::kInfo,
                       "deliberative: left AUTONOMOUS (mode %u): plan dropped, goal %u replanned when back",
                       static_cast<unsigned>(mode.mode), static_cast<unsigned>(goalNumber()));
    }
}

void DeliberativeTask::takeLegReport(const msg::LegReportMsg& report) {
    const std::uint32_t inForce = legs_.legInForce().legId;
    if (status_.state != msg::DeliberativeState::kExecuting || inForce == 0 || report.legId != inForce) {
        return;  // about an older leg, or the 1 Hz repeat of one already handled
    }
    if (report.state == msg::HabitualState::kAchieved && backUp_.active()) {
        backedUp();
        return;
    }
    if (report.state == msg::HabitualState::kAchieved) {
        const bool more = legs_.achieved();
        changed_ = true;
        if (more) {
            sendLeg();
        } else {
            lastLegReached();
        }
        return;
    }
    const bool refused = report.state == msg::HabitualState::kIdle && report.violated == msg::LegConstraint::kBadLeg;
    if (report.state != msg::HabitualState::kFailedUp && !refused) {
        return;
    }
    if (hold_.held()) {
        ++mission_.failUpsWhileHeld;
        events_.report(events::kFailUpWhileHeld, core::Severity::kInfo,
                       "deliberative: leg %u failed up (%s) during a hold (reasons 0x%x): ignored, re-sent on release",
                       static_cast<unsigned>(report.legId), constraintName(report.violated),
                       static_cast<unsigned>(hold_.reasons()));
        return;
    }
    onFailUp(report);
}

void DeliberativeTask::takeHazards(const msg::KnownHazardsMsg& hazards) {
    hazards_ = hazards;
    ++mission_.hazardMaps;
    // A look-ahead planned with less than the rover knows now is planned
    // again (the run starts it anew).
    if (lookAhead_.active() && lookAhead_.stale(hazards_.revision, siteMap_ != nullptr ? siteMap_->revision() : 0)) {
        dropLookAhead("the seen hazards changed", true);
    }
    // The leg in force may end inside what was just seen: the habitual layer
    // could only fail up on it, so move on to the next leg end now.
    if (status_.state == msg::DeliberativeState::kExecuting && legs_.legInForce().legId != 0 && !hold_.held() &&
        !backUp_.active() && legs_.legEndTooClose(clearance())) {
        legs_.dropLegInForce();
        sendLeg();
    }
}

void DeliberativeTask::takeHold(const msg::MissionHoldMsg& hold) {
    const bool driving = status_.state == msg::DeliberativeState::kExecuting && legs_.legToDrive();
    const MissionHold::Change change = hold_.take(hold, legs_.legInForce().legId, driving);
    changed_ = changed_ || change != MissionHold::Change::kNone;
    if (change == MissionHold::Change::kReleased && driving) {
        resendFromPose();
    }
}

void DeliberativeTask::takeReplanRequest(const msg::ReplanRequestMsg& request) {
    if (!active() || !autonomous_ || goalIndex_ >= goals_.count) {
        ++mission_.offMapIgnored;
        events_.report(events::kOffMapReplan, core::Severity::kWarning,
                       "deliberative: off the map at (%.2f, %.2f), try %u: no mission to replan (state %u%s)",
                       pose_.xM, pose_.yM, static_cast<unsigned>(request.attempt),
                       static_cast<unsigned>(status_.state), autonomous_ ? "" : ", not AUTONOMOUS");
        return;
    }
    ++mission_.offMapReplans;
    policy_.countUnlimitedReplan();  // a replan in PLAN telemetry; not one of the goal's replan_limit
    // The waypoint in force led off the map (or the rover was carried off):
    // it is dropped, whatever the leg was doing, and the goals planned again
    // from where the rover stands. A plan under way started from elsewhere.
    cancelLeg();
    backUp_.cancel();
    dropLookAhead("off the map");
    legs_.dropUnconfirmedGoal();
    policy_.capture(msg::LegConstraint::kNone, replanFrom());
    setState(msg::DeliberativeState::kWaiting);
    changed_ = true;
    const ReplanRequest& rr = policy_.request();
    events_.report(events::kOffMapReplan, core::Severity::kWarning,
                   "deliberative: off the map at (%.2f, %.2f), try %u: waypoint cancelled, replan %s",
                   rr.xM, rr.yM, static_cast<unsigned>(request.attempt), hold_.held() ? "after hold" : "from here");
}

// ---------------------------------------------------------------------------
// Executing

void DeliberativeTask::onFailUp(const msg::LegReportMsg& report) {
    ++mission_.failUps;
    if (backUp_.active()) {
        backUp_.cancel();
        callHome(msg::CallHomeReason::kReplansExhausted, "the back-up failed up");
        return;
    }
    const FailUpAnswer answer = policy_.answerFailUp(report, legs_.legGrowth(), legs_.powerGrowth(),
                                                     static_cast<double>(tables_.planner().bound_relax_limit));
    if (answer.action == FailUpAnswer::Action::kReplan) {
        replan(report.violated);
        return;
    }
    legs_.relax(answer, report.violated);
    legs_.dropLegInForce();
    sendLeg();
}

void DeliberativeTask::backedUp() {
    backUp_.reached(pose_, poseSeen_, tables_.planner().no_path_backup_limit, goalNumber());
    legs_.dropLegInForce();
    changed_ = true;
    policy_.capture(msg::LegConstraint::kNoPath, replanFrom());
    setState(msg::DeliberativeState::kWaiting);
}

void DeliberativeTask::lastLegReached() {
    if (!horizonLast_) {
        // A horizon's end, not the goal: the next horizon, planned ahead
        // while the rover drove here when it could be, else from the pose.
        // The replan, risk-relaxation and back-up limits are a plan's: each
        // horizon has them whole (a 700 m goal is many horizons).
        ++horizonsReached_;
        policy_.nextGoal();
        backUp_.nextGoal();
        const Handover next = lookAhead_.handover(geometry::Point2{pose_.xM, pose_.yM}, hazards_.revision,
                                                  siteMap_ != nullptr ? siteMap_->revision() : 0,
                                                  maker_.hasCandidatePath());
        if (next == Handover::kTake) {
            adoptLookAhead();
            onPlanFinished();
        } else if (next == Handover::kFinish) {
            adoptLookAhead();
            setState(msg::DeliberativeState::kPlanning);
        } else {
            setState(msg::DeliberativeState::kWaiting);
        }
        return;
    }
    const GoalClaim claim = legs_.claimGoal(arrival());
    if (claim == GoalClaim::kReached) {
        nextGoal();
    } else {
        changed_ = true;  // waiting for a certain pose
    }
}

void DeliberativeTask::nextGoal() {
    ++goalIndex_;
    policy_.nextGoal();
    backUp_.nextGoal();
    if (goalIndex_ < goals_.count) {
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    setState(msg::DeliberativeState::kComplete);
    events_.report(events::kMissionComplete, core::Severity::kInfo, "deliberative: every goal reached (%u)",
                   static_cast<unsigned>(goals_.count));
}

void DeliberativeTask::replan(msg::LegConstraint why) {
    legs_.dropLegInForce();
    dropLookAhead("a replan of this horizon");
    if (policy_.replan(why, replanFrom(), tables_.planner().replan_limit)) {
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    if (why == msg::LegConstraint::kNoPath && startBackUp()) {
        return;
    }
    callHome(ReplanPolicy::exhaustedReason(why), constraintName(why));
}

bool DeliberativeTask::startBackUp() {
    const tables::PlannerTable& planner = tables_.planner();
    if (!backUp_.start(pose_, static_cast<double>(planner.no_path_backup_m), planner.no_path_backup_limit,
                       policy_.goalReplans(), clearance())) {
        return false;
    }
    setState(msg::DeliberativeState::kExecuting);
    sendBackUpLeg();
    return true;
}

void DeliberativeTask::sendLeg() {
    legs_.send(now_, hold_.held(), goalRadiusM(), clearance());
    changed_ = true;
}

void DeliberativeTask::sendBackUpLeg() {
    legs_.sendBackUp(now_, hold_.held(), backUp_.leg(), pose_, legParams());
    changed_ = true;
}

void DeliberativeTask::resendFromPose() {
    if (status_.state != msg::DeliberativeState::kExecuting) {
        return;
    }
    if (backUp_.active()) {
        sendBackUpLeg();
        return;
    }
    if (legs_.resendFromPose(now_, hold_.held(), goalRadiusM(), clearance(), pose_, legParams())) {
        changed_ = true;
    }
}

void DeliberativeTask::cancelLeg() {
    if (legs_.legInForce().legId == 0 && status_.state != msg::DeliberativeState::kExecuting) {
        return;
    }
    legs_.cancel(now_);
}

void DeliberativeTask::callHome(msg::CallHomeReason reason, const char* detail) {
    legs_.cancel(now_);
    dropLookAhead("call home");
    planFromLookAhead_ = false;
    msg::SafeRequestMsg safe{};
    safe.timeNs = now_;
    safe.reason = reason;
    out_.publish(safe, "safe request");
    ++mission_.callHomes;
    status_.callHome = reason;
    setState(msg::DeliberativeState::kCalledHome);
    cmdtlm::event_data::CALL_HOME data;
    data.reason = static_cast<double>(reason);
    data.goal = static_cast<double>(goalNumber());
    data.risk_bound = goals_.riskBound;
    events_.report(events::kCallHome, core::Severity::kCritical, data.pack(),
                   "deliberative: CALL HOME: %s (%s), goal %u, risk bound %.3g: rover safed, waiting for goals",
                   callHomeReasonName(reason), detail, static_cast<unsigned>(goalNumber()), goals_.riskBound);
}

// ---------------------------------------------------------------------------
// Planning

void DeliberativeTask::startPlan() {
    const msg::Goal& goal = goals_.goals[goalIndex_];
    const StartPoint from = policy_.takeStart(now_, pose_);
    if (siteMode() && !horizons_.routes(geometry::Point2{goal.xM, goal.yM}, siteMap_->revision())) {
        startRoute(from.xM, from.yM, goal);
        return;
    }
    PlanStart start;
    start.xM = from.xM;
    start.yM = from.yM;
    for (std::size_t i = 0; i < 4; ++i) {
        start.cov[i] = from.cov[i];
    }
    start.goalX = goal.xM;
    start.goalY = goal.yM;
    start.goalNumber = goalNumber();
    start.riskBound = policy_.riskInForce(goals_.riskBound);
    start.failedDrives =
        drives_.confirmedFailedDrives(now_, static_cast<double>(tables_.planner().failed_drive_confirm_s));
    start.meanPowerFactor = meanFactor();
    start.hazards = &hazards_;
    horizonLast_ = true;
    if (siteMode() && !planHorizon(from.xM, from.yM, &start)) {
        callHome(msg::CallHomeReason::kGoalUnreachable, "no horizon on the route");
        return;
    }
    const char* refusal = "";
    hazardRevisionAtPlan_ = hazards_.revision;
    if (!maker_.start(start, &refusal)) {
        callHome(msg::CallHomeReason::kGoalUnreachable, refusal);
        return;
    }
    status_.riskInForce = start.riskBound;
    setState(msg::DeliberativeState::kPlanning);
}

bool DeliberativeTask::planHorizon(double fromX, double fromY, PlanStart* start) {
    if (!horizons_.next(geometry::Point2{fromX, fromY}, horizonReach(), &horizon_)) {
        return false;
    }
    horizonLast_ = horizon_.last;
    start->goalX = horizon_.goal.x;
    start->goalY = horizon_.goal.y;
    start->site = SiteCorridor{siteMap_, &siteQuery_, horizon_.corridor, horizon_.count,
                               static_cast<double>(tables_.planner().site_corridor_reach_m)};
    return true;
}

bool DeliberativeTask::lookAheadDue() const {
    if (!siteMode() || horizonLast_ || !autonomous_ || hold_.held() || backUp_.active() || !poseUsable() ||
        legs_.legInForce().legId == 0 || legs_.goalUnconfirmed() || goalIndex_ >= goals_.count ||
        legs_.legs().count == 0) {
        return false;
    }
    const msg::Goal& goal = goals_.goals[goalIndex_];
    if (!horizons_.routes(geometry::Point2{goal.xM, goal.yM}, siteMap_->revision())) {
        return false;
    }
    const msg::PlanLeg& end = legs_.legs().legs[legs_.legs().count - 1];
    const double toEnd = std::hypot(end.xM - pose_.xM, end.yM - pose_.yM);
    return lookAhead_.due(toEnd, legs_.index() + 1 >= legs_.legs().count,
                          static_cast<double>(tables_.planner().site_look_ahead_m));
}

void DeliberativeTask::startLookAhead() {
    // From where the plan in hand ends (its last leg's end), with the
    // covariance its model gives the rover there.
    const msg::PlanLeg& last = legs_.legs().legs[legs_.legs().count - 1];
    const geometry::Point2 end{last.xM, last.yM};
    const std::size_t before = horizons_.progress();
    if (!horizons_.next(end, horizonReach(), lookAhead_.horizonSlot())) {
        lookAhead_.refused();
        return;
    }
    const Horizon& next = lookAhead_.horizon();
    const std::size_t steps = HorizonLookAhead::stepsToGo(maker_.plan(), geometry::Point2{pose_.xM, pose_.yM});
    const double poseCov[4] = {pose_.covariance[0], pose_.covariance[1], pose_.covariance[3], pose_.covariance[4]};
    PlanStart start;
    start.xM = end.x;
    start.yM = end.y;
    HorizonLookAhead::startCovariance(poseCov, steps, maker_.problem().processSigmaM, start.cov);
    start.goalX = next.goal.x;
    start.goalY = next.goal.y;
    start.goalNumber = goalNumber();
    // The operator's bound: the next horizon starts with no relaxation.
    start.riskBound = goals_.riskBound < kMaxRiskInForce ? goals_.riskBound : kMaxRiskInForce;
    start.failedDrives =
        drives_.confirmedFailedDrives(now_, static_cast<double>(tables_.planner().failed_drive_confirm_s));
    start.meanPowerFactor = meanFactor();
    start.hazards = &hazards_;
    start.site = SiteCorridor{siteMap_, &siteQuery_, next.corridor, next.count,
                              static_cast<double>(tables_.planner().site_corridor_reach_m)};
    const char* refusal = "";
    if (!maker_.start(start, &refusal)) {
        horizons_.rewind(before);
        lookAhead_.refused();
        return;
    }
    const double sigma0 = std::sqrt(start.cov[0] > start.cov[3] ? start.cov[0] : start.cov[3]);
    lookAhead_.begin(end, sigma0, steps, before, hazards_.revision, siteMap_->revision(), start.riskBound);
}

void DeliberativeTask::dropLookAhead(const char* why, bool stale) {
    std::size_t progressBefore = 0;
    if (lookAhead_.drop(why, stale, &progressBefore)) {
        horizons_.rewind(progressBefore);
    }
}

void DeliberativeTask::adoptLookAhead() {
    horizon_ = lookAhead_.horizon();
    horizonLast_ = horizon_.last;
    hazardRevisionAtPlan_ = lookAhead_.hazardRevision();
    status_.riskInForce = lookAhead_.riskBound();
    planFromLookAhead_ = true;
}

void DeliberativeTask::startRoute(double fromX, double fromY, const msg::Goal& goal) {
    const tables::PlannerTable& planner = tables_.planner();
    RouteMargins margins;
    margins.marginM = static_cast<double>(planner.site_route_margin_m);
    margins.comfortM = static_cast<double>(planner.site_route_comfort_m);
    margins.zoneMarginM = static_cast<double>(planner.site_route_zone_margin_m);
    const RouteRefusal refusal =
        horizons_.begin(*siteMap_, geometry::Point2{fromX, fromY}, geometry::Point2{goal.xM, goal.yM},
                        rse::geometry::clearanceRadiusM(tables_.roverGeometry()), margins);
    if (refusal != RouteRefusal::kNone) {
        ++routesFailed_;
        events_.report(events::kNoRoute, core::Severity::kWarning,
                       "deliberative: no route to goal %u (%.2f, %.2f) over the site map: %s",
                       static_cast<unsigned>(goalNumber()), goal.xM, goal.yM, toString(refusal));
        callHome(msg::CallHomeReason::kGoalUnreachable, toString(refusal));
        return;
    }
    routing_ = true;
    setState(msg::DeliberativeState::kPlanning);
}

void DeliberativeTask::onRouted() {
    routing_ = false;
    const GlobalRoute& r = horizons_.route();
    if (horizons_.routed()) {
        ++routesFound_;
        horizons_.announce(now_, goalIndex_);
        events_.report(events::kRouteFound, core::Severity::kInfo,
                       "deliberative: route to goal %u: %.1f m, %u points, %u expansions, %u runs",
                       static_cast<unsigned>(goalNumber()), r.lengthM(), static_cast<unsigned>(r.pointCount()),
                       static_cast<unsigned>(r.stats().expansions), static_cast<unsigned>(r.stats().steps));
        setState(msg::DeliberativeState::kWaiting);   // the first horizon next run
        return;
    }
    ++routesFailed_;
    events_.report(events::kNoRoute, core::Severity::kWarning,
                   "deliberative: no route to goal %u over the site map: %s (%u expansions)",
                   static_cast<unsigned>(goalNumber()), toString(r.state()), static_cast<unsigned>(r.stats().expansions));
    callHome(msg::CallHomeReason::kGoalUnreachable, toString(r.state()));
}

void DeliberativeTask::onPlanFinished() {
    const bool hasPath = maker_.finish();
    const bool fromLookAhead = planFromLookAhead_;
    planFromLookAhead_ = false;
    if (hasPath && drives_.interlockTripped()) {
        // Only drives declared failed hold the interlock (else mobilityLost()
        // called home already): a plan fits with them failed, but the rover
        // cannot drive on the others until they are isolated, which no layer
        // does yet.
        maker_.countPlanFound(now_);
        callHome(msg::CallHomeReason::kMobilityLost, "a plan fits, but the interlock holds every drive");
        return;
    }
    if (hasPath) {
        const LegParams params = legParams();
        if (legs_.split(maker_.plan(), params)) {
            maker_.countPlanFound(now_);
            maker_.reportPlanFound(legs_.legs().count);
            legs_.begin();
            if (maker_.fromReentry()) {
                legs_.widenFirstLeg(pose_, params);
            }
            setState(msg::DeliberativeState::kExecuting);
            sendLeg();
            return;
        }
    }
    if (fromLookAhead) {
        // Planned from the horizon's end with the covariance of arriving
        // there: the rover is there now, so plan from its pose (with the
        // wide search and the relaxations a plan has) before giving up.
        events_.report(events::kLookAheadDropped, core::Severity::kInfo,
                       "deliberative: look-ahead found no plan: the horizon planned from the pose");
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    if (maker_.startWideSearch()) {
        return;
    }
    maker_.reportNoPlan(goalNumber());
    if (policy_.relaxRisk(maker_.riskBound(), goals_.riskBound,
                          static_cast<double>(tables_.planner().risk_relax_limit))) {
        setState(msg::DeliberativeState::kWaiting);
        return;
    }
    callHome(msg::CallHomeReason::kNoPlanWithinRisk, "no plan at the relaxed risk limit");
}

// ---------------------------------------------------------------------------
// What the parts are given

bool DeliberativeTask::active() const {
    const msg::DeliberativeState s = status_.state;
    return s == msg::DeliberativeState::kWaiting || s == msg::DeliberativeState::kPlanning ||
           s == msg::DeliberativeState::kExecuting;
}

bool DeliberativeTask::poseUsable() const {
    return poseSeen_ && pose_.initialised != 0 && now_ - pose_.timeNs <= kPoseMaxAgeNs;
}

bool DeliberativeTask::poseUncertain() const {
    const bool faulted = ((faults_.activeMask >> msg::fault::kPoseUncertain) & 1U) != 0U;
    const double limit = static_cast<double>(tables_.estimatorNoise().pose_fault_sigma_m);
    return faulted || !poseSeen_ || pose_.initialised == 0 || !(pose_.positionSigmaM <= limit);
}

double DeliberativeTask::meanFactor() const {
    return drives_.meanPowerFactor(static_cast<double>(tables_.habitual().failed_drive_power_factor));
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

LegEndClearance DeliberativeTask::clearance() const {
    return LegEndClearance(tables_.coarseMap(), rse::geometry::clearanceRadiusM(tables_.roverGeometry()), hazards_);
}

ReplanFrom DeliberativeTask::replanFrom() const {
    ReplanFrom from;
    from.now = now_;
    from.pose = &pose_;
    from.goalIndex = goalIndex_;
    from.goalCount = goals_.count;
    from.seenHazards = hazards_.count;
    from.informed = siteMode() && hazards_.revision != hazardRevisionAtPlan_;
    return from;
}

GoalArrival DeliberativeTask::arrival() const {
    GoalArrival a;
    a.goal = &goals_.goals[goalIndex_];
    a.number = goalNumber();
    a.arrivalM = msg::arrivalRadiusM(static_cast<double>(tables_.habitual().goal_tolerance_m), goalRadiusM());
    a.pose = &pose_;
    a.poseUncertain = poseUncertain();
    a.poseFault = ((faults_.activeMask >> msg::fault::kPoseUncertain) & 1U) != 0U;
    return a;
}

HorizonReach DeliberativeTask::horizonReach() const {
    HorizonReach reach;
    reach.lengthM = static_cast<double>(tables_.planner().site_horizon_m);
    reach.lastFactor = static_cast<double>(tables_.planner().site_last_horizon_factor);
    return reach;
}

double DeliberativeTask::goalRadiusM() const {
    // A horizon short of the goal ends at its point.
    if (!horizonLast_) {
        return 0.0;
    }
    return goalIndex_ < goals_.count ? static_cast<double>(goals_.goals[goalIndex_].radiusM) : 0.0;
}

// ---------------------------------------------------------------------------
// Outputs

void DeliberativeTask::setState(msg::DeliberativeState state) {
    if (status_.state != state) {
        status_.state = state;
        changed_ = true;
    }
}

void DeliberativeTask::publishStatus() {
    const CcPlan& plan = maker_.plan();
    const LegPlan& legs = legs_.legs();
    msg::PlanStatusMsg& s = status_;
    s.timeNs = now_;
    s.planStatus = static_cast<std::uint8_t>(plan.status);
    s.goalIndex = static_cast<std::uint8_t>(goalNumber());
    s.goalCount = goals_.count;
    s.legIndex = static_cast<std::uint8_t>(legs_.index());
    s.legCount = static_cast<std::uint8_t>(legs.count);
    s.riskBound = goalsSeen_ ? goals_.riskBound : static_cast<double>(tables_.planner().default_risk_bound);
    s.riskUsed = plan.riskUsed;
    s.planLengthM = plan.euclideanLengthM;
    s.planGap = maker_.planGap();
    s.plansMade = maker_.counters().plansFound;
    s.replans = policy_.replans();
    s.riskRelaxations = policy_.riskRelaxations();
    s.boundRelaxations = policy_.boundRelaxations();
    s.callHomes = mission_.callHomes;
    s.currentLegId = legs_.legInForce().legId;
    s.goalRevision = goals_.revision;
    s.siteMode = siteMode() ? 1U : 0U;
    s.routesFound = counters_.routesFound;
    s.routesFailed = counters_.routesFailed;
    s.horizonsReached = counters_.horizonsReached;
    s.horizonsDrivenThrough = counters_.horizonsDrivenThrough;
    s.horizonStops = counters_.horizonStops;
    s.lookAheadsStarted = counters_.lookAheadsStarted;
    s.lookAheadsDropped = counters_.lookAheadsDropped;
    s.shownLegs = 0;
    for (std::size_t k = legs_.index(); k < legs.count && s.shownLegs < msg::kPlanStatusLegs; ++k) {
        s.legs[s.shownLegs++] = legs.legs[k];
    }
    for (std::size_t k = s.shownLegs; k < msg::kPlanStatusLegs; ++k) {
        s.legs[k] = msg::PlanLeg{};
    }
    out_.publish(s, "plan status");
    changed_ = false;
}

}  // namespace rse::deliberative
