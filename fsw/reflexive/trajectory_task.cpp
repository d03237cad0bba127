#include "fsw/reflexive/trajectory_task.hpp"

#include <cmath>

#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
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
    }
    return "?";
}

}  // namespace

core::Status TrajectoryTask::init() {
    core::Status status = bus_.createPipe("follower", kTrajectoryPipeDepth, &pipe_);
    const core::MsgId ids[] = {msg::ids::kTrajectory, msg::ids::kPoseEstimate, msg::ids::kMode,
                               msg::ids::kDriveStatus};
    for (core::MsgId id : ids) {
        if (core::isOk(status)) {
            status = bus_.subscribe(pipe_, id);
        }
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

    takeInputs(now);
    const msg::FollowerState before = follower_.state();
    const bool released = !autonomous_ || estop_ || interlockTripped_;
    if (released) {
        releaseWheels();
    }

    const FollowerPose pose{pose_.xM, pose_.yM, pose_.headingRad};
    const FollowerOutput out =
        follower_.step(poseFresh(now) ? &pose : nullptr, tables_.follower(), tables_.roverGeometry(), dt);
    reportTransition(before, out, now, released);
    publishWheels(out, now);
    publishStatus(out, now);
}

void TrajectoryTask::takeInputs(core::TimeNs now) {
    while (core::isOk(bus_.receive(pipe_, &inbox_))) {  // bounded by the pipe depth
        switch (inbox_.header.id) {
            case msg::ids::kTrajectory:
                takeTrajectory(now);
                break;
            case msg::ids::kPoseEstimate: {
                msg::PoseEstimateMsg pose{};
                if (!core::isOk(inbox_.decode(&pose))) {
                    malformed("pose estimate that does not decode");
                } else if (!std::isfinite(pose.xM) || !std::isfinite(pose.yM) || !std::isfinite(pose.headingRad)) {
                    malformed("pose estimate not finite");
                } else {
                    pose_ = pose;
                    havePose_ = true;
                }
                break;
            }
            case msg::ids::kMode: {
                msg::ModeMsg mode{};
                if (!core::isOk(inbox_.decode(&mode))) {
                    malformed("mode message that does not decode");
                } else if (mode.mode >= msg::mode::kCount) {
                    malformed("mode message with an unknown mode");
                } else {
                    autonomous_ = mode.mode == msg::mode::kAutonomous;
                    estop_ = mode.estop != 0;
                }
                break;
            }
            case msg::ids::kDriveStatus: {
                msg::DriveStatusMsg drives{};
                if (!core::isOk(inbox_.decode(&drives))) {
                    malformed("drive status that does not decode");
                } else {
                    interlockTripped_ = drives.interlockTripped != 0;
                }
                break;
            }
            default:
                malformed("message of an id not subscribed");
                break;
        }
    }
}

void TrajectoryTask::takeTrajectory(core::TimeNs now) {
    msg::TrajectoryMsg t{};
    if (!core::isOk(inbox_.decode(&t))) {
        refuse(0, "does not decode");
        return;
    }
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
    if (t.count == 0) {
        ++counters_.stopsAccepted;
        stopStart_ = now;
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

void TrajectoryTask::malformed(const char* what) {
    ++counters_.malformedInputs;
    if (core::isReportableOccurrence(counters_.malformedInputs)) {
        events_.report(events::kFollowerInputMalformed, core::Severity::kError,
                       "follower: %s ignored (%u so far)", what, static_cast<unsigned>(counters_.malformedInputs));
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
    const bool changed = !statusEverPublished_ || status_.state != publishedState_ ||
                         status_.reason != publishedReason_ || status_.trajectoryId != publishedId_;
    if (!changed && counters_.runs % kFollowerStatusEveryRuns != 0) {
        return;
    }
    (void)bus_.publish(status_);
    ++counters_.statusPublished;
    statusEverPublished_ = true;
    publishedState_ = status_.state;
    publishedReason_ = status_.reason;
    publishedId_ = status_.trajectoryId;
}

}  // namespace rse::reflexive
