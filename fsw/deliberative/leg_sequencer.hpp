// The plan's legs and the leg in force (docs/deliberative.md, "Legs",
// "Fail-ups", "Goal reached needs a certain pose"): the habitual layer gets
// one leg at a time (LegCommandMsg, a new legId each time one is sent or
// re-sent; legId 0 cancels), the next when it reports the one in force
// achieved.
//
// - Sending: a leg end too near a seen hazard or a coarse-map polygon
//   (LegEndClearance) is merged into the next leg (lengths, energies and risks
//   added; event 919), never the plan's last; the goal's last leg carries the
//   goal's region (arriveWithinM), every other leg 0. During a mission hold
//   no leg goes out (the leg in force is cleared) and the leg is sent from the
//   pose of the moment when the hold is released.
// - Re-sending from the pose (hold released, goal confirmation): the bounds
//   are recomputed from where the rover stands (plan_legs.hpp legBoundsFrom)
//   and keep the relaxation the leg earned (losing it fails the re-sent leg
//   up again at once); the power bound is the drives', kept.
// - Relaxing: the ReplanPolicy's answer to a fail-up grows the leg's violated
//   bound, or every leg's power bound for the rest of the plan (event 910).
// - A back-up leg (BackUpManoeuvre's target): a leg of its own, not final,
//   bounds from the pose, the plan's power bound.
// - The goal's last leg reached: the goal is claimed (event 907) only from a
//   certain pose; else it waits (event 922) until the pose is certain, then
//   claims it if the rover stands within the goal's arrival radius, or
//   re-sends the last leg from the pose (event 923).
//
// Publishes only LegCommandMsg (through the Publisher). Events 905, 906, 907,
// 910, 919, 922, 923.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/leg_end_clearance.hpp"
#include "fsw/deliberative/plan_legs.hpp"
#include "fsw/deliberative/publisher.hpp"
#include "fsw/deliberative/replan_policy.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"

namespace rse::deliberative {

// The goal in hand and the pose, for claiming it.
struct GoalArrival {
    const msg::Goal* goal = nullptr;
    std::size_t number = 0;       // as the operator numbers it (events)
    double arrivalM = 0.0;        // how near the goal the rover must stand (msg::arrivalRadiusM)
    const msg::PoseEstimateMsg* pose = nullptr;
    bool poseUncertain = false;   // fault 19, sigma above ESTIMATOR_NOISE.pose_fault_sigma_m, no initialised pose
    bool poseFault = false;       // fault 19 itself (named in event 922)
};

enum class GoalClaim : std::uint8_t {
    kReached,      // claimed (event 907): the task goes on to the next goal
    kUnconfirmed,  // not claimed, the pose is uncertain: waiting without a leg
    kWaiting,      // still uncertain
    kResend,       // certain, but off the goal: the last leg is to be re-sent from the pose
};

struct LegCounters {
    std::uint32_t legsSent = 0;
    std::uint32_t legsAchieved = 0;
    std::uint32_t goalsReached = 0;
    std::uint32_t legEndsSkipped = 0;
    std::uint32_t goalsUnconfirmed = 0;
    std::uint32_t goalLegsResent = 0;
};

class LegSequencer {
public:
    LegSequencer(core::EventLog& events, Publisher& out) : events_(events), out_(out) {}

    // A new goal list: no legs, no goal waiting, the power bound as planned.
    void newGoals();
    // Cuts a plan into legs (plan_legs.hpp); true when it gave at least one.
    // The legs replace the last plan's even when it fails.
    bool split(const CcPlan& plan, const LegParams& params);
    // The first leg of the legs just cut is the one to send; no relaxation.
    void begin();
    // The plan starts at the re-entry point, but the rover drives there first:
    // the first leg gets the bounds from where it stands when they are larger.
    void widenFirstLeg(const msg::PoseEstimateMsg& pose, const LegParams& params);

    // Sends the current leg (after merging leg ends too near something);
    // when held, only clears the leg in force. goalRadiusM: the goal's region.
    void send(core::TimeNs now, bool held, double goalRadiusM, const LegEndClearance& clear);
    // Re-sends the current leg from the pose (bounds recomputed, relaxation
    // kept); false when there is no current leg.
    bool resendFromPose(core::TimeNs now, bool held, double goalRadiusM, const LegEndClearance& clear,
                        const msg::PoseEstimateMsg& pose, const LegParams& params);
    // Sends the back-up to *target (its bounds written from the pose).
    void sendBackUp(core::TimeNs now, bool held, msg::PlanLeg* target, const msg::PoseEstimateMsg& pose,
                    const LegParams& params);
    // The leg in force reached (event 906): true when another leg follows (to send).
    bool achieved();
    // The leg in force is over (no cancel sent: the habitual layer stopped on its own).
    void dropLegInForce() { leg_.legId = 0; }
    // Publishes the cancel (legId 0: the habitual layer stops and holds).
    void cancel(core::TimeNs now);
    // Merges leg ends too near something into their next leg, from the
    // current one on while they are not the last leg; true when it moved on.
    bool mergeLegEnds(const LegEndClearance& clear);
    // The current leg (not the last) ends too near something (a new sighting).
    bool legEndTooClose(const LegEndClearance& clear) const;

    // Applies the ReplanPolicy's relaxation of the leg in force (event 910);
    // which: the violated bound (length or energy) for kRelaxBound.
    void relax(const FailUpAnswer& answer, msg::LegConstraint which);

    // The goal's last leg reached.
    GoalClaim claimGoal(const GoalArrival& arrival);
    // While waiting for a certain pose (goalUnconfirmed()).
    GoalClaim reclaimGoal(const GoalArrival& arrival);
    void dropUnconfirmedGoal() { goalUnconfirmed_ = false; }

    const LegPlan& legs() const { return legs_; }
    std::size_t index() const { return index_; }
    const msg::LegCommandMsg& legInForce() const { return leg_; }
    bool goalUnconfirmed() const { return goalUnconfirmed_; }
    // A leg to drive on a release: the goal not waiting for a pose, a leg left.
    bool legToDrive() const { return !goalUnconfirmed_ && index_ < legs_.count; }
    double legGrowth() const { return legGrowth_; }
    double powerGrowth() const { return powerGrowth_; }
    const LegCounters& counters() const { return counters_; }

private:
    // A new leg id (never 0: 0 is the cancel).
    std::uint32_t takeLegId();

    core::EventLog& events_;
    Publisher& out_;
    LegPlan legs_{};
    std::size_t index_ = 0;
    msg::LegCommandMsg leg_{};     // the leg in force (legId 0: none)
    std::uint32_t nextLegId_ = 1;
    double legGrowth_ = 1.0;       // growth of the current leg's bounds by relaxation
    double energyGrowth_ = 1.0;    // ... of its energy bound alone (kept when the leg is re-sent after a hold)
    double lengthGrowth_ = 1.0;    // ... of its length bound alone
    // Growth of every leg's power bound by relaxation, for the rest of the
    // plan: the drives' power is the same on every leg (reset by a new plan,
    // whose legs are bounded at the power factors of the moment).
    double powerGrowth_ = 1.0;
    bool goalUnconfirmed_ = false;  // the goal's last leg reached, pose uncertain: waiting
    LegCounters counters_{};
};

}  // namespace rse::deliberative
