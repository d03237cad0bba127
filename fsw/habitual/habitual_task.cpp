#include "fsw/habitual/habitual_task.hpp"

#include <cmath>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/input_checks.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::habitual {

using geometry::Point2;

namespace {

constexpr core::InputPipeConfig kPosePipe{"habitual_pose", kPosePipeDepth, events::kMalformedInput, "habitual"};
constexpr core::InputPipeConfig kInputPipe{"habitual", kInputPipeDepth, events::kMalformedInput, "habitual"};

}  // namespace

HabitualTask::HabitualTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables,
                           const site_map::SiteMap* siteMap)
    : events_(events),
      tables_(tables),
      posePipe_(bus, events, kPosePipe),
      inputPipe_(bus, events, kInputPipe),
      legEvents_(events),
      memory_(events, tables.coarseMap(), siteMap),
      evaluator_(tables.habitual()),
      supervisor_(events, tables.habitual()),
      outputs_(bus, tables.habitual()),
      session_(memory_, events, tables.habitual(), tables.coarseMap(), tables.roverGeometry()) {
    // Until the drive mode estimator speaks, the drives are taken as nominal.
    for (msg::DriveModeBelief& drive : modes_.drives) {
        drive.powerFactor = 1.0F;
        drive.declared = msg::DriveMode::kNominal;
        drive.probability[0] = 1.0F;
    }
}

core::Status HabitualTask::init() {
    // Each step only while the ones before it succeeded; the input pipe's ids
    // in the order the task has always subscribed them.
    core::Status status = posePipe_.create();
    status = core::isOk(status) ? posePipe_.route<&HabitualTask::takePose>(this) : status;
    status = core::isOk(status) ? inputPipe_.create() : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeLeg>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeHazards>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeDriveModes>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeFollower>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeContact>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeMode>(this) : status;
    status = core::isOk(status) ? inputPipe_.route<&HabitualTask::takeHold>(this) : status;
    if (!core::isOk(status)) {
        events_.report(events::kInitFailed, core::Severity::kError, "habitual: init failed (%s): task disabled",
                       core::toString(status));
        return status;
    }
    initialised_ = true;
    return status;
}

void HabitualTask::run(const core::FrameContext& frame) {
    if (!initialised_) {
        return;
    }
    const core::TimeNs now = frame.actualStart;
    now_ = now;
    ++runs_;
    (void)posePipe_.drain();
    (void)inputPipe_.drain();
    if (legActive_ && poseSeen_) {
        supervisor_.updateOdometry(pose_, meanFactor());
    }
    if (held_) {
        ++counters_.heldRuns;
    }
    switch (held_ ? msg::HabitualState::kIdle : state_) {
        case msg::HabitualState::kPlanning:
        case msg::HabitualState::kRepairing:
            stepPlanning(now);
            break;
        case msg::HabitualState::kDriving:
            superviseDriving(now);
            break;
        case msg::HabitualState::kIdle:
        case msg::HabitualState::kFailedUp:
        case msg::HabitualState::kAchieved:
            break;
    }
    modesChanged_ = false;
    const bool periodic = runs_ % kReportPeriodRuns == 0;
    if (periodic) {
        publishReport(now);
    }
    if (periodic || outputs_.hazardsChanged(memory_)) {
        outputs_.publishHazards(now, memory_);
    }
    collectCounters();
}

void HabitualTask::collectCounters() {
    // The parts count what they do; counters() is read between runs (telemetry,
    // tests, the mission summary), so the figures are gathered once a run.
    HabitualCounters& c = counters_;
    const SessionCounters& session = session_.counters();
    c.planningRuns = session.planningRuns;
    c.noPathRuns = session.noPathRuns;
    c.plannerRefused = session.plannerRefused;
    c.escapes = session.escapes;
    const SupervisorCounters& supervisor = supervisor_.counters();
    c.pathBlocked = supervisor.pathBlocked;
    c.energyViolations = supervisor.energyViolations;
    c.cannotFollow = supervisor.cannotFollow;
    const OutputCounters& outputs = outputs_.counters();
    c.plansSent = outputs.plansSent;
    c.stopsSent = outputs.stopsSent;
    c.hazardMapsSent = outputs.hazardMapsSent;
    c.mapRefused = memory_.mapRefused();
    c.malformedInputs = posePipe_.malformed() + inputPipe_.malformed() + memory_.rejectedSightings();
}

// ---- Inputs ---------------------------------------------------------------------

core::Status HabitualTask::takePose(const msg::PoseEstimateMsg& pose) {
    if (!poseFinite(pose)) {
        return core::Status::kInvalidArgument;
    }
    pose_ = pose;
    poseSeen_ = true;
    return core::Status::kOk;
}

bool HabitualTask::poseUsable(core::TimeNs now) const {
    return poseSeen_ && pose_.initialised != 0 && now - pose_.timeNs <= kPoseMaxAgeNs;
}

double HabitualTask::meanFactor() const {
    return rover_model::meanPowerFactor(modes_, static_cast<double>(tables_.habitual().failed_drive_power_factor));
}

LegProgress HabitualTask::progress() const {
    return LegProgress{supervisor_.drivenLengthM(), supervisor_.drivenEnergyJ(), meanFactor()};
}

core::Status HabitualTask::takeHold(const msg::MissionHoldMsg& hold) {
    if (!msg::holdUsable(hold)) {
        return core::Status::kInvalidArgument;
    }
    if (hold.reasons != 0U && !held_) {
        held_ = true;
        ++counters_.holds;
        session_.stopQuery();  // a planning run restarts from the pose of the release
        const bool moving = legActive_;
        if (moving) {
            sendStop(now_);
        }
        legEvents_.held(hold.reasons, leg_.legId, moving);
    } else if (hold.reasons == 0U && held_) {
        held_ = false;
        ++counters_.releases;
        session_.restartRestWait();
        legEvents_.released(hold.resumeCount, leg_.legId, state_ == msg::HabitualState::kDriving);
    }
    return core::Status::kOk;
}

core::Status HabitualTask::takeMode(const msg::ModeMsg& mode) {
    if (!modeUsable(mode)) {
        return core::Status::kInvalidArgument;
    }
    const bool was = autonomous_;
    autonomous_ = mode.mode == msg::mode::kAutonomous;
    if (!was || autonomous_ || state_ == msg::HabitualState::kIdle) {
        return core::Status::kOk;
    }
    const bool moving = legActive_;
    legActive_ = false;
    session_.stopQuery();
    ++counters_.leftAutonomous;
    if (moving) {
        sendStop(now_);
    }
    legEvents_.leftAutonomous(mode.mode, leg_.legId, moving);
    outputs_.clearFailUp();
    setState(msg::HabitualState::kIdle, now_);
    return core::Status::kOk;
}

core::Status HabitualTask::takeHazards(const msg::HazardMsg& hazards) {
    if (!hazardsUsable(hazards)) {
        return core::Status::kInvalidArgument;
    }
    if (!poseUsable(now_)) {
        ++counters_.hazardsUnplaced;
        return core::Status::kOk;
    }
    memory_.remember(hazards, Point2{pose_.xM, pose_.yM}, pose_.headingRad);
    return core::Status::kOk;
}

core::Status HabitualTask::takeContact(const msg::ContactMsg& contact) {
    if (!contactUsable(contact)) {
        return core::Status::kInvalidArgument;
    }
    memory_.rememberContact(contact, geometry::clearanceRadiusM(tables_.roverGeometry()));
    return core::Status::kOk;
}

core::Status HabitualTask::takeDriveModes(const msg::DriveModesMsg& modes) {
    if (!driveModesUsable(modes)) {
        return core::Status::kInvalidArgument;
    }
    modes_ = modes;
    modesChanged_ = true;
    return core::Status::kOk;
}

core::Status HabitualTask::takeFollower(const msg::FollowerStatusMsg& status) {
    if (!followerStatusUsable(status)) {
        return core::Status::kInvalidArgument;
    }
    followerBackingOff_ = status.state == msg::FollowerState::kBackingOff;
    if (held_ || state_ != msg::HabitualState::kDriving) {
        return core::Status::kOk;  // about a trajectory no longer in force
    }
    switch (supervisor_.judgeFollower(status, outputs_.trajectory(), outputs_.escaping(), leg_.legId)) {
        case FollowerVerdict::kEscapeDone:
            outputs_.escapeEnded();
            beginSession(PlanTrigger::kPathBlocked, 0, now_);  // from where the escape ended
            break;
        case FollowerVerdict::kReached:
            achieveLeg(false, now_);
            break;
        case FollowerVerdict::kReplan:
            ++counters_.replans;
            sendStop(now_);
            beginSession(PlanTrigger::kCannotFollow, 0, now_);
            break;
        case FollowerVerdict::kFailUp: {
            Evaluation e = evaluator_.inForce();
            e.violated = msg::LegConstraint::kCannotFollow;
            e.excess = 0.0;
            failUp(msg::LegConstraint::kCannotFollow, e, now_);
            break;
        }
        case FollowerVerdict::kNothing:
            break;
    }
    return core::Status::kOk;
}

// ---- The leg ----------------------------------------------------------------------

void HabitualTask::takeLeg(const msg::LegCommandMsg& leg) {
    if (leg.legId == 0) {
        cancelLeg(now_);
        return;
    }
    const char* why = legRefusal(leg, autonomous_, leg_.legId, tables_.coarseMap());
    if (why != nullptr) {
        refuseLeg(leg, why, now_);
        return;
    }
    acceptLeg(leg, now_);
}

void HabitualTask::cancelLeg(core::TimeNs now) {
    const bool moving = legActive_;
    legActive_ = false;
    session_.stopQuery();
    ++counters_.legsCancelled;
    sendStop(now);
    legEvents_.cancelled(leg_.legId, moving);
    outputs_.clearFailUp();
    if (state_ == msg::HabitualState::kIdle) {
        publishReport(now);
    } else {
        setState(msg::HabitualState::kIdle, now);
    }
}

void HabitualTask::refuseLeg(const msg::LegCommandMsg& leg, const char* why, core::TimeNs now) {
    ++counters_.legsRefused;
    legEvents_.refused(leg.legId, why, counters_.legsRefused);
    outputs_.publishRefusal(now, leg.legId, reportCounts());
}

void HabitualTask::acceptLeg(const msg::LegCommandMsg& leg, core::TimeNs now) {
    leg_ = leg;
    legActive_ = true;
    session_.beginLeg();
    supervisor_.beginLeg();
    ++counters_.legsAccepted;
    const tables::HabitualTable& hab = tables_.habitual();
    legEvents_.accepted(leg, legStopShortM(hab, leg) > 0.0 ? legArrivalM(hab, leg) : 0.0);
    sendStop(now);  // held stopped while the new leg is planned
    evaluator_.beginLeg(leg);
    outputs_.clearFailUp();
    const bool wasPlanning = state_ == msg::HabitualState::kPlanning;
    beginSession(PlanTrigger::kNewLeg, 0, now);
    if (wasPlanning) {
        publishReport(now);  // a new leg is news even when the state stays kPlanning
    }
}

void HabitualTask::achieveLeg(bool alreadyInside, core::TimeNs now) {
    ++counters_.legsAchieved;
    legActive_ = false;
    session_.stopQuery();
    const Point2 here{pose_.xM, pose_.yM};
    if (alreadyInside) {
        legEvents_.achievedInside(leg_, here, legArrivalM(tables_.habitual(), leg_));
    } else {
        legEvents_.achieved(leg_, here, supervisor_.drivenLengthM(), supervisor_.drivenEnergyJ());
    }
    setState(msg::HabitualState::kAchieved, now);
}

void HabitualTask::failUp(msg::LegConstraint reason, const Evaluation& evaluation, core::TimeNs now) {
    sendStop(now);
    legActive_ = false;
    session_.stopQuery();
    ++counters_.failUps;
    evaluator_.setInForce(evaluation);
    const bool bound = reason == msg::LegConstraint::kPathLength || reason == msg::LegConstraint::kEnergy ||
                       reason == msg::LegConstraint::kPower;
    outputs_.setFailUp(reason, bound ? evaluation.excess : 0.0);
    legEvents_.failUp(leg_, reason, evaluation, static_cast<unsigned>(session_.attempt()) + 1U, meanFactor());
    setState(msg::HabitualState::kFailedUp, now);
}

// ---- Planning --------------------------------------------------------------------

void HabitualTask::beginSession(PlanTrigger trigger, std::uint8_t firstAttempt, core::TimeNs now) {
    session_.begin(trigger, firstAttempt);
    evaluator_.clearCandidate();
    setState(trigger == PlanTrigger::kNewLeg ? msg::HabitualState::kPlanning : msg::HabitualState::kRepairing, now);
}

void HabitualTask::stepPlanning(core::TimeNs now) {
    if (!poseUsable(now)) {
        ++counters_.poseWaits;
        legEvents_.poseNotReady(leg_.legId, counters_.poseWaits);
        return;
    }
    if (!session_.querying()) {
        if (!readyToPlan(now)) {
            return;
        }
        const PlanStep first = session_.start(leg_, pose_);
        if (first != PlanStep::kQuerying) {
            takePlanStep(first, now);  // finished at once (straight line, refused), or a back-out
            return;
        }
    }
    takePlanStep(session_.iterate(leg_), now);
}

bool HabitualTask::readyToPlan(core::TimeNs now) {
    if (followerBackingOff_) {
        ++counters_.backoffWaits;
        return false;  // the follower's reflex first (followerBackingOff_)
    }
    const tables::HabitualTable& hab = tables_.habitual();
    const bool settling = session_.settling(pose_);
    const double fromGoal = distance(Point2{pose_.xM, pose_.yM}, Point2{leg_.goalXM, leg_.goalYM});
    if (legStopShortM(hab, leg_) > 0.0 && fromGoal <= legArrivalM(hab, leg_)) {
        // A region leg from inside its region (the leg before ended there,
        // or a repair stopped the rover there): nothing to drive, nor a
        // power bound to keep. Judged where the rover comes to rest.
        if (settling) {
            session_.waitForRest();
            return false;
        }
        achieveLeg(true, now);
        return false;
    }
    // No path can lower the drives' power: a leg whose power bound no
    // longer holds fails up before any planning.
    const Evaluation power = evaluator_.powerCheck(meanFactor());
    if (power.violated == msg::LegConstraint::kPower) {
        failUp(msg::LegConstraint::kPower, power, now);
        return false;
    }
    if (settling) {
        session_.waitForRest();
        return false;
    }
    return true;
}

void HabitualTask::takePlanStep(PlanStep step, core::TimeNs now) {
    switch (step) {
        case PlanStep::kQuerying:
            break;
        case PlanStep::kEscape:
            sendEscape(now);
            break;
        case PlanStep::kFinished: {
            const std::size_t count = session_.pathCount();
            if (count < 2) {
                finishAttempt(0, Evaluation{}, now);
            } else {
                const Evaluation e = evaluator_.evaluate(session_.path(), count, session_.queryHeading(), progress());
                finishAttempt(count, e, now);
            }
            break;
        }
    }
}

void HabitualTask::sendEscape(core::TimeNs now) {
    const Point2 start = session_.queryStart();
    const Point2 exit = session_.escapeExit();
    outputs_.sendEscape(leg_.legId, start, exit, now);
    supervisor_.followEscape();
    legEvents_.escape(leg_.legId, session_.escapeOffSite(), start, exit, session_.escapesThisLeg());
    setState(msg::HabitualState::kDriving, now);
}

void HabitualTask::finishAttempt(std::size_t count, const Evaluation& evaluation, core::TimeNs now) {
    if (count >= 2 && evaluation.violated == msg::LegConstraint::kNone) {
        acceptPlan(count, evaluation, now);
        return;
    }
    if (count >= 2 && evaluation.violated == msg::LegConstraint::kPower) {
        failUp(msg::LegConstraint::kPower, evaluation, now);  // the power factors rose while planning
        return;
    }
    if (count >= 2) {
        evaluator_.keepCandidate(session_.path(), count, evaluation);
    }
    if (session_.repairLeft()) {
        session_.nextAttempt();
        ++counters_.repairAttempts;
        ++counters_.replans;
        legEvents_.repair(leg_.legId, count, evaluation, session_.attempt(), session_.lastAttempt());
        session_.stopQuery();
        setState(msg::HabitualState::kRepairing, now);
        return;
    }
    if (evaluator_.haveCandidate()) {
        failUp(evaluator_.candidate().violated, evaluator_.candidate(), now);
    } else {
        failUp(msg::LegConstraint::kNoPath, evaluator_.noPath(progress()), now);
    }
}

void HabitualTask::acceptPlan(std::size_t count, const Evaluation& evaluation, core::TimeNs now) {
    outputs_.sendPath(leg_.legId, session_.path(), count, now);
    supervisor_.followPlan(meanFactor());
    evaluator_.setInForce(evaluation);
    outputs_.clearFailUp();
    legEvents_.planSent(leg_.legId, outputs_.trajectory().trajectoryId, count, evaluation,
                        session_.lastQuery().marginDropped);
    if (session_.trigger() != PlanTrigger::kNewLeg || session_.attempt() > 0) {
        ++counters_.minorAnomalies;
        legEvents_.minorAnomaly(leg_.legId, session_.trigger(), session_.attempt());
    }
    setState(msg::HabitualState::kDriving, now);
}

// ---- Driving ----------------------------------------------------------------------

void HabitualTask::superviseDriving(core::TimeNs now) {
    const msg::TrajectoryMsg& trajectory = outputs_.trajectory();
    // An escape starts inside an inflated disc and only moves away from it.
    if (trajectory.count < 2 || !poseSeen_ || outputs_.escaping()) {
        return;
    }
    if (memory_.checkMapStale()) {
        memory_.refreshCheckMap(geometry::clearanceRadiusM(tables_.roverGeometry()), leg_);
        if (supervisor_.pathBlocked(trajectory, Point2{pose_.xM, pose_.yM}, memory_, leg_.legId)) {
            ++counters_.replans;
            sendStop(now);
            beginSession(PlanTrigger::kPathBlocked, 0, now);
            return;
        }
    }
    if (modesChanged_) {
        onPowerFactors(now);
    }
}

void HabitualTask::onPowerFactors(core::TimeNs now) {
    const FactorCheck check =
        supervisor_.checkPowerFactors(outputs_.trajectory(), pose_, evaluator_, progress(), leg_.legId);
    if (check.verdict == FactorVerdict::kUnchanged) {
        return;
    }
    evaluator_.setInForce(check.evaluation);
    if (check.verdict == FactorVerdict::kPower) {
        failUp(msg::LegConstraint::kPower, check.evaluation, now);  // stops the rover; no path mends it
        return;
    }
    if (check.verdict == FactorVerdict::kHolds) {
        return;
    }
    if (tables_.habitual().repair_attempts == 0) {
        failUp(msg::LegConstraint::kEnergy, check.asEnergy, now);
        return;
    }
    sendStop(now);
    beginSession(PlanTrigger::kEnergy, 1, now);
    ++counters_.repairAttempts;
    ++counters_.replans;
    evaluator_.keepCandidate(supervisor_.remaining(), supervisor_.remainingCount(), check.asEnergy);
    legEvents_.energyRepair(leg_.legId, check.evaluation, check.asEnergy.excess, session_.lastAttempt());
}

// ---- Outputs ----------------------------------------------------------------------

void HabitualTask::sendStop(core::TimeNs now) { outputs_.sendStop(leg_.legId, now); }

void HabitualTask::setState(msg::HabitualState state, core::TimeNs now) {
    if (state == state_) {
        return;
    }
    state_ = state;
    publishReport(now);
}

void HabitualTask::publishReport(core::TimeNs now) {
    outputs_.publishReport(now, leg_.legId, state_, evaluator_.inForce(), reportCounts());
}

ReportCounts HabitualTask::reportCounts() const {
    return ReportCounts{counters_.legsAchieved, counters_.failUps, counters_.replans, counters_.minorAnomalies};
}

}  // namespace rse::habitual
