#include "fsw/cmdtlm/executive_commands.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

core::Status ExecutiveCommands::protectRow(std::size_t row, TaskCommandRefusal why) {
    if (row >= core::kMaxTasks || why == TaskCommandRefusal::kNone || why == TaskCommandRefusal::kNoSuchRow) {
        return core::Status::kInvalidArgument;
    }
    protected_[row] = why;
    return core::Status::kOk;
}

void ExecutiveCommands::takeTaskRestart(const msg::TaskRestartMsg& request) {
    // The executive's rows stop only by being disabled (a hung task is the
    // watchdog's), so running the row again is the restart.
    if (!core::isOk(executive_.setTaskEnabled(request.row, true))) {
        ++taskRestartsRefused_;
        events_.report(events::kTaskRestartRefused, core::Severity::kError,
                       "app: task restart refused: row %u is not in the rate-group table",
                       static_cast<unsigned>(request.row));
        return;
    }
    ++taskRestarts_;
    events_.report(events::kTaskRestarted, core::Severity::kWarning, "app: fault protection restarted rate-group row %u",
                   static_cast<unsigned>(request.row));
}

CommandOutcome ExecutiveCommands::execute(const CommandVerdict& verdict) {
    if (verdict.command->code == CommandCode::EXEC_SET_TASK) {
        return setTask(decodedArgs<EXEC_SET_TASK_Args>(verdict));
    }
    return commandFailed(-1);
}

CommandOutcome ExecutiveCommands::setTask(const EXEC_SET_TASK_Args& args) {
    const bool enable = args.enabled != 0;
    TaskCommandRefusal why = TaskCommandRefusal::kNone;
    // Enabling is always safe; only a disable can lose a row for good. The
    // executive alone knows how many rows there are.
    if (!enable && args.row < core::kMaxTasks && protected_[args.row] != TaskCommandRefusal::kNone) {
        why = protected_[args.row];
    } else if (!core::isOk(executive_.setTaskEnabled(args.row, enable))) {
        why = TaskCommandRefusal::kNoSuchRow;
    }
    if (why != TaskCommandRefusal::kNone) {
        ++taskCommandsRefused_;
        lastTaskRefusal_ = why;
        events_.report(events::kTaskSetRefused, core::Severity::kError, "app: EXEC_SET_TASK row %u refused: %s",
                       static_cast<unsigned>(args.row), toString(why));
        return commandFailed(static_cast<std::int16_t>(why));
    }
    ++taskCommands_;
    const core::RateGroupEntry* entry = executive_.entry(args.row);
    if (enable) {
        events_.report(events::kTaskSetByGround, core::Severity::kInfo, "app: ground enabled rate-group row %u (%s)",
                       static_cast<unsigned>(args.row), entry->name);
    } else {
        events_.report(events::kTaskSetByGround, core::Severity::kWarning,
                       "app: ground disabled rate-group row %u (%s): it will be seen to stall",
                       static_cast<unsigned>(args.row), entry->name);
    }
    return {};
}

}  // namespace rse::cmdtlm
