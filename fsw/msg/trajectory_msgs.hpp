// The habitual <-> reflexive boundary: the local trajectory to follow, and how
// following it goes. Site frame as in estimator_msgs.hpp (metres, x east, y north).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// A local plan is at most this many points: RRT* output after shortcutting is a
// handful of corners on a leg of tens of metres.
constexpr std::size_t kMaxTrajectoryPoints = 32;

struct TrajectoryPoint {
    double xM;
    double yM;
};

// Replaces whatever the follower was doing. count 0 means "stop": decelerate to
// zero within the acceleration limit and hold until the next trajectory.
struct TrajectoryMsg {
    static constexpr core::MsgId kMsgId = ids::kTrajectory;
    std::int64_t timeNs;
    std::uint32_t trajectoryId;  // nonzero; a new id for every trajectory the habitual layer sends
    std::uint32_t legId;         // the leg (LegCommandMsg) this trajectory serves
    double speedMS;              // cruise speed along the path; the follower caps it at the rover geometry table's limit
    std::uint8_t count;          // points used, 0..kMaxTrajectoryPoints
    std::uint8_t pad[7];
    TrajectoryPoint points[kMaxTrajectoryPoints];  // points[0] is where the rover was when it was planned
};

enum class FollowerState : std::uint8_t {
    kIdle = 0,          // nothing to follow (start-up, a stop completed, outside AUTONOMOUS)
    kFollowing = 1,
    kReached = 2,       // within the arrival tolerance of the last point; decelerating to zero
    kCannotFollow = 3,  // gave up on the trajectory (reason says why); wheels commanded to zero at once
    kStopping = 4,      // decelerating after a stop trajectory (count 0), within the acceleration limits
    kBackingOff = 5,    // a contact stopped the rover: backing away from it (ContactMsg); then kCannotFollow (kContact)
};

enum class FollowReason : std::uint8_t {
    kNone = 0,
    kCrossTrackError = 1,  // farther from the path than the follower table allows
    kPoseStale = 2,        // no valid pose estimate within the follower table's timeout
    kDrivesHeld = 3,       // e-stop or the drive interlock holds the wheels at zero
    kNotAutonomous = 4,    // the rover left AUTONOMOUS mode
    kBadTrajectory = 5,    // refused on arrival: count, ids or a point not finite
    kContact = 6,          // the rover touched something (ContactMsg): stopped at once, backed off
};

struct FollowerStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kFollowerStatus;
    std::int64_t timeNs;
    std::uint32_t trajectoryId;  // the trajectory this status is about (0: none yet)
    FollowerState state;
    FollowReason reason;
    std::uint8_t targetIndex;    // the path segment being followed ends at points[targetIndex]
    std::uint8_t pad[5];
    double crossTrackErrorM;     // distance from the rover to the path
    double remainingM;           // path length left to the last point
    double commandedSpeedMS;     // body (v, w) sent this cycle, after limits
    double commandedTurnRateRadS;
    // The contact reflex's counts since start (DRIVES telemetry): contacts
    // seen with no fresh pose (wheels zeroed, no back-off), back-offs ended
    // and those cut short, how the last one ended (reflexive::BackoffEnd:
    // 0 none yet, 1 backed the whole way, 2 timeout, 3 another contact,
    // 4 released, 5 superseded), and active wheels whose current or speed
    // was not a finite number (not judged).
    std::uint32_t contactsUnplaced;
    std::uint32_t backoffs;
    std::uint32_t backoffsCut;
    std::uint32_t wheelReadingsNotFinite;
    std::uint8_t lastBackoffEnd;
    std::uint8_t pad2[7];
};

// One per contact the follower sees (fsw/reflexive/contact_reflex.hpp): the
// drives of several wheels pushing at once (current far above a rolling
// wheel's, or the wheels commanded but not turning) while the rover is
// commanded to move. The follower has zeroed the wheels in the same run and
// backs off; the habitual layer remembers where (a hazard the detector did
// not report) and plans round it.
struct ContactMsg {
    static constexpr core::MsgId kMsgId = ids::kContact;
    std::int64_t timeNs;       // the run that saw it
    std::uint32_t contacts;    // contacts seen since start, this one included
    std::uint32_t trajectoryId;  // the trajectory being followed (0: none)
    double xM;                 // the pose estimate when it was seen (site frame)
    double yM;
    double headingRad;
    double directionSign;      // +1 driving forwards, -1 backwards (the side of the rover that touched)
    double maxCurrentA;        // the largest pushing wheel's current
    std::uint8_t wheelsPushing;  // wheels that read contact in that frame
    std::uint8_t pad[7];
};

}  // namespace rse::msg
