// Goal lists as plans (docs/plan_executive.md "Goal lists"). GOTO,
// ADD_TARGET, CLEAR_GOALS and SET_RISK_BOUND change the operator's goal list
// (GoalListMsg); each new revision becomes the plan text
//
//     plan goal_list
//     event goal1 ...
//     activity drive1 drive start goal1 [0, inf] at X Y [within R] ...
//     end
//
// one drive activity a goal, in the list's order, no bounds, no cost, no
// choices, parsed, selected and dispatched as any plan (978). Taken only
// between selections (a PLAN_START's or a regeneration's first): the latest
// revision wins; the same revision again is ignored. An empty list stops a
// goal plan (980, its drive cancelled); a mission plan runs on through it.
// A goal plan's drive fails only when the deliberative layer calls home (its
// SafeRequestMsg already sent): a goal plan has no other method, and a
// second call would only overwrite the deliberative layer's reason, so the
// plan stops (979), no regeneration. The list's risk bound is the next
// drive's.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/goal_msgs.hpp"
#include "fsw/plan_executive/activity_devices.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/plan_adoption.hpp"

namespace rse::plan_executive {

// A goal plan's text: a header and "end" (32 B), then a goal's event line
// (at most 24 B) and drive line (at most 87 B: coordinates up to 100 km to
// the mm and " within 50.000").
constexpr std::size_t kGoalPlanTextBytes = 32 + msg::kMaxGoals * (24 + 88);

// The goal list g as plan text into text[0 .. size): its length, or a
// length >= size when it does not fit (refused as an overflow, never cut).
// g.count is at most msg::kMaxGoals (a usable list).
std::size_t writeGoalPlanText(const msg::GoalListMsg& g, char* text, std::size_t size);

class GoalPlans {
public:
    GoalPlans(ExecutiveContext& ctx, ActivityDevices& devices, ActivityLifecycle& lifecycle, PlanAdoption& adoption)
        : ctx_(ctx), devices_(devices), lifecycle_(lifecycle), adoption_(adoption) {}

    // A usable goal list (msg::goalListUsable): its risk bound for the next
    // drive; a new revision waits for begin().
    void take(const msg::GoalListMsg& m);
    // A revision waits to become a plan (begin() when no selection runs).
    bool pending() const { return pending_; }
    // The latest revision: a plan of its drives, or (empty) the goal plan stopped.
    void begin();
    // A goal plan's drive failed: the plan stopped, the call home stands (979).
    void stop();
    std::uint32_t plansMade() const { return plans_; }

private:
    void stopForEmptyList();

    ExecutiveContext& ctx_;
    ActivityDevices& devices_;
    ActivityLifecycle& lifecycle_;
    PlanAdoption& adoption_;
    msg::GoalListMsg list_{};
    bool seen_ = false;
    bool pending_ = false;
    char text_[kGoalPlanTextBytes] = {};
    std::uint32_t plans_ = 0;
};

}  // namespace rse::plan_executive
