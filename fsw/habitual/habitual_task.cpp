#include "fsw/habitual/habitual_task.hpp"

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/geometry/site_bounds.hpp"

#include <cmath>

#include "fsw/geometry/coarse_map.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::habitual {

using geometry::distanceToCoarseMap;
using geometry::Point2;
using geometry::wrapAngleRad;
using rover_model::meanPowerFactor;
using rover_model::motionEnergyJ;
using rover_model::pathEnergyJ;
using rover_model::PowerModel;
using rover_model::powerModelFrom;

namespace {

// A power factor beyond this is no estimate (the drive would be far over its
// current limit): the message is refused as malformed.
constexpr float kLargestPowerFactor = 100.0F;

std::uint64_t querySeed(std::uint32_t legId, std::uint32_t query) {
    // splitmix64 finaliser: every (leg, query) pair gets an unrelated seed.
    std::uint64_t z = (static_cast<std::uint64_t>(legId) << 32U) ^ query ^ 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
}

const char* triggerName(PlanTrigger trigger) {
    switch (trigger) {
        case PlanTrigger::kNewLeg:
            return "new leg";
        case PlanTrigger::kPathBlocked:
            return "path blocked";
        case PlanTrigger::kEnergy:
            return "energy";
        case PlanTrigger::kCannotFollow:
            return "cannot follow";
    }
    return "?";
}

const char* constraintName(msg::LegConstraint constraint) {
    switch (constraint) {
        case msg::LegConstraint::kNone:
            return "none";
        case msg::LegConstraint::kPathLength:
            return "path length";
        case msg::LegConstraint::kEnergy:
            return "energy";
        case msg::LegConstraint::kNoPath:
            return "no path";
        case msg::LegConstraint::kCannotFollow:
            return "cannot follow";
        case msg::LegConstraint::kBadLeg:
            return "bad leg";
        case msg::LegConstraint::kPower:
            return "power";
    }
    return "?";
}

const char* followReasonName(msg::FollowReason reason) {
    switch (reason) {
        case msg::FollowReason::kNone:
            return "no reason";
        case msg::FollowReason::kCrossTrackError:
            return "cross-track error";
        case msg::FollowReason::kPoseStale:
            return "pose stale";
        case msg::FollowReason::kDrivesHeld:
            return "drives held";
        case msg::FollowReason::kNotAutonomous:
            return "not autonomous";
        case msg::FollowReason::kBadTrajectory:
            return "bad trajectory";
    }
    return "?";
}

}  // namespace

HabitualTask::HabitualTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables)
    : bus_(bus), events_(events), tables_(tables) {
    // Until the drive mode estimator speaks, the drives are taken as nominal.
    for (msg::DriveModeBelief& drive : modes_.drives) {
        drive.powerFactor = 1.0F;
        drive.declared = msg::DriveMode::kNominal;
        drive.probability[0] = 1.0F;
    }
}

core::Status HabitualTask::init() {
    core::Status status = bus_.createPipe("habitual_pose", kPosePipeDepth, &posePipe_);
    if (core::isOk(status)) {
        status = bus_.subscribe(posePipe_, msg::ids::kPoseEstimate);
    }
    if (core::isOk(status)) {
        status = bus_.createPipe("habitual", kInputPipeDepth, &inputPipe_);
    }
    const core::MsgId inputs[] = {msg::ids::kLegCommand,     msg::ids::kHazards, msg::ids::kDriveModes,
                                  msg::ids::kFollowerStatus, msg::ids::kMode,    msg::ids::kMissionHold};
    for (const core::MsgId id : inputs) {
        if (core::isOk(status)) {
            status = bus_.subscribe(inputPipe_, id);
        }
    }
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
    ++runs_;
    drainPoses();
    drainInputs(now);
    updateOdometry();
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
    if (periodic || mapBuilder_.revision() != hazardsRevision_) {
        publishHazards(now);
    }
}

// ---- Inputs ---------------------------------------------------------------------

void HabitualTask::malformed(const char* what, core::MsgId id) {
    ++counters_.malformedInputs;
    if (core::isReportableOccurrence(counters_.malformedInputs)) {
        events_.report(events::kMalformedInput, core::Severity::kError,
                       "habitual: malformed %s (msg 0x%04x) ignored (%u so far)", what, static_cast<unsigned>(id),
                       static_cast<unsigned>(counters_.malformedInputs));
    }
}

void HabitualTask::drainPoses() {
    for (std::uint16_t i = 0; i < kPosePipeDepth && core::isOk(bus_.receive(posePipe_, &inbox_)); ++i) {
        msg::PoseEstimateMsg pose{};
        if (!core::isOk(inbox_.decode(&pose)) || !std::isfinite(pose.xM) || !std::isfinite(pose.yM) ||
            !std::isfinite(pose.headingRad) || !std::isfinite(pose.speedMS) || !std::isfinite(pose.yawRateRadS)) {
            malformed("pose estimate", inbox_.header.id);
            continue;
        }
        pose_ = pose;
        poseSeen_ = true;
    }
}

void HabitualTask::drainInputs(core::TimeNs now) {
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
            case msg::ids::kLegCommand: {
                msg::LegCommandMsg leg{};
                if (core::isOk(inbox_.decode(&leg))) {
                    onLeg(leg, now);
                } else {
                    malformed("leg command", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kHazards: {
                msg::HazardMsg hazards{};
                if (core::isOk(inbox_.decode(&hazards)) && hazards.count <= msg::kMaxHazardsInMsg) {
                    onHazards(hazards, now);
                } else {
                    malformed("hazards", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kDriveModes: {
                msg::DriveModesMsg modes{};
                if (core::isOk(inbox_.decode(&modes))) {
                    onDriveModes(modes);
                } else {
                    malformed("drive modes", inbox_.header.id);
                }
                break;
            }
            case msg::ids::kFollowerStatus: {
                msg::FollowerStatusMsg status{};
                if (core::isOk(inbox_.decode(&status)) &&
                    static_cast<std::uint8_t>(status.state) <= static_cast<std::uint8_t>(msg::FollowerState::kStopping) &&
                    static_cast<std::uint8_t>(status.reason) <= static_cast<std::uint8_t>(msg::FollowReason::kBadTrajectory)) {
                    onFollower(status, now);
                } else {
                    malformed("follower status", inbox_.header.id);
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
            default:
                malformed("message", inbox_.header.id);
                break;
        }
    }
}

void HabitualTask::onHold(const msg::MissionHoldMsg& hold, core::TimeNs now) {
    if (hold.reasons != 0U && !held_) {
        held_ = true;
        ++counters_.holds;
        queryActive_ = false;  // a planning run restarts from the pose of the release
        const bool moving = legActive_;
        if (moving) {
            sendStop(now);
        }
        events_.report(events::kMissionHeld, core::Severity::kWarning,
                       "habitual: mission held (reasons 0x%x): %s, leg %u kept", static_cast<unsigned>(hold.reasons),
                       moving ? "rover stopped" : "nothing under way", static_cast<unsigned>(leg_.legId));
    } else if (hold.reasons == 0U && held_) {
        held_ = false;
        ++counters_.releases;
        restWaitRuns_ = 0;
        events_.report(events::kMissionReleased, core::Severity::kInfo,
                       "habitual: hold released (resume %u): leg %u %s", static_cast<unsigned>(hold.resumeCount),
                       static_cast<unsigned>(leg_.legId),
                       state_ == msg::HabitualState::kDriving ? "waits for the re-sent leg" : "goes on");
    }
}

bool HabitualTask::poseUsable(core::TimeNs now) const {
    return poseSeen_ && pose_.initialised != 0 && now - pose_.timeNs <= kPoseMaxAgeNs;
}

double HabitualTask::meanFactor() const {
    return meanPowerFactor(modes_, static_cast<double>(tables_.habitual().failed_drive_power_factor));
}

void HabitualTask::onMode(const msg::ModeMsg& mode, core::TimeNs now) {
    const bool was = autonomous_;
    autonomous_ = mode.mode == msg::mode::kAutonomous;
    if (!was || autonomous_ || state_ == msg::HabitualState::kIdle) {
        return;
    }
    const bool moving = legActive_;
    legActive_ = false;
    queryActive_ = false;
    ++counters_.leftAutonomous;
    if (moving) {
        sendStop(now);
    }
    events_.report(events::kLeftAutonomous, core::Severity::kInfo,
                   "habitual: left AUTONOMOUS (mode %u): leg %u dropped, %s", static_cast<unsigned>(mode.mode),
                   static_cast<unsigned>(leg_.legId), moving ? "rover stopped" : "rover already stopped");
    reportViolated_ = msg::LegConstraint::kNone;
    reportExcess_ = 0.0;
    setState(msg::HabitualState::kIdle, now);
}

void HabitualTask::refuseLeg(const msg::LegCommandMsg& leg, const char* why, core::TimeNs now) {
    ++counters_.legsRefused;
    if (core::isReportableOccurrence(counters_.legsRefused)) {
        events_.report(events::kLegRefused, core::Severity::kWarning, "habitual: leg %u refused: %s (%u so far)",
                       static_cast<unsigned>(leg.legId), why, static_cast<unsigned>(counters_.legsRefused));
    }
    // A one-off answer about the refused leg; the leg in force (if any) goes on
    // and the next periodic report is about it again.
    msg::LegReportMsg r{};
    r.timeNs = now;
    r.legId = leg.legId;
    r.state = msg::HabitualState::kIdle;
    r.violated = msg::LegConstraint::kBadLeg;
    r.legsAchieved = counters_.legsAchieved;
    r.failUps = counters_.failUps;
    r.replans = counters_.replans;
    r.minorAnomalies = counters_.minorAnomalies;
    (void)bus_.publish(r);
    report_ = r;
}

void HabitualTask::onLeg(const msg::LegCommandMsg& leg, core::TimeNs now) {
    if (leg.legId == 0) {
        const bool moving = legActive_;
        legActive_ = false;
        queryActive_ = false;
        ++counters_.legsCancelled;
        sendStop(now);
        events_.report(events::kLegCancelled, core::Severity::kInfo, "habitual: leg %u cancelled: %s",
                       static_cast<unsigned>(leg_.legId), moving ? "rover stopped" : "nothing under way");
        reportViolated_ = msg::LegConstraint::kNone;
        reportExcess_ = 0.0;
        if (state_ == msg::HabitualState::kIdle) {
            publishReport(now);
        } else {
            setState(msg::HabitualState::kIdle, now);
        }
        return;
    }
    const tables::CoarseMapTable& coarse = tables_.coarseMap();
    if (!autonomous_) {
        refuseLeg(leg, "not in AUTONOMOUS mode", now);
        return;
    }
    if (leg.legId == leg_.legId) {
        refuseLeg(leg, "leg id not new", now);
        return;
    }
    if (!std::isfinite(leg.goalXM) || !std::isfinite(leg.goalYM)) {
        refuseLeg(leg, "goal not finite", now);
        return;
    }
    if (geometry::outsideBy(geometry::siteBox(coarse, 0.0), leg.goalXM, leg.goalYM) > 0.0) {
        refuseLeg(leg, "goal off the coarse map", now);
        return;
    }
    if (!std::isfinite(leg.maxPathLengthM) || leg.maxPathLengthM <= 0.0) {
        refuseLeg(leg, "path length bound not positive and finite", now);
        return;
    }
    if (!std::isfinite(leg.maxEnergyJ) || leg.maxEnergyJ <= 0.0) {
        refuseLeg(leg, "energy bound not positive and finite", now);
        return;
    }
    if (!std::isfinite(leg.maxPowerW) || leg.maxPowerW < 0.0) {
        refuseLeg(leg, "power bound negative or not finite", now);
        return;
    }
    if (!(leg.arriveWithinM >= 0.0 && leg.arriveWithinM <= static_cast<double>(msg::kMaxGoalRadiusM))) {
        refuseLeg(leg, "arrival radius negative, too large or not finite", now);
        return;
    }

    leg_ = leg;
    legActive_ = true;
    escapesThisLeg_ = 0;
    drivenLengthM_ = 0.0;
    drivenEnergyJ_ = 0.0;
    anchorSet_ = false;
    cannotFollowReplans_ = 0;
    ++counters_.legsAccepted;
    if (stopShortM() > 0.0) {
        events_.report(events::kLegAccepted, core::Severity::kInfo,
                       "habitual: leg %u to (%.2f, %.2f) within %.2f m: max %.1f m, %.0f J",
                       static_cast<unsigned>(leg.legId), leg.goalXM, leg.goalYM, arrivalM(), leg.maxPathLengthM,
                       leg.maxEnergyJ);
    } else {
        events_.report(events::kLegAccepted, core::Severity::kInfo,
                       "habitual: leg %u to (%.2f, %.2f): max %.1f m, %.0f J", static_cast<unsigned>(leg.legId),
                       leg.goalXM, leg.goalYM, leg.maxPathLengthM, leg.maxEnergyJ);
    }
    sendStop(now);  // held stopped while the new leg is planned
    const tables::HabitualTable& hab = tables_.habitual();
    plan_ = Evaluation{0.0, 0.0, leg.maxPathLengthM * (1.0 - static_cast<double>(hab.distance_margin_frac)),
                       leg.maxEnergyJ * (1.0 - static_cast<double>(hab.power_margin_frac)), msg::LegConstraint::kNone,
                       0.0, 0.0, 0.0, leg.maxPowerW * (1.0 - static_cast<double>(hab.power_margin_frac))};
    reportViolated_ = msg::LegConstraint::kNone;
    reportExcess_ = 0.0;
    const bool wasPlanning = state_ == msg::HabitualState::kPlanning;
    beginSession(PlanTrigger::kNewLeg, 0, now);
    if (wasPlanning) {
        publishReport(now);  // a new leg is news even when the state stays kPlanning
    }
}

void HabitualTask::onHazards(const msg::HazardMsg& hazards, core::TimeNs now) {
    if (!poseUsable(now)) {
        ++counters_.hazardsUnplaced;
        return;
    }
    const tables::CoarseMapTable& coarse = tables_.coarseMap();
    const Point2 rover{pose_.xM, pose_.yM};
    for (std::size_t i = 0; i < hazards.count && i < msg::kMaxHazardsInMsg; ++i) {
        const msg::HazardSightingTlm& s = hazards.sightings[i];
        switch (mapBuilder_.remember(coarse, rover, pose_.headingRad, s)) {
            case SightingOutcome::kAdded: {
                const RememberedHazard* h = nullptr;
                for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
                    if (mapBuilder_.slot(k).used && mapBuilder_.slot(k).obstacleId == s.obstacleId) {
                        h = &mapBuilder_.slot(k);
                    }
                }
                if (h != nullptr) {
                    events_.report(events::kHazardRemembered, core::Severity::kInfo,
                                   "habitual: hazard %u seen at (%.2f, %.2f), radius %.2f m: on the map",
                                   static_cast<unsigned>(s.obstacleId), h->centre.x, h->centre.y, h->radiusM);
                }
                break;
            }
            case SightingOutcome::kUpdated:
            case SightingOutcome::kUnchanged:
                break;
            case SightingOutcome::kReplacedOldest:
                if (core::isReportableOccurrence(mapBuilder_.replacedOldest())) {
                    events_.report(events::kHazardTableFull, core::Severity::kWarning,
                                   "habitual: hazard table full (%u): oldest replaced by id %u (%u so far)",
                                   static_cast<unsigned>(kMaxMapDiscs), static_cast<unsigned>(s.obstacleId),
                                   static_cast<unsigned>(mapBuilder_.replacedOldest()));
                }
                break;
            case SightingOutcome::kKnownObstacle:
                if (core::isReportableOccurrence(mapBuilder_.knownObstacles())) {
                    events_.report(events::kHazardKnown, core::Severity::kDebug,
                                   "habitual: hazard %u is on the coarse map: not added (%u so far)",
                                   static_cast<unsigned>(s.obstacleId),
                                   static_cast<unsigned>(mapBuilder_.knownObstacles()));
                }
                break;
            case SightingOutcome::kRejected:
                malformed("hazard sighting", msg::ids::kHazards);
                break;
        }
    }
}

void HabitualTask::onDriveModes(const msg::DriveModesMsg& modes) {
    for (const msg::DriveModeBelief& drive : modes.drives) {
        if (!std::isfinite(drive.powerFactor) || drive.powerFactor < 0.0F || drive.powerFactor > kLargestPowerFactor ||
            static_cast<std::uint8_t>(drive.declared) >= msg::kDriveModeCount) {
            malformed("drive modes", msg::ids::kDriveModes);
            return;
        }
    }
    modes_ = modes;
    modesChanged_ = true;
}

void HabitualTask::onFollower(const msg::FollowerStatusMsg& status, core::TimeNs now) {
    if (held_ || state_ != msg::HabitualState::kDriving || trajectory_.count == 0 ||
        status.trajectoryId != trajectory_.trajectoryId) {
        return;  // about a trajectory no longer in force
    }
    if (status.state == msg::FollowerState::kReached && escaping_) {
        escaping_ = false;
        beginSession(PlanTrigger::kPathBlocked, 0, now);  // from where the escape ended
        return;
    }
    if (status.state == msg::FollowerState::kReached) {
        achieveLeg(false, now);
    } else if (status.state == msg::FollowerState::kCannotFollow) {
        onCannotFollow(status, now);
    }
}

void HabitualTask::achieveLeg(bool alreadyInside, core::TimeNs now) {
    ++counters_.legsAchieved;
    legActive_ = false;
    queryActive_ = false;
    if (alreadyInside) {
        events_.report(events::kLegAchieved, core::Severity::kInfo,
                       "habitual: leg %u achieved at (%.2f, %.2f): already within %.2f m of (%.2f, %.2f)",
                       static_cast<unsigned>(leg_.legId), pose_.xM, pose_.yM, arrivalM(), leg_.goalXM, leg_.goalYM);
    } else {
        events_.report(events::kLegAchieved, core::Severity::kInfo,
                       "habitual: leg %u achieved at (%.2f, %.2f): %.1f m, %.0f J driven",
                       static_cast<unsigned>(leg_.legId), pose_.xM, pose_.yM, drivenLengthM_, drivenEnergyJ_);
    }
    setState(msg::HabitualState::kAchieved, now);
}

// ---- Planning --------------------------------------------------------------------

double HabitualTask::arrivalM() const {
    return msg::arrivalRadiusM(static_cast<double>(tables_.habitual().goal_tolerance_m), leg_.arriveWithinM);
}

double HabitualTask::stopShortM() const {
    return arrivalM() - static_cast<double>(tables_.habitual().goal_tolerance_m);
}

void HabitualTask::beginSession(PlanTrigger trigger, std::uint8_t firstAttempt, core::TimeNs now) {
    trigger_ = trigger;
    attempt_ = firstAttempt;
    lastAttempt_ = tables_.habitual().repair_attempts;
    queryActive_ = false;
    bareFootprint_ = false;
    restWaitRuns_ = 0;
    haveCandidate_ = false;
    candidateCount_ = 0;
    setState(trigger == PlanTrigger::kNewLeg ? msg::HabitualState::kPlanning : msg::HabitualState::kRepairing, now);
}

bool HabitualTask::rebuildMap(LocalMap* map, double clearanceM, const MapRelief* relief) {
    // Every map of a leg (planning and checking alike) takes the hazard whose
    // cover reaches the leg's end as its seen disc (map_builder.hpp, MapRelief).
    MapRelief withEnd = relief != nullptr ? *relief : MapRelief{};
    if (leg_.legId != 0) {
        withEnd.seenAt = Point2{leg_.goalXM, leg_.goalYM};
        withEnd.hasSeenAt = true;
    }
    const core::Status status = mapBuilder_.build(tables_.coarseMap(), clearanceM, map, &withEnd);
    if (!core::isOk(status)) {
        ++counters_.mapRefused;
        if (core::isReportableOccurrence(counters_.mapRefused)) {
            events_.report(events::kMapRefused, core::Severity::kError,
                           "habitual: local map refused an obstacle (%s) (%u so far)", core::toString(status),
                           static_cast<unsigned>(counters_.mapRefused));
        }
    }
    return map->valid();
}

void HabitualTask::stepPlanning(core::TimeNs now) {
    if (!poseUsable(now)) {
        ++counters_.poseWaits;
        if (core::isReportableOccurrence(counters_.poseWaits)) {
            events_.report(events::kPoseNotReady, core::Severity::kWarning,
                           "habitual: leg %u waits: no fresh initialised pose (%u runs so far)",
                           static_cast<unsigned>(leg_.legId), static_cast<unsigned>(counters_.poseWaits));
        }
        return;
    }
    if (!queryActive_) {
        const bool atRest =
            std::fabs(pose_.speedMS) < kAtRestSpeedMS && std::fabs(pose_.yawRateRadS) < kAtRestYawRateRadS;
        const bool settling = !atRest && restWaitRuns_ < kMaxRestWaitRuns;
        const Point2 here{pose_.xM, pose_.yM};
        if (stopShortM() > 0.0 && distance(here, Point2{leg_.goalXM, leg_.goalYM}) <= arrivalM()) {
            // A region leg from inside its region (the leg before ended there,
            // or a repair stopped the rover there): nothing to drive, nor a
            // power bound to keep. Judged where the rover comes to rest.
            if (settling) {
                ++restWaitRuns_;
                return;
            }
            achieveLeg(true, now);
            return;
        }
        // No path can lower the drives' power: a leg whose power bound no
        // longer holds fails up before any planning.
        const Evaluation power = powerCheck();
        if (power.violated == msg::LegConstraint::kPower) {
            failUp(msg::LegConstraint::kPower, power, now);
            return;
        }
        if (settling) {
            ++restWaitRuns_;
            return;
        }
        if (!startQuery(now)) {
            return;  // finished at once: straight line, or refused
        }
    }
    const std::uint32_t budget = queryBudget();
    const std::uint32_t done = rrt_.iterations();
    const std::uint32_t remaining = budget > done ? budget - done : 0;
    const std::uint32_t slice = remaining < kRrtIterationsPerRun ? remaining : kRrtIterationsPerRun;
    const std::uint32_t ran = rrt_.iterate(slice);
    ++lastQuery_.taskRuns;
    const double straight = distance(queryStart_, Point2{leg_.goalXM, leg_.goalYM});
    const bool early = rrt_.solved() && rrt_.bestCost() <= kEarlyStopCostRatio * straight;
    if (rrt_.iterations() >= budget || ran < slice || early) {
        lastQuery_.earlyStop = early;
        finishQuery(now);
    }
}

std::uint32_t HabitualTask::queryBudget() const {
    const tables::HabitualTable& hab = tables_.habitual();
    if (trigger_ == PlanTrigger::kNewLeg && attempt_ == 0) {
        return hab.rrt_iterations;
    }
    // A local replan (the rover stopped mid-leg, or a repair) is bounded in time
    // as well: the table's milliseconds as iterations at the calibrated rate.
    const std::uint32_t timed = static_cast<std::uint32_t>(hab.replan_budget_ms) * kRrtIterationsPerMs;
    return timed < hab.rrt_iterations ? timed : hab.rrt_iterations;
}

bool HabitualTask::startQuery(core::TimeNs now) {
    const tables::HabitualTable& hab = tables_.habitual();
    const double footprint = rse::geometry::clearanceRadiusM(tables_.roverGeometry());
    queryStart_ = Point2{pose_.xM, pose_.yM};
    queryHeading_ = pose_.headingRad;
    const Point2 goal{leg_.goalXM, leg_.goalYM};
    lastQuery_ = PlannerQueryStats{};
    lastQuery_.attempt = attempt_;
    lastQuery_.rawCostM = INFINITY;

    // A path planned at the bare footprint leaves pure pursuit no room, so the
    // margin is given up no further than the start and goal need: first only
    // for the seen hazards they lie in; then by halves for everything.
    bool mapOk = false;
    if (!bareFootprint_) {
        mapOk = rebuildMap(&planMap_, footprint + kPlanMarginM);
        if (mapOk && (!planMap_.pointFree(queryStart_) || !planMap_.pointFree(goal))) {
            const MapRelief relief{{queryStart_, goal}, 2, kPlanMarginM};
            mapOk = rebuildMap(&planMap_, footprint + kPlanMarginM, &relief);
            lastQuery_.marginDropped = true;
        }
    }
    const double margins[] = {0.5 * kPlanMarginM, 0.0};
    for (double margin : margins) {
        if (mapOk && !bareFootprint_ && planMap_.pointFree(queryStart_) && planMap_.pointFree(goal)) {
            break;
        }
        if (bareFootprint_ && margin > 0.0) {
            continue;
        }
        mapOk = rebuildMap(&planMap_, footprint + margin);
        lastQuery_.marginDropped = true;
    }
    lastQuery_.marginDropped = lastQuery_.marginDropped || bareFootprint_;
    if (!mapOk) {
        completePlan(0, now);
        return false;
    }
    Point2 exit{0.0, 0.0};
    if (!planMap_.pointFree(queryStart_) && escapesThisLeg_ < kMaxEscapesPerLeg) {
        const bool offMap =
            geometry::outsideBy(geometry::siteBox(tables_.coarseMap(), 0.0), queryStart_.x, queryStart_.y) > 0.0;
        if (offMap ? findReentry(footprint, &exit) : findEscape(footprint, &exit)) {
            sendEscape(exit, offMap, now);
            return false;
        }
    }
    if (planMap_.segmentFree(queryStart_, goal)) {
        // The shortest path there is: nothing to sample.
        rawPath_[0] = queryStart_;
        rawPath_[1] = goal;
        lastQuery_.straightLine = true;
        lastQuery_.rawCostM = distance(queryStart_, goal);
        completePlan(2, now);
        return false;
    }
    // A node within the leg's arrival radius that sees the point solves the
    // query (the path still runs to the point; completePlan cuts it).
    const RrtStarParams params{static_cast<double>(hab.rrt_step_m), static_cast<double>(hab.rrt_goal_bias),
                               arrivalM(), hab.rrt_k_cap};
    ++queryCount_;
    const core::Status status = rrt_.start(planMap_, queryStart_, goal, params, querySeed(leg_.legId, queryCount_));
    if (!core::isOk(status)) {
        ++counters_.plannerRefused;
        if (core::isReportableOccurrence(counters_.plannerRefused)) {
            events_.report(events::kPlannerRefused, core::Severity::kWarning,
                           "habitual: leg %u: RRT* refused (%s): start %s, goal %s (%u so far)",
                           static_cast<unsigned>(leg_.legId), core::toString(status),
                           planMap_.pointFree(queryStart_) ? "free" : "blocked",
                           planMap_.pointFree(goal) ? "free" : "blocked",
                           static_cast<unsigned>(counters_.plannerRefused));
        }
        completePlan(0, now);
        return false;
    }
    queryActive_ = true;
    return true;
}

bool HabitualTask::findEscape(double footprint, Point2* exit) const {
    // The seen hazard the start lies deepest inside (planMap_ is at the bare
    // footprint here: its discs are the remembered ones plus the footprint).
    const RememberedHazard* deepest = nullptr;
    double depth = 0.0;
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = mapBuilder_.slot(k);
        if (!h.used) {
            continue;
        }
        const double d = h.radiusM + footprint - distance(queryStart_, h.centre);
        if (d > depth) {
            depth = d;
            deepest = &h;
        }
    }
    if (deepest == nullptr) {
        return false;  // blocked by a coarse-map polygon or the bounds: no escape from a disc
    }
    const double away = distance(queryStart_, deepest->centre);
    const double base = away > 1e-6 ? std::atan2(queryStart_.y - deepest->centre.y, queryStart_.x - deepest->centre.x)
                                    : queryHeading_ + 3.141592653589793;
    // Straight away first; then turned either way, in case that runs towards
    // another obstacle.
    const double turns[] = {0.0, 0.5236, -0.5236, 1.0472, -1.0472, 1.5708, -1.5708};
    const tables::CoarseMapTable& coarse = tables_.coarseMap();
    const double keep = footprint + kPlanMarginM;
    for (const double turn : turns) {
        const Point2 u{std::cos(base + turn), std::sin(base + turn)};
        double reach = deepest->radiusM + keep + kEscapeExtraM;
        for (std::uint32_t i = 0; i < kEscapeSteps; ++i, reach += kEscapeStepM) {
            const Point2 p = deepest->centre + reach * u;
            if (distance(p, queryStart_) > kMaxEscapeM) {
                break;
            }
            if (planMap_.pointFree(p) && escapeClear(coarse, p, keep, deepest)) {
                *exit = p;
                return true;
            }
        }
    }
    return false;
}

bool HabitualTask::findReentry(double footprint, Point2* exit) const {
    const tables::CoarseMapTable& coarse = tables_.coarseMap();
    const double keep = footprint + kPlanMarginM;
    const geometry::SiteBox site = geometry::siteBox(coarse, keep + kEscapeExtraM);
    Point2 nearest{0.0, 0.0};
    if (!geometry::nearestInside(site, queryStart_.x, queryStart_.y, &nearest.x, &nearest.y)) {
        return false;  // a site narrower than the rover's keep: nowhere to go
    }
    // Along the edge either way from the nearest point, in case a rock stands there.
    const Point2 inward = nearest - queryStart_;
    const double length = std::hypot(inward.x, inward.y);
    const Point2 along = length > 1e-9 ? Point2{-inward.y / length, inward.x / length} : Point2{1.0, 0.0};
    for (std::uint32_t i = 0; i <= 2 * kEscapeSteps; ++i) {
        const double step = static_cast<double>((i + 1) / 2) * kEscapeStepM * ((i % 2 == 1) ? 1.0 : -1.0);
        const Point2 slid = nearest + step * along;
        Point2 p{0.0, 0.0};
        if (!geometry::nearestInside(site, slid.x, slid.y, &p.x, &p.y) || distance(p, queryStart_) > kMaxReentryM) {
            continue;
        }
        if (planMap_.pointFree(p) && escapeClear(coarse, p, keep, nullptr)) {
            *exit = p;
            return true;
        }
    }
    return false;
}

bool HabitualTask::escapeClear(const tables::CoarseMapTable& coarse, Point2 exit, double keep,
                               const RememberedHazard* leaving) const {
    // The end keeps the planning margin from every other obstacle; the way
    // there keeps the bare footprint from the mapped rocks.
    if (distanceToCoarseMap(coarse, exit) < keep) {
        return false;
    }
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = mapBuilder_.slot(k);
        if (h.used && &h != leaving && distance(exit, h.centre) < h.radiusM + keep) {
            return false;
        }
    }
    const double length = distance(queryStart_, exit);
    const double footprint = rse::geometry::clearanceRadiusM(tables_.roverGeometry());
    for (std::uint32_t i = 1; i <= kEscapeChecks; ++i) {
        const double f = static_cast<double>(i) / static_cast<double>(kEscapeChecks);
        const Point2 q = queryStart_ + f * (exit - queryStart_);
        if (length > 0.0 && distanceToCoarseMap(coarse, q) < footprint) {
            return false;
        }
    }
    return true;
}

void HabitualTask::beginTrajectory(core::TimeNs now) {
    trajectory_ = msg::TrajectoryMsg{};
    trajectory_.timeNs = now;
    trajectory_.trajectoryId = nextTrajectoryId_++;
    if (nextTrajectoryId_ == 0) {
        nextTrajectoryId_ = 1;
    }
    trajectory_.legId = leg_.legId;
    trajectory_.speedMS = static_cast<double>(tables_.habitual().cruise_speed_m_s);
}

void HabitualTask::sendEscape(Point2 exit, bool offMap, core::TimeNs now) {
    ++escapesThisLeg_;
    ++counters_.escapes;
    beginTrajectory(now);
    trajectory_.count = 2;
    trajectory_.points[0] = msg::TrajectoryPoint{queryStart_.x, queryStart_.y};
    trajectory_.points[1] = msg::TrajectoryPoint{exit.x, exit.y};
    (void)bus_.publish(trajectory_);
    progressIndex_ = 0;
    escaping_ = true;
    events_.report(events::kEscape, core::Severity::kWarning,
                   "habitual: leg %u: %s at (%.2f, %.2f): out %.2f m to (%.2f, %.2f) (%u of %u)",
                   static_cast<unsigned>(leg_.legId), offMap ? "off the site" : "in a hazard disc",
                   queryStart_.x, queryStart_.y, distance(queryStart_, exit), exit.x, exit.y,
                   static_cast<unsigned>(escapesThisLeg_), static_cast<unsigned>(kMaxEscapesPerLeg));
    setState(msg::HabitualState::kDriving, now);
}

void HabitualTask::finishQuery(core::TimeNs now) {
    queryActive_ = false;
    lastQuery_.iterations = rrt_.iterations();
    lastQuery_.nodes = rrt_.nodeCount();
    lastQuery_.poolFull = rrt_.poolFull();
    lastQuery_.rawCostM = rrt_.bestCost();
    completePlan(rrt_.bestPath(rawPath_, kMaxRawPathPoints), now);
}

void HabitualTask::completePlan(std::size_t count, core::TimeNs now) {
    ++counters_.planningRuns;
    const Point2 goal{leg_.goalXM, leg_.goalYM};
    if (count >= 2) {
        count = shortcutPath(planMap_, rawPath_, count);
        const Point2 last = rawPath_[count - 1];
        const bool atGoal = last.x == goal.x && last.y == goal.y;
        if (!atGoal && distance(last, goal) <= arrivalM() && planMap_.segmentFree(last, goal) &&
            count < kMaxRawPathPoints) {
            rawPath_[count++] = goal;
        }
        // A region: the path ends where it enters it (stopShortM() from the point).
        count = cutPathAtDisc(rawPath_, count, goal, stopShortM());
        if (count > msg::kMaxTrajectoryPoints) {
            count = 0;
        }
    }
    if (count >= 2) {
        // Sightings may have come in while the query ran on its frozen map.
        (void)rebuildMap(&checkMap_, rse::geometry::clearanceRadiusM(tables_.roverGeometry()));
        checkedRevision_ = mapBuilder_.revision();
        for (std::size_t i = 0; i + 1 < count; ++i) {
            if (!checkMap_.segmentFree(rawPath_[i], rawPath_[i + 1])) {
                count = 0;
                break;
            }
        }
    }
    lastQuery_.points = count;
    lastQuery_.lengthM = count >= 2 ? pathLength(rawPath_, count) : 0.0;
    if (count < 2) {
        ++counters_.noPathRuns;
        bareFootprint_ = true;  // perhaps a passage only the bare footprint fits through
        finishAttempt(0, Evaluation{}, now);
        return;
    }
    finishAttempt(count, evaluate(rawPath_, count, queryHeading_), now);
}

HabitualTask::Evaluation HabitualTask::evaluate(const Point2* path, std::size_t count, double headingRad) const {
    const tables::HabitualTable& hab = tables_.habitual();
    Evaluation e{};
    e.lengthM = pathLength(path, count);
    e.energyJ = pathEnergyJ(powerModelFrom(hab), path, count, headingRad, meanFactor());
    e.allowedLengthM = (leg_.maxPathLengthM - drivenLengthM_) * (1.0 - static_cast<double>(hab.distance_margin_frac));
    e.allowedEnergyJ = (leg_.maxEnergyJ - drivenEnergyJ_) * (1.0 - static_cast<double>(hab.power_margin_frac));
    const double lengthExcess = e.lengthM - e.allowedLengthM;
    const double energyExcess = e.energyJ - e.allowedEnergyJ;
    // Relative to the whole leg's bounds (validated positive), so the two
    // compare and the least violating plan is well defined.
    const double relativeLength = lengthExcess / leg_.maxPathLengthM;
    const double relativeEnergy = energyExcess / leg_.maxEnergyJ;
    e.score = relativeLength > relativeEnergy ? relativeLength : relativeEnergy;
    const Evaluation power = powerCheck();
    e.powerW = power.powerW;
    e.allowedPowerW = power.allowedPowerW;
    if (power.violated == msg::LegConstraint::kPower) {
        // Whatever the path: the power bound is the drives', and no repair mends it.
        e.violated = msg::LegConstraint::kPower;
        e.excess = power.excess;
        e.score = power.score > e.score ? power.score : e.score;
    } else if (lengthExcess <= 0.0 && energyExcess <= 0.0) {
        e.violated = msg::LegConstraint::kNone;
        e.excess = 0.0;
    } else if (lengthExcess > 0.0 && (energyExcess <= 0.0 || relativeLength >= relativeEnergy)) {
        e.violated = msg::LegConstraint::kPathLength;
        e.excess = lengthExcess;
    } else {
        e.violated = msg::LegConstraint::kEnergy;
        e.excess = energyExcess;
    }
    return e;
}

HabitualTask::Evaluation HabitualTask::powerCheck() const {
    const tables::HabitualTable& hab = tables_.habitual();
    Evaluation e = plan_;
    e.powerW = rover_model::cruisePowerW(powerModelFrom(hab), static_cast<double>(hab.cruise_speed_m_s), meanFactor());
    e.allowedPowerW = leg_.maxPowerW * (1.0 - static_cast<double>(hab.power_margin_frac));
    const bool bounded = leg_.maxPowerW > 0.0;
    if (bounded && e.powerW > e.allowedPowerW) {
        e.violated = msg::LegConstraint::kPower;
        e.excess = e.powerW - e.allowedPowerW;
        e.score = e.excess / leg_.maxPowerW;
    } else if (e.violated == msg::LegConstraint::kPower) {
        e.violated = msg::LegConstraint::kNone;
        e.excess = 0.0;
    }
    return e;
}

void HabitualTask::keepCandidate(const Point2* path, std::size_t count, const Evaluation& evaluation) {
    if (count > msg::kMaxTrajectoryPoints || (haveCandidate_ && evaluation.score >= candidate_.score)) {
        return;
    }
    for (std::size_t i = 0; i < count; ++i) {
        candidatePath_[i] = path[i];
    }
    candidateCount_ = count;
    candidate_ = evaluation;
    haveCandidate_ = true;
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
        keepCandidate(rawPath_, count, evaluation);
    }
    if (attempt_ < lastAttempt_) {
        ++attempt_;
        ++counters_.repairAttempts;
        ++counters_.replans;
        if (count >= 2) {
            events_.report(events::kRepairAttempt, core::Severity::kInfo,
                           "habitual: leg %u: plan %.1f m %.0f J violates %s by %.1f: repair %u of %u",
                           static_cast<unsigned>(leg_.legId), evaluation.lengthM, evaluation.energyJ,
                           constraintName(evaluation.violated), evaluation.excess, static_cast<unsigned>(attempt_),
                           static_cast<unsigned>(lastAttempt_));
        } else {
            events_.report(events::kRepairAttempt, core::Severity::kInfo,
                           "habitual: leg %u: no path found: repair %u of %u", static_cast<unsigned>(leg_.legId),
                           static_cast<unsigned>(attempt_), static_cast<unsigned>(lastAttempt_));
        }
        queryActive_ = false;
        setState(msg::HabitualState::kRepairing, now);
        return;
    }
    if (haveCandidate_) {
        failUp(candidate_.violated, candidate_, now);
    } else {
        Evaluation none = evaluate(nullptr, 0, 0.0);
        none.violated = msg::LegConstraint::kNoPath;
        none.excess = 0.0;
        failUp(msg::LegConstraint::kNoPath, none, now);
    }
}

void HabitualTask::acceptPlan(std::size_t count, const Evaluation& evaluation, core::TimeNs now) {
    beginTrajectory(now);
    trajectory_.count = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count; ++i) {
        trajectory_.points[i] = msg::TrajectoryPoint{rawPath_[i].x, rawPath_[i].y};
    }
    (void)bus_.publish(trajectory_);
    escaping_ = false;
    ++counters_.plansSent;
    progressIndex_ = 0;
    plan_ = evaluation;
    predictedFactor_ = meanFactor();
    reportViolated_ = msg::LegConstraint::kNone;
    reportExcess_ = 0.0;
    events_.report(events::kPlanSent, core::Severity::kInfo,
                   "habitual: leg %u trajectory %u: %u pts, %.1f/%.1f m, %.0f/%.0f J%s",
                   static_cast<unsigned>(leg_.legId), static_cast<unsigned>(trajectory_.trajectoryId),
                   static_cast<unsigned>(count), evaluation.lengthM, evaluation.allowedLengthM, evaluation.energyJ,
                   evaluation.allowedEnergyJ, lastQuery_.marginDropped ? ", margin cut" : "");
    if (trigger_ != PlanTrigger::kNewLeg || attempt_ > 0) {
        ++counters_.minorAnomalies;
        events_.report(events::kMinorAnomaly, core::Severity::kWarning,
                       "habitual: leg %u replanned (%s, run %u): constraints hold: minor anomaly",
                       static_cast<unsigned>(leg_.legId), triggerName(trigger_), static_cast<unsigned>(attempt_));
    }
    setState(msg::HabitualState::kDriving, now);
}

void HabitualTask::failUp(msg::LegConstraint reason, const Evaluation& evaluation, core::TimeNs now) {
    sendStop(now);
    legActive_ = false;
    queryActive_ = false;
    ++counters_.failUps;
    plan_ = evaluation;
    reportViolated_ = reason;
    reportExcess_ = reason == msg::LegConstraint::kPathLength || reason == msg::LegConstraint::kEnergy ||
                            reason == msg::LegConstraint::kPower
                        ? evaluation.excess
                        : 0.0;
    const unsigned legId = static_cast<unsigned>(leg_.legId);
    switch (reason) {
        case msg::LegConstraint::kPathLength:
            events_.report(events::kFailUp, core::Severity::kError,
                           "habitual: leg %u fail-up: path length %.1f m > allowed %.1f m by %.1f m", legId,
                           evaluation.lengthM, evaluation.allowedLengthM, evaluation.excess);
            break;
        case msg::LegConstraint::kEnergy:
            events_.report(events::kFailUp, core::Severity::kError,
                           "habitual: leg %u fail-up: energy %.0f J > allowed %.0f J by %.0f J", legId,
                           evaluation.energyJ, evaluation.allowedEnergyJ, evaluation.excess);
            break;
        case msg::LegConstraint::kNoPath:
            events_.report(events::kFailUp, core::Severity::kError,
                           "habitual: leg %u fail-up: no path to (%.2f, %.2f) in %u planning runs", legId,
                           leg_.goalXM, leg_.goalYM, static_cast<unsigned>(attempt_) + 1U);
            break;
        case msg::LegConstraint::kPower:
            events_.report(events::kFailUp, core::Severity::kError,
                           "habitual: leg %u fail-up: power %.1f W > allowed %.1f W by %.1f W (power factor %.3f)",
                           legId, evaluation.powerW, evaluation.allowedPowerW, evaluation.excess, meanFactor());
            break;
        case msg::LegConstraint::kNone:
        case msg::LegConstraint::kCannotFollow:
        case msg::LegConstraint::kBadLeg:
            events_.report(events::kFailUp, core::Severity::kError, "habitual: leg %u fail-up: %s", legId,
                           constraintName(reason));
            break;
    }
    setState(msg::HabitualState::kFailedUp, now);
}

// ---- Driving ----------------------------------------------------------------------

void HabitualTask::updateOdometry() {
    if (!legActive_ || !poseSeen_ || pose_.initialised == 0) {
        return;
    }
    const Point2 here{pose_.xM, pose_.yM};
    if (!anchorSet_) {
        anchor_ = here;
        anchorHeading_ = pose_.headingRad;
        anchorSet_ = true;
        return;
    }
    const PowerModel model = powerModelFrom(tables_.habitual());
    const double moved = distance(here, anchor_);
    if (moved >= kOdometryStepM) {
        drivenLengthM_ += moved;
        drivenEnergyJ_ += motionEnergyJ(model, moved, 0.0, meanFactor());
        anchor_ = here;
    }
    const double turned = std::fabs(wrapAngleRad(pose_.headingRad - anchorHeading_));
    if (turned >= kOdometryStepRad) {
        drivenEnergyJ_ += motionEnergyJ(model, 0.0, turned, meanFactor());
        anchorHeading_ = pose_.headingRad;
    }
}

std::size_t HabitualTask::remainingPath(Point2* out) {
    const std::size_t count =
        trajectory_.count < msg::kMaxTrajectoryPoints ? trajectory_.count : msg::kMaxTrajectoryPoints;
    if (count < 2) {
        return 0;
    }
    const Point2 here{pose_.xM, pose_.yM};
    std::size_t best = progressIndex_ < count - 1 ? progressIndex_ : count - 2;
    Point2 bestPoint{0.0, 0.0};
    double bestD2 = INFINITY;
    for (std::size_t i = best; i + 1 < count; ++i) {
        const Point2 a{trajectory_.points[i].xM, trajectory_.points[i].yM};
        const Point2 b{trajectory_.points[i + 1].xM, trajectory_.points[i + 1].yM};
        const Point2 q = closestOnSegment(here, a, b);
        const double d2 = distanceSquared(here, q);
        if (d2 < bestD2) {
            bestD2 = d2;
            bestPoint = q;
            best = i;
        }
    }
    progressIndex_ = best;
    std::size_t n = 0;
    out[n++] = bestPoint;
    for (std::size_t i = best + 1; i < count; ++i) {
        out[n++] = Point2{trajectory_.points[i].xM, trajectory_.points[i].yM};
    }
    return n;
}

void HabitualTask::superviseDriving(core::TimeNs now) {
    // An escape starts inside an inflated disc and only moves away from it.
    if (trajectory_.count < 2 || !poseSeen_ || escaping_) {
        return;
    }
    Point2 remaining[msg::kMaxTrajectoryPoints];
    if (mapBuilder_.revision() != checkedRevision_) {
        (void)rebuildMap(&checkMap_, rse::geometry::clearanceRadiusM(tables_.roverGeometry()));
        checkedRevision_ = mapBuilder_.revision();
        const std::size_t n = remainingPath(remaining);
        for (std::size_t i = 0; i + 1 < n; ++i) {
            if (!checkMap_.segmentFree(remaining[i], remaining[i + 1])) {
                ++counters_.pathBlocked;
                ++counters_.replans;
                // Name the remembered disc that blocks it (the coarse map did not change).
                const double clearance = checkMap_.clearance();
                const RememberedHazard* blocker = nullptr;
                for (std::size_t k = 0; k < kMaxMapDiscs && blocker == nullptr; ++k) {
                    const RememberedHazard& h = mapBuilder_.slot(k);
                    const double reach = h.radiusM + clearance;
                    if (h.used && pointSegmentDistanceSquared(h.centre, remaining[i], remaining[i + 1]) <= reach * reach) {
                        blocker = &h;
                    }
                }
                if (blocker != nullptr) {
                    events_.report(events::kPathBlocked, core::Severity::kWarning,
                                   "habitual: leg %u: hazard %u at (%.2f, %.2f) r %.2f m on the path: stop, replan",
                                   static_cast<unsigned>(leg_.legId), static_cast<unsigned>(blocker->obstacleId),
                                   blocker->centre.x, blocker->centre.y, blocker->radiusM);
                } else {
                    events_.report(events::kPathBlocked, core::Severity::kWarning,
                                   "habitual: leg %u: path to (%.2f, %.2f) blocked: stop and replan",
                                   static_cast<unsigned>(leg_.legId), remaining[i + 1].x, remaining[i + 1].y);
                }
                sendStop(now);
                beginSession(PlanTrigger::kPathBlocked, 0, now);
                return;
            }
        }
    }
    if (!modesChanged_) {
        return;
    }
    const double factor = meanFactor();
    if (factor == predictedFactor_) {
        return;
    }
    predictedFactor_ = factor;
    const std::size_t n = remainingPath(remaining);
    const Evaluation e = evaluate(remaining, n, pose_.headingRad);
    plan_ = e;
    if (e.violated == msg::LegConstraint::kPower) {
        failUp(msg::LegConstraint::kPower, e, now);  // stops the rover; no path mends it
        return;
    }
    if (e.energyJ <= e.allowedEnergyJ) {
        return;
    }
    ++counters_.energyViolations;
    events_.report(events::kEnergyViolated, core::Severity::kWarning,
                   "habitual: leg %u power factor %.2f: %.0f J left > allowed %.0f J: repair",
                   static_cast<unsigned>(leg_.legId), factor, e.energyJ, e.allowedEnergyJ);
    Evaluation asEnergy = e;
    if (asEnergy.violated != msg::LegConstraint::kEnergy) {
        asEnergy.violated = msg::LegConstraint::kEnergy;
        asEnergy.excess = e.energyJ - e.allowedEnergyJ;
    }
    if (tables_.habitual().repair_attempts == 0) {
        failUp(msg::LegConstraint::kEnergy, asEnergy, now);
        return;
    }
    sendStop(now);
    beginSession(PlanTrigger::kEnergy, 1, now);
    ++counters_.repairAttempts;
    ++counters_.replans;
    keepCandidate(remaining, n, asEnergy);
    events_.report(events::kRepairAttempt, core::Severity::kInfo,
                   "habitual: leg %u: remaining path %.1f m %.0f J violates energy by %.0f: repair 1 of %u",
                   static_cast<unsigned>(leg_.legId), e.lengthM, e.energyJ, asEnergy.excess,
                   static_cast<unsigned>(lastAttempt_));
}

void HabitualTask::onCannotFollow(const msg::FollowerStatusMsg& status, core::TimeNs now) {
    ++counters_.cannotFollow;
    const bool hopeless = status.reason == msg::FollowReason::kDrivesHeld ||
                          status.reason == msg::FollowReason::kNotAutonomous || cannotFollowReplans_ > 0;
    events_.report(events::kCannotFollow, core::Severity::kWarning, "habitual: leg %u: follower gave up (%s): %s",
                   static_cast<unsigned>(leg_.legId), followReasonName(status.reason),
                   hopeless ? "fail-up" : "replanning once");
    if (hopeless) {
        Evaluation e = plan_;
        e.violated = msg::LegConstraint::kCannotFollow;
        e.excess = 0.0;
        failUp(msg::LegConstraint::kCannotFollow, e, now);
        return;
    }
    ++cannotFollowReplans_;
    ++counters_.replans;
    sendStop(now);
    beginSession(PlanTrigger::kCannotFollow, 0, now);
}

// ---- Outputs ----------------------------------------------------------------------

void HabitualTask::sendStop(core::TimeNs now) {
    escaping_ = false;
    trajectory_ = msg::TrajectoryMsg{};
    trajectory_.timeNs = now;
    trajectory_.trajectoryId = nextTrajectoryId_++;
    if (nextTrajectoryId_ == 0) {
        nextTrajectoryId_ = 1;
    }
    trajectory_.legId = leg_.legId;
    trajectory_.count = 0;
    (void)bus_.publish(trajectory_);
    ++counters_.stopsSent;
}

void HabitualTask::publishHazards(core::TimeNs now) {
    static_assert(msg::kMaxKnownHazards == kMaxMapDiscs, "KnownHazardsMsg carries the whole disc table");
    msg::KnownHazardsMsg m{};
    m.timeNs = now;
    m.revision = mapBuilder_.revision();
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = mapBuilder_.slot(k);
        if (h.used) {
            msg::KnownHazard& out = m.hazards[m.count++];
            // The seen disc, not the cover (map_builder.hpp).
            out.xM = static_cast<float>(h.seenCentre.x);
            out.yM = static_cast<float>(h.seenCentre.y);
            out.radiusM = static_cast<float>(h.seenRadiusM);
            out.obstacleId = h.obstacleId;
        }
    }
    (void)bus_.publish(m);
    ++counters_.hazardMapsSent;
    hazardsRevision_ = m.revision;
}

void HabitualTask::setState(msg::HabitualState state, core::TimeNs now) {
    if (state == state_) {
        return;
    }
    state_ = state;
    publishReport(now);
}

void HabitualTask::publishReport(core::TimeNs now) {
    msg::LegReportMsg r{};
    r.timeNs = now;
    r.legId = leg_.legId;
    r.state = state_;
    const bool failed = state_ == msg::HabitualState::kFailedUp;
    r.violated = failed ? reportViolated_ : msg::LegConstraint::kNone;
    r.predictedLengthM = plan_.lengthM;
    r.allowedLengthM = plan_.allowedLengthM;
    r.predictedEnergyJ = plan_.energyJ;
    r.allowedEnergyJ = plan_.allowedEnergyJ;
    r.predictedPowerW = plan_.powerW;
    r.allowedPowerW = plan_.allowedPowerW;
    r.excess = failed ? reportExcess_ : 0.0;
    r.legsAchieved = counters_.legsAchieved;
    r.failUps = counters_.failUps;
    r.replans = counters_.replans;
    r.minorAnomalies = counters_.minorAnomalies;
    (void)bus_.publish(r);
    report_ = r;
}

}  // namespace rse::habitual
