#include "fsw/reflexive/trajectory_task.hpp"

#include <cmath>

#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/reflexive/manual_drive.hpp"
#include "fsw/reflexive/reflexive_events.hpp"

namespace rse::reflexive {

namespace {

// The first run has no previous one to measure dt from: one nominal minor frame.
constexpr double kFirstStepS = 0.01;

const char* stateName(msg::FollowerState s) {
    switch (s) {
        case msg::FollowerState::kIdle:
            return "idle";
        case msg::FollowerState::kFollowing:
            return "following";
        case msg::FollowerState::kReached:
            return "reached";
        case msg::FollowerState::kCannotFollow:
            return "cannot follow";
        case msg::FollowerState::kStopping:
            return "stopping";
        case msg::FollowerState::kBackingOff:
            return "backing off";
    }
    return "?";
}

}  // namespace

TrajectoryTask::TrajectoryTask(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                               const tables::TableService& tables)
    : clock_(clock),
      bus_(bus),
      events_(events),
      tables_(tables),
      input_(bus, events,
             core::InputPipeConfig{"follower", kTrajectoryPipeDepth, events::kFollowerInputMalformed, "follower"}) {}

core::Status TrajectoryTask::init() {
    // A trajectory that does not decode is a refused trajectory (event 612,
    // kBadTrajectory in the status), not a malformed input.
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&TrajectoryTask::takeTrajectory, &TrajectoryTask::refuseUndecodableTrajectory>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&TrajectoryTask::takePose>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&TrajectoryTask::takeMode>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&TrajectoryTask::takeDriveStatus>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&TrajectoryTask::takeHold>(this);
    }
    return status;
}

void TrajectoryTask::run(const core::FrameContext&) {
    const core::TimeNs now = clock_.now();
    const double dt = hasRun_ ? static_cast<double>(now - lastRun_) / static_cast<double>(core::kNsPerSec)
                              : kFirstStepS;
    lastRun_ = now;
    hasRun_ = true;
    ++counters_.runs;

    runStart_ = now;
    input_.drain();
    counters_.malformedInputs = input_.malformed();
    const msg::FollowerState before = follower_.state();
    const bool released = !autonomous_ || estop_ || interlockTripped_;
    if (released) {
        releaseWheels();
        endBackoff(contact_.abortBackoff(BackoffEnd::kReleased));
    } else if (held_) {
        // Fault protection holds the mission: CAN I/O holds the drives at
        // zero; a back-off must not resume by itself when the hold ends.
        endBackoff(contact_.abortBackoff(BackoffEnd::kReleased));
    }
    if (!released && contactPending_) {
        if (contact_.state() == BackoffState::kBacking) {
            endBackoff(contact_.abortBackoff(BackoffEnd::kContact));  // backed into something: stop there
        } else if (follower_.speedMS() != 0.0) {
            seeContact(now);
        }
    }
    contactPending_ = false;

    const FollowerPose pose{pose_.xM, pose_.yM, pose_.headingRad};
    FollowerOutput out =
        follower_.step(poseFresh(now) ? &pose : nullptr, tables_.follower(), tables_.roverGeometry(), dt);
    reportTransition(before, out, now, released);
    applyBackoff(now, dt, &out);
    publishWheels(out, now);
    publishStatus(out, now);
}

void TrajectoryTask::seeContact(core::TimeNs now) {
    const double direction = follower_.speedMS() > 0.0 ? 1.0 : -1.0;
    const ContactReading reading = contactReading_;
    if (follower_.state() == msg::FollowerState::kFollowing) {
        follower_.giveUp(msg::FollowReason::kContact);
    } else {
        follower_.haltNow(msg::FollowReason::kContact);
    }
    ++counters_.contacts;
    if (!poseFresh(now)) {
        // Wheels to zero, but no back-off and nothing to remember: with no
        // fresh pose there is no telling where, nor how far it backed.
        ++counters_.contactsUnplaced;
        events_.report(events::kContactSeen, core::Severity::kWarning,
                       "follower: contact: %u wheels pushing, up to %.2f A; wheels to zero; no fresh pose: not "
                       "backing off (%u so far)",
                       static_cast<unsigned>(reading.wheelsPushing), reading.maxCurrentA,
                       static_cast<unsigned>(counters_.contacts));
        return;
    }
    contact_.startBackoff(pose_.xM, pose_.yM, direction, now);
    msg::ContactMsg m{};
    m.timeNs = now;
    m.contacts = counters_.contacts;
    m.trajectoryId = trajectoryId_;
    m.xM = pose_.xM;
    m.yM = pose_.yM;
    m.headingRad = pose_.headingRad;
    m.directionSign = direction;
    m.maxCurrentA = reading.maxCurrentA;
    m.wheelsPushing = reading.wheelsPushing;
    (void)bus_.publish(m);
    events_.report(events::kContactSeen, core::Severity::kWarning,
                   "follower: contact driving %s at (%.2f, %.2f): %u wheels pushing, up to %.2f A; wheels to zero, "
                   "backing off %.2f m (%u so far)",
                   direction > 0.0 ? "forwards" : "backwards", pose_.xM, pose_.yM,
                   static_cast<unsigned>(reading.wheelsPushing), reading.maxCurrentA,
                   static_cast<double>(tables_.follower().contact_backoff_m), static_cast<unsigned>(counters_.contacts));
}

void TrajectoryTask::endBackoff(BackoffEnd why) {
    if (why == BackoffEnd::kNone) {
        return;
    }
    ++counters_.backoffs;
    counters_.backoffsCut += why == BackoffEnd::kDistance ? 0U : 1U;
    counters_.lastBackoffEnd = static_cast<std::uint8_t>(why);
    events_.report(events::kBackedOff, why == BackoffEnd::kDistance ? core::Severity::kInfo : core::Severity::kWarning,
                   "follower: back-off ended (%s) %.2f m from the contact; cannot follow (contact)", toString(why),
                   contact_.backedM());
}

void TrajectoryTask::applyBackoff(core::TimeNs now, double dtS, FollowerOutput* out) {
    if (contact_.state() != BackoffState::kBacking) {
        return;
    }
    BackoffEnd ended = BackoffEnd::kNone;
    const double dt = dtS > 0.0 ? (dtS < kMaxFollowerStepS ? dtS : kMaxFollowerStepS) : 0.0;
    const tables::RoverGeometryTable& g = tables_.roverGeometry();
    const double v = contact_.backoffStep(poseFresh(now), pose_.xM, pose_.yM, now, dt,
                                          static_cast<double>(g.max_accel_m_s2),
                                          static_cast<double>(g.max_body_speed_m_s), tables_.follower(), &ended);
    if (ended != BackoffEnd::kNone) {
        endBackoff(ended);
        return;  // the follower's own output: zero, cannot follow (contact)
    }
    out->speedMS = v;
    out->turnRateRadS = 0.0;
    out->state = msg::FollowerState::kBackingOff;
    out->reason = msg::FollowReason::kContact;
}

core::Status TrajectoryTask::takePose(const msg::PoseEstimateMsg& pose) {
    if (!std::isfinite(pose.xM) || !std::isfinite(pose.yM) || !std::isfinite(pose.headingRad)) {
        input_.explain("pose not finite");
        return core::Status::kInvalidArgument;
    }
    pose_ = pose;
    havePose_ = true;
    return core::Status::kOk;
}

core::Status TrajectoryTask::takeMode(const msg::ModeMsg& mode) {
    if (mode.mode >= msg::mode::kCount) {
        input_.explain("mode %u is no mode", static_cast<unsigned>(mode.mode));
        return core::Status::kInvalidArgument;
    }
    autonomous_ = mode.mode == msg::mode::kAutonomous;
    estop_ = mode.estop != 0;
    return core::Status::kOk;
}

core::Status TrajectoryTask::takeHold(const msg::MissionHoldMsg& hold) {
    if (!msg::holdUsable(hold)) {
        input_.explain("hold reasons 0x%x not known", static_cast<unsigned>(hold.reasons));
        return core::Status::kInvalidArgument;
    }
    held_ = hold.reasons != 0U;
    return core::Status::kOk;
}

void TrajectoryTask::takeDriveStatus(const msg::DriveStatusMsg& drives) {
    interlockTripped_ = drives.interlockTripped != 0;
    const ContactReading r = contact_.observe(drives, tables_.follower());
    for (std::uint8_t k = 0; k < r.notFinite; ++k) {
        ++counters_.wheelReadingsNotFinite;
        if (core::isReportableOccurrence(counters_.wheelReadingsNotFinite)) {
            events_.report(events::kFollowerInputMalformed, core::Severity::kWarning,
                           "follower: a commanded wheel's current or speed is not a finite number: not judged by "
                           "the contact reflex (%u so far)",
                           static_cast<unsigned>(counters_.wheelReadingsNotFinite));
        }
    }
    if (r.contact && !contactPending_) {
        contactReading_ = r;  // the first of the run's statuses that read a contact
    }
    contactPending_ = r.contact || contactPending_;
}

void TrajectoryTask::refuseUndecodableTrajectory(const core::Message&) { refuse(0, "does not decode"); }

void TrajectoryTask::takeTrajectory(const msg::TrajectoryMsg& t) {
    if (t.count > msg::kMaxTrajectoryPoints) {
        refuse(t.trajectoryId, "more points than kMaxTrajectoryPoints");
        return;
    }
    if (t.trajectoryId == 0) {
        refuse(t.trajectoryId, "trajectory id 0");
        return;
    }
    if (!std::isfinite(t.speedMS) || t.speedMS < 0.0) {
        refuse(t.trajectoryId, "speed not finite or negative");
        return;
    }
    for (std::size_t i = 0; i < t.count; ++i) {
        if (!std::isfinite(t.points[i].xM) || !std::isfinite(t.points[i].yM)) {
            refuse(t.trajectoryId, "a point not finite");
            return;
        }
    }
    trajectoryId_ = t.trajectoryId;
    refusalPending_ = false;
    if (t.count > 0) {
        // A new path: the layer above has decided. A stop does not cut a
        // back-off short: the rover is against something, and the back-off
        // (slow, short, bounded) is how it stops being so.
        endBackoff(contact_.abortBackoff(BackoffEnd::kSuperseded));
    }
    if (t.count == 0) {
        ++counters_.stopsAccepted;
        stopStart_ = runStart_;
        stopFromSpeed_ = follower_.speedMS();
        events_.report(events::kStopAccepted, core::Severity::kInfo,
                       "follower: stop %u (leg %u): decelerating from v=%.2f m/s w=%.2f rad/s",
                       static_cast<unsigned>(t.trajectoryId), static_cast<unsigned>(t.legId),
                       follower_.speedMS(), follower_.turnRateRadS());
        follower_.stop();
        return;
    }
    (void)follower_.follow(t.points, t.count, t.speedMS);  // checked above: cannot refuse
    ++counters_.trajectoriesAccepted;
    events_.report(events::kTrajectoryAccepted, core::Severity::kInfo,
                   "follower: trajectory %u (leg %u): %u points, %.1f m at %.2f m/s",
                   static_cast<unsigned>(t.trajectoryId), static_cast<unsigned>(t.legId),
                   static_cast<unsigned>(t.count), follower_.latest().remainingM, t.speedMS);
}

void TrajectoryTask::refuse(std::uint32_t trajectoryId, const char* why) {
    ++counters_.trajectoriesRefused;
    refusalPending_ = true;
    if (core::isReportableOccurrence(counters_.trajectoriesRefused)) {
        events_.report(events::kTrajectoryRefused, core::Severity::kError,
                       "follower: trajectory %u refused: %s (%u so far); %u stays in force",
                       static_cast<unsigned>(trajectoryId), why, static_cast<unsigned>(counters_.trajectoriesRefused),
                       static_cast<unsigned>(trajectoryId_));
    }
}

void TrajectoryTask::releaseWheels() {
    const msg::FollowReason reason =
        !autonomous_ ? msg::FollowReason::kNotAutonomous : msg::FollowReason::kDrivesHeld;
    if (follower_.state() == msg::FollowerState::kFollowing) {
        follower_.giveUp(reason);  // evented by reportTransition
        return;
    }
    if (follower_.moving()) {
        const msg::FollowerState state = follower_.state();
        follower_.haltNow(reason);
        ++counters_.halts;
        events_.report(events::kFollowerHalted, core::Severity::kWarning,
                       "follower: wheels to zero at once while %s: %s", stateName(state),
                       !autonomous_ ? "left AUTONOMOUS" : (estop_ ? "software e-stop set" : "drive interlock tripped"));
    }
}

bool TrajectoryTask::poseFresh(core::TimeNs now) const {
    const core::TimeNs timeout = static_cast<core::TimeNs>(tables_.follower().pose_timeout_ms) * core::kNsPerMs;
    return havePose_ && pose_.initialised != 0 && now - pose_.timeNs <= timeout;
}

void TrajectoryTask::reportTransition(msg::FollowerState before, const FollowerOutput& out, core::TimeNs now,
                                      bool released) {
    const unsigned id = static_cast<unsigned>(trajectoryId_);
    if (before == msg::FollowerState::kFollowing && out.state == msg::FollowerState::kReached) {
        ++counters_.reached;
        events_.report(events::kTrajectoryReached, core::Severity::kInfo,
                       "follower: trajectory %u reached, %.3f m from its last point", id, out.toEndM);
        return;
    }
    if (before == msg::FollowerState::kFollowing && out.state == msg::FollowerState::kCannotFollow) {
        refusalPending_ = false;
        switch (out.reason) {
            case msg::FollowReason::kCrossTrackError:
                ++counters_.gaveUpCrossTrack;
                events_.report(events::kFollowerGaveUp, core::Severity::kWarning,
                               "follower: gave up on %u: cross-track %.2f m > %.2f m; wheels to zero", id,
                               out.crossTrackErrorM, static_cast<double>(tables_.follower().max_cross_track_m));
                break;
            case msg::FollowReason::kPoseStale:
                ++counters_.gaveUpPoseStale;
                if (!havePose_ || pose_.initialised == 0) {
                    events_.report(events::kFollowerGaveUp, core::Severity::kWarning,
                                   "follower: gave up on %u: no initialised pose estimate; wheels to zero", id);
                } else {
                    events_.report(events::kFollowerGaveUp, core::Severity::kWarning,
                                   "follower: gave up on %u: pose %lld ms old > %u ms; wheels to zero", id,
                                   static_cast<long long>((now - pose_.timeNs) / core::kNsPerMs),
                                   static_cast<unsigned>(tables_.follower().pose_timeout_ms));
                }
                break;
            case msg::FollowReason::kDrivesHeld:
                ++counters_.gaveUpDrivesHeld;
                events_.report(events::kFollowerGaveUp, core::Severity::kWarning,
                               "follower: gave up on %u: %s; wheels to zero", id,
                               estop_ ? "software e-stop set" : "drive interlock tripped");
                break;
            case msg::FollowReason::kNotAutonomous:
                ++counters_.gaveUpNotAutonomous;
                events_.report(events::kFollowerGaveUp, core::Severity::kWarning,
                               "follower: gave up on %u: not in AUTONOMOUS mode; wheels to zero", id);
                break;
            case msg::FollowReason::kContact:  // evented by seeContact
            case msg::FollowReason::kNone:
            case msg::FollowReason::kBadTrajectory:
                break;
        }
        return;
    }
    if (before == msg::FollowerState::kStopping && out.state == msg::FollowerState::kIdle && !released) {
        ++counters_.stopsCompleted;
        events_.report(events::kFollowerStopped, core::Severity::kInfo,
                       "follower: stop %u done: at rest %.2f s after it came (from %.2f m/s)", id,
                       static_cast<double>(now - stopStart_) / static_cast<double>(core::kNsPerSec), stopFromSpeed_);
    }
}

void TrajectoryTask::publishWheels(const FollowerOutput& out, core::TimeNs now) {
    if (estop_) {
        lastCommandMoving_ = false;  // CAN I/O zeroed every drive when the e-stop came
        return;
    }
    const bool moving = out.speedMS != 0.0 || out.turnRateRadS != 0.0;
    if (autonomous_) {
        const bool active =
            out.state == msg::FollowerState::kFollowing || out.state == msg::FollowerState::kStopping || moving;
        if (!active && !lastCommandMoving_) {
            return;
        }
    } else if (!lastCommandMoving_) {
        return;
    }
    const WheelSpeeds speeds = skidSteerWheelSpeeds(out.speedMS, out.turnRateRadS, tables_.roverGeometry());
    msg::WheelCommandMsg command{};
    command.timeNs = now;
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        command.velocityRadS[i] = speeds.radS[i];
    }
    (void)bus_.publish(command);
    ++counters_.wheelCommandsPublished;
    lastCommandMoving_ = moving;
}

void TrajectoryTask::publishStatus(const FollowerOutput& out, core::TimeNs now) {
    status_.timeNs = now;
    status_.trajectoryId = trajectoryId_;
    status_.state = out.state;
    status_.reason = refusalPending_ ? msg::FollowReason::kBadTrajectory : out.reason;
    status_.targetIndex = out.targetIndex;
    status_.crossTrackErrorM = out.crossTrackErrorM;
    status_.remainingM = out.remainingM;
    status_.commandedSpeedMS = out.speedMS;
    status_.commandedTurnRateRadS = out.turnRateRadS;
    status_.contactsUnplaced = counters_.contactsUnplaced;
    status_.backoffs = counters_.backoffs;
    status_.backoffsCut = counters_.backoffsCut;
    status_.wheelReadingsNotFinite = counters_.wheelReadingsNotFinite;
    status_.lastBackoffEnd = counters_.lastBackoffEnd;
    // A back-off's end or an unplaced contact is news for the ground at once.
    const bool changed = !statusEverPublished_ || status_.state != publishedState_ ||
                         status_.reason != publishedReason_ || status_.trajectoryId != publishedId_ ||
                         status_.backoffs != publishedBackoffs_ || status_.contactsUnplaced != publishedUnplaced_;
    if (!changed && counters_.runs % kFollowerStatusEveryRuns != 0) {
        return;
    }
    (void)bus_.publish(status_);
    ++counters_.statusPublished;
    statusEverPublished_ = true;
    publishedState_ = status_.state;
    publishedReason_ = status_.reason;
    publishedId_ = status_.trajectoryId;
    publishedBackoffs_ = status_.backoffs;
    publishedUnplaced_ = status_.contactsUnplaced;
}

}  // namespace rse::reflexive
