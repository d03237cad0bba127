#include "fsw/app/command_handlers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>

#include "fsw/app/app_events.hpp"
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"

namespace rse::app {

using cmdtlm::CommandCode;
using cmdtlm::CommandOutcome;

namespace {

template <typename Args>
Args decoded(const cmdtlm::CommandVerdict& verdict) {
    Args args{};
    core::BeReader r(verdict.args, verdict.argLength);
    cmdtlm::decodeArgs(r, &args);
    return args;
}

CommandOutcome failed(std::int16_t detail) { return CommandOutcome{false, detail}; }

}  // namespace

AppCommandHandler::AppCommandHandler(const Parts& parts) : parts_(parts), goals_(1e-3) {}

core::Status AppCommandHandler::protectRow(std::size_t row, TaskCommandRefusal why) {
    if (row >= core::kMaxTasks || why == TaskCommandRefusal::kNone || why == TaskCommandRefusal::kNoSuchRow) {
        return core::Status::kInvalidArgument;
    }
    protected_[row] = why;
    return core::Status::kOk;
}

namespace {
constexpr std::uint16_t kRequestPipeDepth = 8;  // call homes and task restarts (one per stalled row at most)
}  // namespace

core::Status AppCommandHandler::init() {
    core::Status status = parts_.bus.createPipe("mode_requests", kRequestPipeDepth, &requestPipe_);
    if (core::isOk(status)) {
        status = parts_.bus.subscribe(requestPipe_, msg::ids::kSafeRequest);
    }
    if (core::isOk(status)) {
        status = parts_.bus.subscribe(requestPipe_, msg::ids::kTaskRestart);
    }
    if (!core::isOk(status)) {
        return status;
    }
    requestsReady_ = true;
    goals_.setRiskBound(parts_.tables.planner().default_risk_bound);
    publishMode();
    publishGoals();
    return core::Status::kOk;
}

void AppCommandHandler::refuseMalformedRequest() {
    ++malformedRequests_;
    if (core::isReportableOccurrence(malformedRequests_)) {
        parts_.events.report(events::kBusMessageMalformed, core::Severity::kError,
                             "app: command handlers ignored a malformed onboard request 0x%04x (%u so far)",
                             static_cast<unsigned>(inbox_.header.id), static_cast<unsigned>(malformedRequests_));
    }
}

void AppCommandHandler::serviceOnboardRequests() {
    for (std::uint16_t i = 0; requestsReady_ && i < kRequestPipeDepth && core::isOk(parts_.bus.receive(requestPipe_, &inbox_));
         ++i) {
        if (inbox_.header.id == msg::ids::kTaskRestart) {
            restartTask();
            continue;
        }
        msg::SafeRequestMsg request{};
        if (!core::isOk(inbox_.decode(&request))) {
            refuseMalformedRequest();
            continue;
        }
        ++safeRequests_;
        parts_.events.report(events::kSafedOnRequest, core::Severity::kWarning,
                             "app: onboard call home (reason %u): mode %s -> SAFE",
                             static_cast<unsigned>(request.reason), cmdtlm::toString(mode_));
        if (mode_ != cmdtlm::Mode::kSafe) {
            setMode(cmdtlm::Mode::kSafe);
        }
    }
}

void AppCommandHandler::restartTask() {
    msg::TaskRestartMsg request{};
    if (!core::isOk(inbox_.decode(&request))) {
        refuseMalformedRequest();
        return;
    }
    // The executive's rows stop only by being disabled (a hung task is the
    // watchdog's), so running the row again is the restart.
    if (!core::isOk(parts_.executive.setTaskEnabled(request.row, true))) {
        ++taskRestartsRefused_;
        parts_.events.report(events::kTaskRestartRefused, core::Severity::kError,
                             "app: task restart refused: row %u is not in the rate-group table",
                             static_cast<unsigned>(request.row));
        return;
    }
    ++taskRestarts_;
    parts_.events.report(events::kTaskRestarted, core::Severity::kWarning,
                         "app: fault protection restarted rate-group row %u", static_cast<unsigned>(request.row));
}

CommandOutcome AppCommandHandler::execute(const cmdtlm::CommandVerdict& verdict) {
    switch (verdict.command->code) {
        case CommandCode::NOOP:
            parts_.events.report(cmdtlm::events::kNoop, core::Severity::kInfo, "cmd: NOOP (key %u, seq %u)",
                                 static_cast<unsigned>(verdict.keyId), static_cast<unsigned>(verdict.authSequence));
            return {};
        case CommandCode::RESET_COUNTERS:
            parts_.executive.resetCounters();
            parts_.bus.resetCounters();
            parts_.events.resetCounters();
            parts_.telemetry.resetCounters();
            parts_.tables.resetCounters();
            if (commands_ != nullptr) {
                commands_->resetCounters();
            }
            parts_.events.report(cmdtlm::events::kCountersReset, core::Severity::kInfo, "cmd: counters reset");
            return {};
        case CommandCode::REQUEST_HK:
            if (telemetryTask_ != nullptr) {
                telemetryTask_->requestHousekeeping();
            }
            return {};
        case CommandCode::AUTH_RESYNC:
            // The validator did the work (the nonce matched, the floor moved and
            // was persisted); unauthenticated, in the lab setting, there is no key to resync.
            if (verdict.keyId == cmdtlm::kNoKey) {
                return failed(1);
            }
            parts_.events.report(cmdtlm::events::kAuthResynced, core::Severity::kWarning,
                                 "cmd: AUTH_RESYNC: key %u re-synchronised (seq %u, floor in HK and the store)",
                                 static_cast<unsigned>(verdict.keyId), static_cast<unsigned>(verdict.authSequence));
            return {};
        case CommandCode::SET_MODE:
            setMode(static_cast<cmdtlm::Mode>(decoded<cmdtlm::SET_MODE_Args>(verdict).mode));
            return {};
        case CommandCode::GOTO: {
            const auto a = decoded<cmdtlm::GOTO_Args>(verdict);
            goals_.replaceWithGoal(a.x, a.y, a.risk);
            publishGoals();
            return {};
        }
        case CommandCode::ADD_TARGET: {
            const auto a = decoded<cmdtlm::ADD_TARGET_Args>(verdict);
            if (!core::isOk(goals_.addTarget(a.x, a.y, a.priority))) {
                return failed(static_cast<std::int16_t>(msg::kMaxGoals));  // goal list full
            }
            publishGoals();
            return {};
        }
        case CommandCode::CLEAR_GOALS:
            goals_.clear();
            publishGoals();
            return {};
        case CommandCode::SET_RISK_BOUND:
            goals_.setRiskBound(decoded<cmdtlm::SET_RISK_BOUND_Args>(verdict).risk);
            publishGoals();
            return {};
        case CommandCode::ESTOP_SET:
            setEstop(true);
            return {};
        case CommandCode::ESTOP_CLEAR:
            setEstop(false);
            return {};
        case CommandCode::RESET_INTERLOCK: {
            msg::InterlockResetMsg request{};
            request.timeNs = parts_.clock.now();
            return core::isOk(parts_.bus.publish(request)) ? CommandOutcome{} : failed(0);
        }
        case CommandCode::DRIVE: {
            if (estop_) {
                return failed(0);  // the e-stop holds: clear it first
            }
            const auto a = decoded<cmdtlm::DRIVE_Args>(verdict);
            msg::ManualDriveMsg request{};
            request.timeNs = parts_.clock.now();
            request.speedMS = static_cast<double>(a.v);
            request.turnRateRadS = static_cast<double>(a.omega);
            request.durationS = static_cast<double>(a.duration);
            return core::isOk(parts_.bus.publish(request)) ? CommandOutcome{} : failed(1);
        }
        case CommandCode::EXEC_SET_TASK:
            return setTask(decoded<cmdtlm::EXEC_SET_TASK_Args>(verdict));
        case CommandCode::TABLE_LOAD:
        case CommandCode::TABLE_VALIDATE:
        case CommandCode::TABLE_ACTIVATE:
        case CommandCode::TABLE_DUMP:
            return executeTable(verdict);
        case CommandCode::PLAN_LOAD:
        case CommandCode::PLAN_START:
        case CommandCode::PLAN_SHORT:
        case CommandCode::PLAN_ABORT:
        case CommandCode::PLAN_EXTEND:
            return executePlan(verdict);
        case CommandCode::kCount:
            break;
    }
    return failed(-1);
}

CommandOutcome AppCommandHandler::setTask(const cmdtlm::EXEC_SET_TASK_Args& args) {
    const bool enable = args.enabled != 0;
    TaskCommandRefusal why = TaskCommandRefusal::kNone;
    // Enabling is always safe; only a disable can lose a row for good. The
    // executive alone knows how many rows there are.
    if (!enable && args.row < core::kMaxTasks && protected_[args.row] != TaskCommandRefusal::kNone) {
        why = protected_[args.row];
    } else if (!core::isOk(parts_.executive.setTaskEnabled(args.row, enable))) {
        why = TaskCommandRefusal::kNoSuchRow;
    }
    if (why != TaskCommandRefusal::kNone) {
        ++taskCommandsRefused_;
        lastTaskRefusal_ = why;
        parts_.events.report(events::kTaskSetRefused, core::Severity::kError, "app: EXEC_SET_TASK row %u refused: %s",
                             static_cast<unsigned>(args.row), toString(why));
        return failed(static_cast<std::int16_t>(why));
    }
    ++taskCommands_;
    const core::RateGroupEntry* entry = parts_.executive.entry(args.row);
    if (enable) {
        parts_.events.report(events::kTaskSetByGround, core::Severity::kInfo, "app: ground enabled rate-group row %u (%s)",
                             static_cast<unsigned>(args.row), entry->name);
    } else {
        parts_.events.report(events::kTaskSetByGround, core::Severity::kWarning,
                             "app: ground disabled rate-group row %u (%s): it will be seen to stall",
                             static_cast<unsigned>(args.row), entry->name);
    }
    return {};
}

CommandOutcome AppCommandHandler::executeTable(const cmdtlm::CommandVerdict& verdict) {
    tables::TableId id{};
    tables::TableCheck check{};
    switch (verdict.command->code) {
        case CommandCode::TABLE_LOAD: {
            const auto a = decoded<cmdtlm::TABLE_LOAD_Args>(verdict);
            id = static_cast<tables::TableId>(a.table_id);
            check = parts_.tables.loadChunk(id, a.offset, a.data, a.data_length);
            break;
        }
        case CommandCode::TABLE_VALIDATE:
            id = static_cast<tables::TableId>(decoded<cmdtlm::TABLE_VALIDATE_Args>(verdict).table_id);
            check = parts_.tables.validate(id);
            break;
        case CommandCode::TABLE_ACTIVATE:
            id = static_cast<tables::TableId>(decoded<cmdtlm::TABLE_ACTIVATE_Args>(verdict).table_id);
            check = parts_.tables.activate(id);
            break;
        case CommandCode::TABLE_DUMP: {
            const auto a = decoded<cmdtlm::TABLE_DUMP_Args>(verdict);
            id = static_cast<tables::TableId>(a.table_id);
            if (telemetryTask_ == nullptr || !core::isOk(telemetryTask_->sendTableDump(id, a.buffer != 0))) {
                check.reason = tables::TableReject::kNotLoaded;
            }
            break;
        }
        default:
            return failed(-1);
    }
    if (telemetryTask_ != nullptr) {
        telemetryTask_->sendTableStatus(id, check);
    }
    if (check.reason != tables::TableReject::kNone) {
        return failed(static_cast<std::int16_t>(check.reason));
    }
    return {};
}

// The plan commands go to the plan executive task as they are: it checks
// them (offsets, length, CRC, the text) and events every refusal. The
// command is accepted when the bus took the message (detail 0: it did not).
CommandOutcome AppCommandHandler::executePlan(const cmdtlm::CommandVerdict& verdict) {
    msg::PlanCommandMsg& m = planCommand_;
    m = msg::PlanCommandMsg{};
    m.timeNs = parts_.clock.now();
    switch (verdict.command->code) {
        case CommandCode::PLAN_LOAD: {
            const auto a = decoded<cmdtlm::PLAN_LOAD_Args>(verdict);
            m.kind = msg::PlanCommandKind::kChunk;
            m.offset = a.offset;
            m.length = static_cast<std::uint16_t>(std::min<std::size_t>(a.data_length, msg::kPlanChunkBytes));
            std::memcpy(m.data, a.data, m.length);
            break;
        }
        case CommandCode::PLAN_START: {
            const auto a = decoded<cmdtlm::PLAN_START_Args>(verdict);
            m.kind = msg::PlanCommandKind::kStart;
            m.textLength = a.length;
            m.crc32 = a.crc32;
            break;
        }
        case CommandCode::PLAN_SHORT: {
            const auto a = decoded<cmdtlm::PLAN_SHORT_Args>(verdict);
            m.kind = msg::PlanCommandKind::kShort;
            m.length = static_cast<std::uint16_t>(std::min<std::size_t>(a.text_length, msg::kPlanChunkBytes));
            std::memcpy(m.data, a.text, m.length);
            break;
        }
        case CommandCode::PLAN_ABORT:
            m.kind = msg::PlanCommandKind::kAbort;
            break;
        case CommandCode::PLAN_EXTEND: {
            const auto a = decoded<cmdtlm::PLAN_EXTEND_Args>(verdict);
            m.kind = msg::PlanCommandKind::kExtend;
            // extra is checked finite and within [0.1, 6553.5] s by the validator.
            m.extendMs = static_cast<std::uint32_t>(std::lround(static_cast<double>(a.extra) * 1000.0));
            m.length = static_cast<std::uint16_t>(std::min<std::size_t>(a.activity_length, msg::kPlanChunkBytes));
            std::memcpy(m.data, a.activity, m.length);
            break;
        }
        default:
            return failed(-1);
    }
    return core::isOk(parts_.bus.publish(m)) ? CommandOutcome{} : failed(0);
}

void AppCommandHandler::setMode(cmdtlm::Mode mode) {
    parts_.events.report(events::kModeChanged, core::Severity::kInfo, "app: mode %s -> %s",
                         cmdtlm::toString(mode_), cmdtlm::toString(mode));
    mode_ = mode;
    publishMode();
}

void AppCommandHandler::setEstop(bool set) {
    if (set) {
        parts_.events.report(events::kEstopSet, core::Severity::kWarning,
                             "app: software e-stop SET: all drives commanded to zero and held");
    } else {
        parts_.events.report(events::kEstopCleared, core::Severity::kInfo,
                             "app: software e-stop cleared (drives stay at zero until commanded)");
    }
    estop_ = set;
    publishMode();
}

void AppCommandHandler::publishMode() {
    msg::ModeMsg m{};
    m.timeNs = parts_.clock.now();
    m.mode = static_cast<std::uint8_t>(mode_);
    m.estop = estop_ ? 1 : 0;
    (void)parts_.bus.publish(m);
}

void AppCommandHandler::publishGoals() {
    msg::GoalListMsg m = goals_.message();
    m.timeNs = parts_.clock.now();
    (void)parts_.bus.publish(m);
    parts_.events.report(events::kGoalsChanged, core::Severity::kInfo, "app: %u goal(s), risk bound %.3g",
                         static_cast<unsigned>(m.count), m.riskBound);
}

}  // namespace rse::app
