// Mission goals from ground (GOTO, ADD_TARGET, CLEAR_GOALS, SET_RISK_BOUND).
// The command handlers publish the operator's goal list; the plan executive
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

struct Goal {
    double xM;
    double yM;
    std::uint8_t priority;  // 0: a plain GOTO goal; 1..10 science target priority
    std::uint8_t pad[7];
};

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

// The checks every reader applies: at most kMaxGoals, finite points, a risk
// bound in (0, 0.5) (NaN refused).
inline bool goalListUsable(const GoalListMsg& g) {
    if (g.count > kMaxGoals || !(g.riskBound > 0.0 && g.riskBound < 0.5)) {
        return false;
    }
    for (std::size_t i = 0; i < g.count; ++i) {
        if (!std::isfinite(g.goals[i].xM) || !std::isfinite(g.goals[i].yM)) {
            return false;
        }
    }
    return true;
}

}  // namespace rse::msg
