#include "fsw/plan_executive/goal_list.hpp"

namespace rse::plan_executive {

void GoalList::replaceWithGoal(double x, double y, double risk) {
    list_.count = 1;
    list_.goals[0] = msg::Goal{x, y, 0, {}, 0.0F};
    list_.riskBound = risk;
    ++list_.revision;
}

core::Status GoalList::addTarget(double x, double y, std::uint8_t priority) {
    if (list_.count >= msg::kMaxGoals) {
        return core::Status::kFull;
    }
    list_.goals[list_.count++] = msg::Goal{x, y, priority, {}, 0.0F};
    ++list_.revision;
    return core::Status::kOk;
}

void GoalList::clear() {
    list_.count = 0;
    ++list_.revision;
}

void GoalList::setRiskBound(double risk) {
    list_.riskBound = risk;
    ++list_.revision;
}

}  // namespace rse::plan_executive
