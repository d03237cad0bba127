// Supervision of the trajectory the rover is driving (HabitualState kDriving)
// and the leg's odometry:
//   odometry        driven length: the sum of pose displacements, each step at
//                   least kOdometryStepM (pose jitter at rest adds nothing);
//                   driven energy: the power model on those steps and on heading
//                   changes of at least kOdometryStepRad, with the power factors
//                   of the moment. The leg's remaining bounds come from these
//                   (candidate_evaluator.hpp).
//   remaining path  from the point of the trajectory nearest the rover (never
//                   back before the last such point) to its end
//   blocked path    the remaining path against the check map (bare footprint,
//                   latest hazards): blocked -> event 804 naming the remembered
//                   disc on it; the task stops and replans
//   power factors   new factors (the drives' mean changed): the remaining path
//                   re-evaluated; the power bound violated -> the task fails up
//                   at once; the energy bound violated -> event 809, the task
//                   repairs (or fails up when the table allows no repair)
//   follower        kReached ends the leg (or the back-out); kCannotFollow ->
//                   event 810, one replan per leg, then fail-up (drives held or
//                   not autonomous: fail-up at once)
// It decides and events; the task acts on the verdicts (stop, session, fail-up).
// No bus, no heap; loops bounded by kMaxTrajectoryPoints and kMaxMapDiscs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/habitual/hazard_memory.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// Driven-distance and heading accumulation steps (filter pose jitter at rest).
constexpr double kOdometryStepM = 0.05;
constexpr double kOdometryStepRad = 0.05;

enum class FactorVerdict : std::uint8_t {
    kUnchanged = 0,  // the mean power factor is the one the plan was predicted with: nothing evaluated
    kHolds = 1,      // re-evaluated: the power and energy bounds hold
    kPower = 2,      // the power bound no longer holds: fail up at once
    kEnergy = 3,     // the remaining path needs more energy than allowed: repair
};

struct FactorCheck {
    FactorVerdict verdict;
    Evaluation evaluation;  // the remaining path's figures (unless kUnchanged)
    Evaluation asEnergy;    // kEnergy: the figures with energy named the violated bound
};

enum class FollowerVerdict : std::uint8_t {
    kNothing = 0,     // about another trajectory, or no news
    kEscapeDone = 1,  // the back-out reached: plan again from there
    kReached = 2,     // the leg's end reached
    kReplan = 3,      // gave up: stop and replan (once per leg)
    kFailUp = 4,      // gave up again, or the drives are held: fail up
};

struct SupervisorCounters {
    std::uint32_t pathBlocked = 0;
    std::uint32_t energyViolations = 0;
    std::uint32_t cannotFollow = 0;
};

class DriveSupervisor {
public:
    DriveSupervisor(core::EventLog& events, const tables::HabitualTable& habitual)
        : events_(events), habitual_(habitual) {}

    // A new leg: nothing driven, the odometry anchored at the next pose, no
    // replan for the follower yet.
    void beginLeg();
    // Every run while a leg is under way, with the latest pose (ignored until initialised).
    void updateOdometry(const msg::PoseEstimateMsg& pose, double powerFactor);
    double drivenLengthM() const { return drivenLengthM_; }
    double drivenEnergyJ() const { return drivenEnergyJ_; }

    // A plan sent: progress from its start; powerFactor: the one its energy was predicted with.
    void followPlan(double powerFactor);
    // A back-out sent: progress from its start.
    void followEscape() { progressIndex_ = 0; }

    // The rest of t from the point nearest here (out: at most kMaxTrajectoryPoints).
    std::size_t remainingPath(const msg::TrajectoryMsg& t, geometry::Point2 here, geometry::Point2* out);
    // The rest of t against memory's check map (rebuilt by the caller): true,
    // evented and counted, when a segment of it is blocked.
    bool pathBlocked(const msg::TrajectoryMsg& t, geometry::Point2 here, const HazardMemory& memory,
                     std::uint32_t legId);
    // New drive modes came: the rest of t re-evaluated when the mean power
    // factor changed (progress.powerFactor); kEnergy evented and counted.
    FactorCheck checkPowerFactors(const msg::TrajectoryMsg& t, const msg::PoseEstimateMsg& pose,
                                  const CandidateEvaluator& evaluator, const LegProgress& progress,
                                  std::uint32_t legId);
    // The remaining path of the last checkPowerFactors (the candidate a repair keeps).
    const geometry::Point2* remaining() const { return remaining_; }
    std::size_t remainingCount() const { return remainingCount_; }

    // A follower status while driving t (escaping: t is a back-out). A give-up
    // is evented and counted.
    FollowerVerdict judgeFollower(const msg::FollowerStatusMsg& status, const msg::TrajectoryMsg& t, bool escaping,
                                  std::uint32_t legId);

    const SupervisorCounters& counters() const { return counters_; }

private:
    core::EventLog& events_;
    const tables::HabitualTable& habitual_;
    double drivenLengthM_ = 0.0;
    double drivenEnergyJ_ = 0.0;
    geometry::Point2 anchor_{0.0, 0.0};
    double anchorHeading_ = 0.0;
    bool anchorSet_ = false;
    std::uint32_t cannotFollowReplans_ = 0;
    std::size_t progressIndex_ = 0;
    double predictedFactor_ = 1.0;
    geometry::Point2 remaining_[msg::kMaxTrajectoryPoints] = {};
    std::size_t remainingCount_ = 0;
    SupervisorCounters counters_{};
};

}  // namespace rse::habitual
