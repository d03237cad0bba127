// Mission goals from ground (GOTO, ADD_TARGET, CLEAR_GOALS, SET_RISK_BOUND) for
// the deliberative layer, which turns them into plans.
#pragma once

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

}  // namespace rse::msg
