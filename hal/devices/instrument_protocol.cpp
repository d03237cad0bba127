#include "hal/devices/instrument_protocol.hpp"

#include <cmath>

#include "hal/canopen/le_codec.hpp"

namespace rse::hal::instrument {

const char* toString(Kind kind) {
    switch (kind) {
        case Kind::kGrinder:
            return "grinder";
        case Kind::kCamera:
            return "camera";
    }
    return "?";
}

const char* toString(Action action) {
    switch (action) {
        case Action::kNone:
            return "none";
        case Action::kSample:
            return "sample";
        case Action::kDig:
            return "dig";
        case Action::kImage:
            return "image";
        case Action::kCancel:
            return "cancel";
        case Action::kExtend:
            return "extend";
    }
    return "?";
}

const char* toString(State state) {
    switch (state) {
        case State::kIdle:
            return "idle";
        case State::kBusy:
            return "busy";
        case State::kDone:
            return "done";
        case State::kFailed:
            return "failed";
    }
    return "?";
}

const char* toString(Result result) {
    switch (result) {
        case Result::kNone:
            return "none";
        case Result::kCancelled:
            return "cancelled";
        case Result::kTimedOut:
            return "timed out";
        case Result::kOutOfReach:
            return "target out of reach";
        case Result::kAborted:
            return "aborted by a fault";
    }
    return "?";
}

const char* toString(Refusal refusal) {
    switch (refusal) {
        case Refusal::kNone:
            return "none";
        case Refusal::kBusy:
            return "busy";
        case Refusal::kUnsupportedAction:
            return "action not supported";
        case Refusal::kUnknownTarget:
            return "unknown target";
        case Refusal::kOutOfReach:
            return "target out of reach";
        case Refusal::kFaulted:
            return "instrument faulted";
        case Refusal::kMalformed:
            return "malformed command";
        case Refusal::kNoSuchCommand:
            return "cancel or extend: no such command running";
        case Refusal::kOffline:
            return "instrument offline";
        case Refusal::kNotSent:
            return "CAN refused the frame";
    }
    return "?";
}

bool durationField(double seconds, std::uint16_t* field) {
    // Written so that NaN fails too.
    if (!(seconds >= 0.0 && seconds <= kMaxDurationS)) {
        return false;
    }
    *field = static_cast<std::uint16_t>(std::ceil(seconds / kDurationUnitS - 1e-9));
    return true;
}

void encodeCommand(Kind kind, const Command& command, CanFrame* frame) {
    *frame = CanFrame{};
    frame->id = idsOf(kind).commandCobId;
    frame->dlc = kFrameDlc;
    frame->data[0] = static_cast<std::uint8_t>(command.action);
    frame->data[1] = command.target;
    le::putU16(&frame->data[2], command.commandId);
    le::putU16(&frame->data[4], command.maxDurationDs);
    if (command.action == Action::kExtend) {
        le::putU16(&frame->data[6], command.extendsCommandId);
    }
}

bool decodeCommand(const CanFrame& frame, Command* command, Refusal* why) {
    command->action = static_cast<Action>(frame.data[0]);
    command->target = frame.data[1];
    command->commandId = le::getU16(&frame.data[2]);
    command->maxDurationDs = le::getU16(&frame.data[4]);
    const bool extend = command->action == Action::kExtend;
    command->extendsCommandId = extend ? le::getU16(&frame.data[6]) : 0;
    const bool reservedOk = extend ? command->extendsCommandId != 0 && command->extendsCommandId != command->commandId &&
                                         command->maxDurationDs != 0
                                   : frame.data[6] == 0 && frame.data[7] == 0;
    if (frame.dlc != kFrameDlc || frame.remote() || command->commandId == 0 || !reservedOk) {
        *why = Refusal::kMalformed;
        return false;
    }
    return true;
}

void encodeReport(Kind kind, const Report& report, CanFrame* frame) {
    *frame = CanFrame{};
    frame->id = idsOf(kind).statusCobId;
    frame->dlc = kFrameDlc;
    frame->data[0] = static_cast<std::uint8_t>((static_cast<unsigned>(report.kind) << 4U) |
                                               (static_cast<unsigned>(report.state) & 0x0FU));
    frame->data[1] = static_cast<std::uint8_t>(report.action);
    frame->data[2] = report.target;
    le::putU16(&frame->data[3], report.commandId);
    const bool status = report.kind == ReportKind::kStatus;
    frame->data[5] = status ? report.progressPct : static_cast<std::uint8_t>(report.refusal);
    frame->data[6] = status ? static_cast<std::uint8_t>(report.result) : 0;
    frame->data[7] = report.faultCode;
}

namespace {

// The invariants of a status report (see the header); nullptr when it keeps them.
const char* statusProblem(Kind kind, const Report& r) {
    if (r.action != Action::kNone && !doesWork(kind, r.action)) {
        return "action not one of this instrument's";
    }
    if (r.progressPct > 100 || static_cast<std::uint8_t>(r.result) > kLastResult) {
        return "progress above 100 % or unknown result";
    }
    if ((r.commandId == 0) != (r.action == Action::kNone) || (r.commandId == 0) != (r.target == 0) ||
        (r.commandId == 0 && r.result != Result::kNone)) {
        return "command id, action, target and result not all set or all 0";
    }
    const bool failureResult =
        r.result == Result::kTimedOut || r.result == Result::kOutOfReach || r.result == Result::kAborted;
    switch (r.state) {
        case State::kBusy:
        case State::kDone:
            if (r.commandId == 0 || r.result != Result::kNone || r.faultCode != 0 ||
                (r.state == State::kBusy) != (r.progressPct < 100)) {
                return "busy or done without its command, with a result or fault, or at the wrong progress";
            }
            return nullptr;
        case State::kFailed:
            if (r.faultCode == 0 && !failureResult) {
                return "failed without a fault code or a failure result";
            }
            return nullptr;
        case State::kIdle:
            return nullptr;  // its fault code was checked above
    }
    return "unknown state";
}

}  // namespace

bool decodeReport(Kind kind, const std::uint8_t (&data)[kCanMaxDlc], Report* report, const char** reason) {
    Report r;
    const auto kind4 = static_cast<std::uint8_t>(data[0] >> 4U);
    const auto state4 = static_cast<std::uint8_t>(data[0] & 0x0FU);
    if ((kind4 != static_cast<std::uint8_t>(ReportKind::kStatus) &&
         kind4 != static_cast<std::uint8_t>(ReportKind::kRefusal)) ||
        state4 > static_cast<std::uint8_t>(State::kFailed)) {
        *reason = "unknown report kind or state";
        return false;
    }
    r.kind = static_cast<ReportKind>(kind4);
    r.state = static_cast<State>(state4);
    r.action = static_cast<Action>(data[1]);
    r.target = data[2];
    r.commandId = le::getU16(&data[3]);
    r.faultCode = data[7];
    if (r.faultCode != 0 && r.state != State::kFailed) {
        *reason = "fault code outside state failed";
        return false;
    }
    if (r.kind == ReportKind::kRefusal) {
        r.refusal = static_cast<Refusal>(data[5]);
        if (data[5] == 0 || data[5] > kLastWireRefusal || data[6] != 0) {
            *reason = "refusal with an unknown reason or a reserved byte set";
            return false;
        }
        *report = r;
        return true;
    }
    r.progressPct = data[5];
    r.result = static_cast<Result>(data[6]);
    const char* problem = statusProblem(kind, r);
    if (problem != nullptr) {
        *reason = problem;
        return false;
    }
    *report = r;
    return true;
}

}  // namespace rse::hal::instrument
