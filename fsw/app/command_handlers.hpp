// What each ground command does, once the command service has checked it
// (fsw/cmdtlm/command_task.hpp). Owns the rover mode and the software e-stop
// flag and announces both on the bus (ModeMsg); mission goals go to the goal
// list (GoalListMsg), manual drives to the manual-drive task, table commands to
// the table service, plan commands to the plan executive (PlanCommandMsg), counter resets to everything that counts. Onboard layers
// may ask for SAFE (SafeRequestMsg, pipe "mode_requests"); fault protection may
// ask for a stalled rate-group row to run again (TaskRestartMsg, same pipe);
// ground may disable or enable a row (EXEC_SET_TASK), except the rows whose
// loss could not be undone (protectRow).
#pragma once

#include "fsw/app/task_command_refusal.hpp"
#include "fsw/app/telemetry_task.hpp"
#include "fsw/cmdtlm/command_handler.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/goal_list.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/tables/table_service.hpp"

namespace rse::app {

// The mode the rover boots in: nothing moves until ground says so.
constexpr cmdtlm::Mode kBootMode = cmdtlm::Mode::kSafe;

class AppCommandHandler final : public cmdtlm::CommandHandler {
public:
    struct Parts {
        const core::Clock& clock;
        core::SoftwareBus& bus;
        core::EventLog& events;
        core::Executive& executive;
        tables::TableService& tables;
        cmdtlm::TelemetryOutput& telemetry;
    };
    explicit AppCommandHandler(const Parts& parts);

    // The parts built after this one (they need it to exist first).
    void attach(cmdtlm::CommandTask* commands, TelemetryTask* telemetryTask) {
        commands_ = commands;
        telemetryTask_ = telemetryTask;
    }
    // Start-up: announces the boot mode; the goal list takes the planner table's default risk bound.
    core::Status init();
    // Start-up, after the executive's table: a row ground may not disable, and why
    // (kInvalidArgument for a row beyond kMaxTasks or a reason that is not a row's).
    core::Status protectRow(std::size_t row, TaskCommandRefusal why);

    cmdtlm::Mode mode() const override { return mode_; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict& verdict) override;
    // A SafeRequestMsg (the deliberative layer's call home) puts the rover in SAFE.
    void serviceOnboardRequests() override;
    std::uint32_t safeRequests() const { return safeRequests_; }
    std::uint32_t malformedRequests() const { return malformedRequests_; }
    std::uint32_t taskRestarts() const { return taskRestarts_; }
    std::uint32_t taskRestartsRefused() const { return taskRestartsRefused_; }
    std::uint32_t taskCommands() const { return taskCommands_; }  // EXEC_SET_TASK carried out
    std::uint32_t taskCommandsRefused() const { return taskCommandsRefused_; }
    TaskCommandRefusal lastTaskRefusal() const { return lastTaskRefusal_; }

    bool estop() const { return estop_; }
    const deliberative::GoalList& goals() const { return goals_; }

private:
    cmdtlm::CommandOutcome executeTable(const cmdtlm::CommandVerdict& verdict);
    cmdtlm::CommandOutcome executePlan(const cmdtlm::CommandVerdict& verdict);
    cmdtlm::CommandOutcome setTask(const cmdtlm::EXEC_SET_TASK_Args& args);
    void setMode(cmdtlm::Mode mode);
    void setEstop(bool set);
    void publishMode();
    void publishGoals();
    void restartTask();  // a TaskRestartMsg in inbox_
    void refuseMalformedRequest();  // inbox_ did not decode: counted and evented (throttled)

    Parts parts_;
    cmdtlm::CommandTask* commands_ = nullptr;
    TelemetryTask* telemetryTask_ = nullptr;
    cmdtlm::Mode mode_ = kBootMode;
    bool estop_ = false;
    deliberative::GoalList goals_;
    core::PipeId requestPipe_ = 0;
    bool requestsReady_ = false;
    std::uint32_t safeRequests_ = 0;
    std::uint32_t malformedRequests_ = 0;
    std::uint32_t taskRestarts_ = 0;
    std::uint32_t taskRestartsRefused_ = 0;
    std::uint32_t taskCommands_ = 0;
    std::uint32_t taskCommandsRefused_ = 0;
    TaskCommandRefusal lastTaskRefusal_ = TaskCommandRefusal::kNone;
    TaskCommandRefusal protected_[core::kMaxTasks] = {};  // kNone: ground may disable the row
    core::Message inbox_{};
    msg::PlanCommandMsg planCommand_{};  // kept off the stack
};

}  // namespace rse::app
