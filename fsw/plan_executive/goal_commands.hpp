// The mission-goal commands (APID 0x181), owned by the plan executive, which
// owns the mission: its goals (these) and its plans (plan_commands.hpp, 0x185).
// GOTO, ADD_TARGET, CLEAR_GOALS and SET_RISK_BOUND change the goal list
// (goal_list.hpp), which is announced on the bus after each change and once at
// start-up (GoalListMsg: the plan executive task makes it a plan of drives,
// goal_plan.hpp, and sends the deliberative layer one goal a drive; PLAN
// telemetry shows it) and evented (208, events::kGoalsCommanded).
// ADD_TARGET on a full list fails (execution_failed, detail kMaxGoals).
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/plan_executive/goal_list.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::plan_executive {

class GoalCommands final : public cmdtlm::AppCommands {
public:
    GoalCommands(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                 const tables::TableService& tables);

    // Start-up, after the tables: the risk bound is the planner table's
    // default; the (empty) goal list is announced.
    void init();

    std::uint16_t apid() const override { return cmdtlm::describe(cmdtlm::CommandCode::GOTO).apid; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;

    const GoalList& goals() const { return goals_; }

private:
    void publish();

    const core::Clock& clock_;
    core::SoftwareBus& bus_;
    core::EventLog& events_;
    const tables::TableService& tables_;
    GoalList goals_;
};

}  // namespace rse::plan_executive
