// The reflexive trajectory follower task (every minor frame, 100 Hz, right after
// the estimator so it steers from this frame's pose): TrajectoryMsg in,
// WheelCommandMsg and FollowerStatusMsg out. The control law is
// TrajectoryFollower (trajectory_follower.hpp); this task is its bus side.
//
// Each run, with now = the clock at the start of the run and dt = now - the
// previous run (10 ms the first time; the follower caps it at 0.1 s):
//  1. Drains its pipe (core::InputPipe, at most kTrajectoryPipeDepth messages),
//     in arrival order:
//     - TrajectoryMsg: refused whole when it does not decode, count >
//       kMaxTrajectoryPoints, trajectoryId 0, speed not finite or negative, or a
//       used point not finite (counted, event 612 throttled, kBadTrajectory in
//       the status until the next accepted trajectory or give-up); the previous
//       trajectory stays in force. count 0 is a stop (kStopping, event 611);
//       otherwise following (re)starts on it (event 610), from the body speed
//       and turn rate already commanded.
//     - PoseEstimateMsg (latest kept), ModeMsg (AUTONOMOUS = mode 2, e-stop),
//       DriveStatusMsg (interlockTripped; read by the contact reflex,
//       contact_reflex.hpp), MissionHoldMsg (a hold ends a back-off). One that does not decode, a pose
//       with a non-finite x, y or heading, or a mode beyond MANUAL is counted,
//       evented (616, throttled) and ignored: the pipe's malformed count.
//  2. Wheels no longer ours, checked first: mode not AUTONOMOUS (kNotAutonomous),
//     else the e-stop or the drive interlock (kDrivesHeld). Following gives up
//     (kCannotFollow, event 614); any other state still moving is zeroed at
//     once (event 617). So a trajectory arriving outside AUTONOMOUS or while the
//     drives are held is accepted and given up in the same run.
//  2b. A contact read by a drive status of this run, while driving and the
//     wheels ours: the follower gives up (kContact), ContactMsg, event 618,
//     and the back-off starts (a contact while backing off ends it there).
//  3. One follower step with the pose when it is initialised and at most the
//     follower table's pose_timeout_ms old (else none: following gives up with
//     kPoseStale). Reaching the end is evented (613) once; a give-up by the
//     follower (cross-track, pose) is evented (614); the end of a stop (615).
//  3b. A back-off in hand replaces the step's command with its own (state
//     kBackingOff) until it ends (event 619).
//  4. WheelCommandMsg (skidSteerWheelSpeeds of the commanded (v, w)) in
//     AUTONOMOUS mode while following, stopping or still moving, plus one zero
//     command when the commanded (v, w) has come to zero; then nothing while at
//     rest, so MANUAL driving is never overridden. Outside AUTONOMOUS nothing is
//     published, with one exception: the frame the follower learns that
//     AUTONOMOUS was left while its last command was still moving the rover, it
//     publishes one zero command (nobody else would stop the wheels). While the
//     e-stop is set nothing is published (CAN I/O has zeroed every drive on the
//     same ModeMsg and would refuse the command as held).
//  5. FollowerStatusMsg when the state, the reason or the trajectory id changes,
//     and every 10th run (10 Hz).
// Tables (FOLLOWER, ROVER_GEOMETRY) are read every run. No heap; loops bounded
// by the pipe depth and kMaxTrajectoryPoints.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/reflexive/contact_reflex.hpp"
#include "fsw/reflexive/trajectory_follower.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::reflexive {

// Per frame: one drive status, one pose, now and then a mode, a mission hold
// or a trajectory (a stop and its replacement may come together).
constexpr std::uint16_t kTrajectoryPipeDepth = 8;
constexpr std::uint32_t kFollowerStatusEveryRuns = 10;

struct TrajectoryTaskCounters {
    std::uint32_t runs = 0;
    std::uint32_t trajectoriesAccepted = 0;  // count >= 1
    std::uint32_t stopsAccepted = 0;         // count 0
    std::uint32_t trajectoriesRefused = 0;
    std::uint32_t reached = 0;
    std::uint32_t gaveUpCrossTrack = 0;
    std::uint32_t gaveUpPoseStale = 0;
    std::uint32_t gaveUpDrivesHeld = 0;
    std::uint32_t gaveUpNotAutonomous = 0;
    std::uint32_t stopsCompleted = 0;        // kStopping -> kIdle through the deceleration
    std::uint32_t halts = 0;                 // zeroed at once outside following (event 617)
    std::uint32_t malformedInputs = 0;       // pose, mode, drive status (not trajectories): the pipe's count
    std::uint32_t wheelCommandsPublished = 0;
    std::uint32_t statusPublished = 0;
    std::uint32_t contacts = 0;        // contacts seen (event 618; ContactMsg unless unplaced)
    std::uint32_t contactsUnplaced = 0;  // of those, seen with no fresh pose: wheels to zero, no back-off, no ContactMsg
    std::uint32_t backoffs = 0;        // back-offs ended, whatever the reason (event 619)
    std::uint32_t backoffsCut = 0;     // of those, ended before contact_backoff_m (timeout, contact, released, superseded)
    std::uint8_t lastBackoffEnd = 0;   // how the last back-off ended (BackoffEnd; 0: none yet)
    std::uint32_t wheelReadingsNotFinite = 0;  // active wheels whose current or speed was not finite (not judged)
};

class TrajectoryTask final : public core::Task {
public:
    TrajectoryTask(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                   const tables::TableService& tables);

    // Creates the pipe "follower" and routes TrajectoryMsg, PoseEstimateMsg,
    // ModeMsg and DriveStatusMsg to their takers.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    msg::FollowerState state() const { return follower_.state(); }
    // Built every run; published on change and at 10 Hz.
    const msg::FollowerStatusMsg& latestStatus() const { return status_; }
    const TrajectoryTaskCounters& counters() const { return counters_; }
    const TrajectoryFollower& follower() const { return follower_; }
    const ContactReflex& contactReflex() const { return contact_; }
    bool autonomous() const { return autonomous_; }

private:
    // The pipe's takers (step 1). Pose and mode return kInvalidArgument for
    // content they cannot use: the pipe counts it with the malformed.
    void takeTrajectory(const msg::TrajectoryMsg& t);
    void refuseUndecodableTrajectory(const core::Message& message);
    core::Status takePose(const msg::PoseEstimateMsg& pose);
    core::Status takeMode(const msg::ModeMsg& mode);
    void takeDriveStatus(const msg::DriveStatusMsg& drives);
    core::Status takeHold(const msg::MissionHoldMsg& hold);
    void refuse(std::uint32_t trajectoryId, const char* why);
    void releaseWheels();  // step 2
    bool poseFresh(core::TimeNs now) const;
    // Counts and events reaching, giving up and the end of a stop (not one cut
    // short by releaseWheels, which events its own).
    void reportTransition(msg::FollowerState before, const FollowerOutput& out, core::TimeNs now, bool released);
    void publishWheels(const FollowerOutput& out, core::TimeNs now);
    // The contact reflex (contact_reflex.hpp): a contact seen while driving
    // stops the wheels and starts the back-off; the back-off's command
    // replaces the follower's while it lasts.
    void seeContact(core::TimeNs now);
    void endBackoff(BackoffEnd why);
    void applyBackoff(core::TimeNs now, double dtS, FollowerOutput* out);
    void publishStatus(const FollowerOutput& out, core::TimeNs now);

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    TrajectoryFollower follower_;
    ContactReflex contact_;
    bool contactPending_ = false;  // a drive status of this run's drain read a contact
    ContactReading contactReading_{};  // the first such reading of the run
    bool held_ = false;            // fault protection holds the mission (MissionHoldMsg)
    core::InputPipe input_;
    core::TimeNs runStart_ = 0;  // now of the current run (a stop's start)

    msg::PoseEstimateMsg pose_{};
    bool havePose_ = false;
    bool autonomous_ = false;  // until a ModeMsg says otherwise
    bool estop_ = false;
    bool interlockTripped_ = false;

    std::uint32_t trajectoryId_ = 0;  // the trajectory (or stop) in force
    bool refusalPending_ = false;     // kBadTrajectory in the status
    core::TimeNs lastRun_ = 0;
    bool hasRun_ = false;
    core::TimeNs stopStart_ = 0;
    double stopFromSpeed_ = 0.0;
    bool lastCommandMoving_ = false;  // the last wheel command published (or CAN I/O's) is not zero

    bool statusEverPublished_ = false;
    msg::FollowerState publishedState_ = msg::FollowerState::kIdle;
    msg::FollowReason publishedReason_ = msg::FollowReason::kNone;
    std::uint32_t publishedId_ = 0;
    std::uint32_t publishedBackoffs_ = 0;
    std::uint32_t publishedUnplaced_ = 0;
    msg::FollowerStatusMsg status_{};
    TrajectoryTaskCounters counters_{};
};

}  // namespace rse::reflexive
