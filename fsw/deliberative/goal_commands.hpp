// The mission-goal commands (APID 0x181), owned by the deliberative layer
// whose planner reaches the goals: GOTO, ADD_TARGET, CLEAR_GOALS and
// SET_RISK_BOUND change the goal list (goal_list.hpp), which is announced on
// the bus after each change and once at start-up (GoalListMsg: the plan
// executive makes it a plan, PLAN telemetry shows it) and evented (208).
// ADD_TARGET on a full list fails (execution_failed, detail kMaxGoals).
#pragma once

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/goal_list.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::deliberative {

namespace events {
// A goal command changed the goal list (count, risk bound). Kept from fsw/app's range (its
// text starts "app:"), where the goal commands were before.
constexpr core::EventId kGoalsCommanded = 208;
}  // namespace events

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

}  // namespace rse::deliberative
