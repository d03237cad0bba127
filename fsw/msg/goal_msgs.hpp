// Mission goals from ground (GOTO, ADD_TARGET, CLEAR_GOALS, SET_RISK_BOUND).
// The goal commands (fsw/plan_executive/goal_commands.hpp) publish the operator's goal list; the plan executive
// turns it into a plan of drive activities, one per goal, and gives the
// deliberative layer one goal at a time (PlanGoalMsg, plan_executive_msgs.hpp):
// the same executive runs GOTO, the goal list and mission plans
// (docs/plan_executive.md "Goal lists").
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

constexpr std::size_t kMaxGoals = 16;  // PLAN telemetry shows up to 16 waypoints
// The largest goal region (a plan's `drive ... at X Y within R`): wider than
// any site the coarse map holds, so a larger one is a mistake, not a wish.
constexpr float kMaxGoalRadiusM = 50.0F;

struct Goal {
    double xM;
    double yM;
    std::uint8_t priority;  // 0: a plain GOTO goal; 1..10 science target priority
    std::uint8_t pad[3];
    // The goal is reached anywhere within this of (xM, yM); 0 (GOTO,
    // ADD_TARGET), or anything up to HABITUAL.goal_tolerance_m: the point,
    // reached to that tolerance. At most kMaxGoalRadiusM.
    float radiusM;
};

// How near the goal the rover must stop: its region, never tighter than the
// habitual table's goal tolerance (the deliberative layer's "reached" and the
// habitual layer's arrival on the goal's last leg use the same figure).
inline double arrivalRadiusM(double goalToleranceM, double radiusM) {
    return radiusM > goalToleranceM ? radiusM : goalToleranceM;
}

// Published whenever the goal list or the risk bound changes.
struct GoalListMsg {
    static constexpr core::MsgId kMsgId = ids::kGoalList;
    std::int64_t timeNs;
    double riskBound;          // joint chance-constraint bound for planning
    std::uint32_t revision;    // counts changes
    std::uint8_t count;
    std::uint8_t pad[3];
    Goal goals[kMaxGoals];
};

// The checks every reader applies: at most kMaxGoals, finite points, a radius
// in [0, kMaxGoalRadiusM], a risk bound in (0, 0.5) (NaN refused).
inline bool goalListUsable(const GoalListMsg& g) {
    if (g.count > kMaxGoals || !(g.riskBound > 0.0 && g.riskBound < 0.5)) {
        return false;
    }
    for (std::size_t i = 0; i < g.count; ++i) {
        const float r = g.goals[i].radiusM;
        if (!std::isfinite(g.goals[i].xM) || !std::isfinite(g.goals[i].yM) || !(r >= 0.0F && r <= kMaxGoalRadiusM)) {
            return false;
        }
    }
    return true;
}

}  // namespace rse::msg
