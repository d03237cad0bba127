// The executive's commands (APID 0x184) and its onboard requests: ground may
// disable or enable a rate-group row (EXEC_SET_TASK, cFS SCH's schedule-entry
// enable / disable), except the rows whose loss could not be undone
// (protectRow: refused with the reason, task_command_refusal.hpp); fault
// protection may ask for a stalled row to run again (TaskRestartMsg on the
// command router's onboard-request pipe). Each is evented (220/221, 224/225)
// and counted.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/app_commands.hpp"
#include "fsw/cmdtlm/task_command_refusal.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"

namespace rse::cmdtlm {

class ExecutiveCommands final : public AppCommands {
public:
    ExecutiveCommands(core::Executive& executive, core::EventLog& events) : executive_(executive), events_(events) {}

    // Start-up: fault protection's task restarts come on the router's onboard-request pipe.
    core::Status routeRequests(core::InputPipe& requests) {
        return requests.route<&ExecutiveCommands::takeTaskRestart>(this);
    }
    // Start-up, after the executive's table: a row ground may not disable, and why
    // (kInvalidArgument for a row beyond kMaxTasks or a reason that is not a row's).
    core::Status protectRow(std::size_t row, TaskCommandRefusal why);

    std::uint16_t apid() const override { return describe(CommandCode::EXEC_SET_TASK).apid; }
    CommandOutcome execute(const CommandVerdict& verdict) override;

    std::uint32_t taskRestarts() const { return taskRestarts_; }
    std::uint32_t taskRestartsRefused() const { return taskRestartsRefused_; }
    std::uint32_t taskCommands() const { return taskCommands_; }  // EXEC_SET_TASK carried out
    std::uint32_t taskCommandsRefused() const { return taskCommandsRefused_; }
    TaskCommandRefusal lastTaskRefusal() const { return lastTaskRefusal_; }

private:
    void takeTaskRestart(const msg::TaskRestartMsg& request);
    CommandOutcome setTask(const EXEC_SET_TASK_Args& args);

    core::Executive& executive_;
    core::EventLog& events_;
    std::uint32_t taskRestarts_ = 0;
    std::uint32_t taskRestartsRefused_ = 0;
    std::uint32_t taskCommands_ = 0;
    std::uint32_t taskCommandsRefused_ = 0;
    TaskCommandRefusal lastTaskRefusal_ = TaskCommandRefusal::kNone;
    TaskCommandRefusal protected_[core::kMaxTasks] = {};  // kNone: ground may disable the row
};

}  // namespace rse::cmdtlm
