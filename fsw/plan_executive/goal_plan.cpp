#include "fsw/plan_executive/goal_plan.hpp"

#include <cstdio>

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

std::size_t writeGoalPlanText(const msg::GoalListMsg& g, char* text, std::size_t size) {
    std::size_t n = 0;
    n += static_cast<std::size_t>(std::snprintf(text + n, size - n, "plan goal_list\n"));
    for (std::size_t i = 0; i < g.count && n < size; ++i) {
        n += static_cast<std::size_t>(std::snprintf(text + n, size - n, "event goal%u\n", static_cast<unsigned>(i + 1)));
    }
    for (std::size_t i = 0; i < g.count && n < size; ++i) {
        char from[16] = "start";
        if (i > 0) {
            std::snprintf(from, sizeof from, "goal%u", static_cast<unsigned>(i));
        }
        // A goal's region goes with it (the goal commands' goals are
        // points: radius 0, no `within`); below the text's 1 mm it is the point.
        char within[24] = "";
        if (g.goals[i].radiusM >= 0.0005F) {
            std::snprintf(within, sizeof within, " within %.3f", static_cast<double>(g.goals[i].radiusM));
        }
        n += static_cast<std::size_t>(std::snprintf(text + n, size - n,
                                                    "activity drive%u drive %s goal%u [0, inf] at %.3f %.3f%s\n",
                                                    static_cast<unsigned>(i + 1), from, static_cast<unsigned>(i + 1),
                                                    g.goals[i].xM, g.goals[i].yM, within));
    }
    if (n < size) {
        n += static_cast<std::size_t>(std::snprintf(text + n, size - n, "end\n"));
    }
    return n;
}

void GoalPlans::take(const msg::GoalListMsg& m) {
    devices_.setRiskBound(m.riskBound);
    if (seen_ && m.revision == list_.revision) {
        return;
    }
    list_ = m;
    seen_ = true;
    pending_ = true;
}

void GoalPlans::begin() {
    pending_ = false;
    const msg::GoalListMsg& g = list_;
    if (g.count == 0) {
        stopForEmptyList();
        return;
    }
    const std::size_t n = writeGoalPlanText(g, text_, sizeof text_);
    if (n >= sizeof text_) {
        adoption_.refuse(msg::PlanRefusal::kOverflow, events::kUploadRefused,
                         "goal list longer than its plan text buffer");
        return;
    }
    ++plans_;
    ctx_.events.report(events::kGoalPlan, core::Severity::kInfo,
                       "plan_exec: goal list rev %u: %u goal(s), risk bound %.3g: plan goal_list of %u drive(s)",
                       static_cast<unsigned>(g.revision), static_cast<unsigned>(g.count), g.riskBound,
                       static_cast<unsigned>(g.count));
    adoption_.beginNewPlan(text_, n, true);
}

void GoalPlans::stopForEmptyList() {
    const msg::GoalListMsg& g = list_;
    const bool running = ctx_.goalPlan && ctx_.planRunning();
    const bool missionPlan = !ctx_.goalPlan && ctx_.planRunning();
    // DEBUG when there is nothing to say (the goal commands' first list at boot).
    ctx_.events.report(events::kGoalListEmpty, running || missionPlan ? core::Severity::kInfo : core::Severity::kDebug,
                       "plan_exec: goal list rev %u empty: %s", static_cast<unsigned>(g.revision),
                       running ? "goal plan stopped"
                               : (missionPlan ? "the mission plan runs on (PLAN_ABORT stops it)" : "no goal plan to stop"));
    if (running) {
        lifecycle_.cancelDispatch();
        ctx_.state = msg::PlanExecutiveState::kIdle;
    }
}

void GoalPlans::stop() {
    const DispatchSnapshot snap = ctx_.dispatcher.snapshot(ctx_.planMs());
    const Tpn& p = ctx_.plan();
    lifecycle_.cancelDispatch();
    ctx_.state = msg::PlanExecutiveState::kFailed;
    ctx_.events.report(events::kGoalPlanStopped, core::Severity::kWarning,
                       "plan_exec: goal plan stopped at %s: no other method; the deliberative layer's call home stands",
                       snap.reasonActivity < p.activityCount ? p.activities[snap.reasonActivity].name : "-");
}

}  // namespace rse::plan_executive
