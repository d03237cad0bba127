// The operator's goals and the risk bound they are to be reached within: what
// GOTO, ADD_TARGET, CLEAR_GOALS and SET_RISK_BOUND change. Fixed capacity.
// Announced as a GoalListMsg, which the plan executive task makes a plan of
// drives (goal_plan.hpp) and PLAN telemetry shows.
#pragma once

#include "fsw/core/status.hpp"
#include "fsw/msg/goal_msgs.hpp"

namespace rse::plan_executive {

class GoalList {
public:
    explicit GoalList(double defaultRiskBound) { list_.riskBound = defaultRiskBound; }

    // GOTO: the goal list becomes this one goal, planned within risk.
    void replaceWithGoal(double x, double y, double risk);
    // ADD_TARGET: kFull when kMaxGoals are held (the list is unchanged).
    core::Status addTarget(double x, double y, std::uint8_t priority);
    void clear();
    void setRiskBound(double risk);

    const msg::GoalListMsg& message() const { return list_; }
    std::uint8_t count() const { return list_.count; }
    double riskBound() const { return list_.riskBound; }
    std::uint32_t revision() const { return list_.revision; }

private:
    msg::GoalListMsg list_{};
};

}  // namespace rse::plan_executive
