// The back-up manoeuvre (docs/deliberative.md, "No path the replans cannot
// fix: back up"): when a "no path" fail-up comes with PLANNER.replan_limit
// replans of the goal spent, the rover backs up PLANNER.no_path_backup_m along
// the track it drove, to the first point there clear of the seen hazards and
// the coarse map (LegEndClearance), as a leg of its own; reached, the goal is
// replanned from there. At most PLANNER.no_path_backup_limit per goal.
//
// The driven track: the pose every kTrackStepM, the last kTrackPoints points;
// not recorded while backing up, and cut back to the back-up's end when it is
// reached, so a further back-up goes on back rather than over the ground just
// reversed along.
//
// Owns the track, the target and whether a back-up is in force; the leg
// itself is sent by the LegSequencer (its leg ids and power bound). Events
// 925 (backing up) and 926 (backed up). No bus, no tables.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/leg_end_clearance.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"

namespace rse::deliberative {

// The driven track kept for backing up: a point every kTrackStepM, the last kTrackPoints.
constexpr double kTrackStepM = 0.25;
constexpr std::size_t kTrackPoints = 64;

class BackUpManoeuvre {
public:
    explicit BackUpManoeuvre(core::EventLog& events) : events_(events) {}

    // Every run, with the latest pose (poseSeen: there is one): a track point
    // when the rover has moved kTrackStepM from the last (not while backing up).
    void record(const msg::PoseEstimateMsg& pose, bool poseSeen);

    // The point distanceM back along the track from the pose, clear of what
    // `clear` keeps clear of (then every kTrackStepM up to twice distanceM);
    // false when there is none. *keep: the track points older than the target.
    bool target(const msg::PoseEstimateMsg& pose, double distanceM, const LegEndClearance& clear, msg::PlanLeg* out,
                std::size_t* keep) const;

    // A back-up of distanceM (PLANNER.no_path_backup_m), the goal's limit
    // (PLANNER.no_path_backup_limit) not reached: true and in force (event 925,
    // naming replans, the goal's replans spent). False when the limit is
    // reached, the distance is 0 or no target is found.
    bool start(const msg::PoseEstimateMsg& pose, double distanceM, std::uint32_t limit, std::uint32_t replans,
               const LegEndClearance& clear);
    // The back-up leg was reached: no longer in force, the track cut back to
    // its end and the pose recorded (event 926 for the goal numbered goalNumber).
    void reached(const msg::PoseEstimateMsg& pose, bool poseSeen, std::uint32_t limit, std::size_t goalNumber);
    // Dropped (left AUTONOMOUS, off the map, it failed up, new goals).
    void cancel() { active_ = false; }
    // A new goal: its back-ups counted from 0.
    void nextGoal() { goalBackUps_ = 0; }

    bool active() const { return active_; }
    // The back-up leg's end; its bounds are written when the leg is sent.
    msg::PlanLeg* leg() { return &leg_; }
    std::uint32_t goalBackUps() const { return goalBackUps_; }
    std::uint32_t backUps() const { return backUps_; }
    std::size_t trackCount() const { return trackCount_; }

private:
    core::EventLog& events_;
    // The driven track: track_[(trackHead_ + k) % kTrackPoints], k < trackCount_, oldest first.
    double trackX_[kTrackPoints] = {};
    double trackY_[kTrackPoints] = {};
    std::size_t trackHead_ = 0;
    std::size_t trackCount_ = 0;
    bool active_ = false;            // the leg in force is a back-up
    msg::PlanLeg leg_{};
    std::size_t keep_ = 0;           // track points kept when the back-up is reached
    std::uint32_t goalBackUps_ = 0;  // back-ups of the current goal
    std::uint32_t backUps_ = 0;      // all back-ups (DeliberativeCounters::backUps)
};

}  // namespace rse::deliberative
