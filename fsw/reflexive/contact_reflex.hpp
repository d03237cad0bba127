// The contact reflex of the trajectory follower (issue 31, "Never a contact"):
// see that the rover is pushing against something within the frame the
// drives report it, zero the wheels, and back away from it, instead of
// pushing until the drives' over-current trips (all six at once, faults,
// resets, a call home: what a rock left out of a plan did before).
//
// Seeing it, from each DriveStatusMsg (every frame). A wheel is ACTIVE when
// it is commanded to turn (|target| >= kActiveWheelRadS), its drive is
// operational and its feedback is fresh (kFeedbackMaxAgeNs). An active wheel
// reads CONTACT when
//   pushing: |current| >= FOLLOWER.contact_current_a - far above what rolling
//            or turning draws (the load a push adds is the wheel's sliding
//            friction, several times the rolling resistance), or
//   stalled: its target has been steady for kSteadyFrames frames (the drive's
//            lag has settled) and it turns slower than contact_stall_ratio of
//            it, in the commanded direction or not at all.
// A contact is contact_wheels or more wheels reading contact in the same
// frame while the rover is commanded to drive (the follower's body speed not
// zero): one degraded drive, or five dragging a locked sixth, is not one.
//
// Backing off (the task drives it): straight back along the heading, opposite
// the direction driven, at contact_backoff_speed_m_s (reached within the rover
// geometry table's acceleration limit, as the follower's own commands), until the pose is
// contact_backoff_m from where the contact was seen, or kBackoffTimeFactor
// times the time that takes (+ 1 s: the drives' start), or another contact
// (backing into something), or the wheels stop being the follower's, or a
// new trajectory comes (a stop does not end it: the back-off is how a rover
// against a rock stops being so). Then the wheels go to zero and the follower
// reports kCannotFollow (kContact), or what a stop that came made it; until
// then kBackingOff.
//
// Pure: no bus, no events, no heap; the task reports.
#pragma once

#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::reflexive {

// A wheel turning slower than this is not commanded to turn.
constexpr double kActiveWheelRadS = 0.5;
// Feedback older than this says nothing about now (the drives report at 100 Hz).
constexpr core::TimeNs kFeedbackMaxAgeNs = 50 * core::kNsPerMs;
// Frames a wheel's target must hold (within kSteadyTargetTolerance) before
// its speed is judged against it: 20 frames, four of the drives' 50 ms lags.
constexpr std::uint8_t kSteadyFrames = 20;
constexpr double kSteadyTargetTolerance = 0.05;  // relative
// A back-off not done in this many times its nominal time (+ 1 s) ends anyway.
constexpr double kBackoffTimeFactor = 3.0;

// What one drive status says.
struct ContactReading {
    std::uint8_t wheelsPushing = 0;  // active wheels reading contact (pushing or stalled)
    double maxCurrentA = 0.0;        // the largest |current| among them
    bool contact = false;            // wheelsPushing >= contact_wheels
    std::uint8_t notFinite = 0;      // commanded wheels whose current or speed is not finite (not judged)
};

// Where a back-off stands after a step.
enum class BackoffState : std::uint8_t {
    kNone = 0,      // no back-off in hand
    kBacking = 1,   // driving back
};
enum class BackoffEnd : std::uint8_t {
    kNone = 0,
    kDistance = 1,  // backed contact_backoff_m
    kTimeout = 2,   // not there in time (kBackoffTimeFactor)
    kContact = 3,   // another contact while backing
    kReleased = 4,  // the wheels stopped being the follower's (mode, e-stop, interlock) or no pose
    kSuperseded = 5,  // a new trajectory came: the layer above has decided
};
const char* toString(BackoffEnd end);

class ContactReflex {
public:
    // Every drive status, in order.
    ContactReading observe(const msg::DriveStatusMsg& drives, const tables::FollowerTable& table);

    // Starts backing off from (x, y) after a contact seen driving in
    // directionSign (+1 forwards, -1 backwards).
    void startBackoff(double xM, double yM, double directionSign, core::TimeNs now);
    // Ends a back-off in hand (kReleased, a contact while backing): the caller zeroes the wheels.
    BackoffEnd abortBackoff(BackoffEnd why);

    // The body command of the back-off this run, reached from the last one at
    // no more than maxAccelMS2 over dtS, and whether it ended (*ended: why;
    // the command is then zero, at once, as every give-up). poseKnown false:
    // no fresh pose (the back-off ends, kReleased).
    // The contact's own run (now == the start) commands zero. The speed is
    // at most maxSpeedMS (the body limit), and the time allowed is reckoned
    // at the speed driven.
    double backoffStep(bool poseKnown, double xM, double yM, core::TimeNs now, double dtS, double maxAccelMS2,
                       double maxSpeedMS, const tables::FollowerTable& table, BackoffEnd* ended);

    BackoffState state() const { return state_; }
    double backedM() const { return backedM_; }
    const ContactReading& latest() const { return latest_; }

private:
    double steadyTarget_[msg::kWheelCount] = {};
    std::uint8_t steadyFrames_[msg::kWheelCount] = {};
    ContactReading latest_{};

    BackoffState state_ = BackoffState::kNone;
    double fromX_ = 0.0, fromY_ = 0.0;
    double sign_ = -1.0;   // the back-off's direction: opposite the one driven
    double backedM_ = 0.0;
    double speed_ = 0.0;   // the back-off's body speed commanded last
    core::TimeNs start_ = 0;
};

}  // namespace rse::reflexive
