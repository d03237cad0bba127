#include "fsw/plan_executive/goal_commands.hpp"

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

using cmdtlm::CommandCode;

GoalCommands::GoalCommands(const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                           const tables::TableService& tables)
    : clock_(clock), bus_(bus), events_(events), tables_(tables), goals_(1e-3) {}

void GoalCommands::init() {
    goals_.setRiskBound(tables_.planner().default_risk_bound);
    publish();
}

cmdtlm::CommandOutcome GoalCommands::execute(const cmdtlm::CommandVerdict& verdict) {
    switch (verdict.command->code) {
        case CommandCode::GOTO: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::GOTO_Args>(verdict);
            goals_.replaceWithGoal(a.x, a.y, a.risk);
            break;
        }
        case CommandCode::ADD_TARGET: {
            const auto a = cmdtlm::decodedArgs<cmdtlm::ADD_TARGET_Args>(verdict);
            if (!core::isOk(goals_.addTarget(a.x, a.y, a.priority))) {
                return cmdtlm::commandFailed(static_cast<std::int16_t>(msg::kMaxGoals));  // goal list full
            }
            break;
        }
        case CommandCode::CLEAR_GOALS:
            goals_.clear();
            break;
        case CommandCode::SET_RISK_BOUND:
            goals_.setRiskBound(cmdtlm::decodedArgs<cmdtlm::SET_RISK_BOUND_Args>(verdict).risk);
            break;
        default:
            return cmdtlm::commandFailed(-1);
    }
    publish();
    return {};
}

void GoalCommands::publish() {
    msg::GoalListMsg m = goals_.message();
    m.timeNs = clock_.now();
    (void)bus_.publish(m);  // a refusal is counted and evented by the bus
    cmdtlm::event_data::GOALS_COMMANDED data;
    data.goal_count = m.count;
    data.risk_bound = m.riskBound;
    events_.report(events::kGoalsCommanded, core::Severity::kInfo, data.pack(), "app: %u goal(s), risk bound %.3g",
                   static_cast<unsigned>(m.count), m.riskBound);
}

}  // namespace rse::plan_executive
