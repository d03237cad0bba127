#include "fsw/fault_protection/fault_protection_task.hpp"

#include <cstring>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"

namespace rse::fault_protection {

FaultProtectionTask::FaultProtectionTask(core::SoftwareBus& bus, core::EventLog& events,
                                         const tables::TableService& tables)
    : bus_(bus),
      events_(events),
      tables_(tables),
      responder_(events),
      input_(bus, events,
             core::InputPipeConfig{"fault_protection", kPipeDepth, events::kMalformedInput, "fault protection"}) {}

core::Status FaultProtectionTask::init() {
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&FaultProtectionTask::takeFaultStatus>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&FaultProtectionTask::takeDriveStatus>(this);
    }
    if (core::isOk(status)) {
        status = input_.route<&FaultProtectionTask::takeMode>(this);
    }
    if (!core::isOk(status)) {
        events_.report(events::kInitFailed, core::Severity::kError, "fault protection: init refused (%s)",
                       core::toString(status));
    }
    return status;
}

void FaultProtectionTask::takeFaultStatus(const msg::FaultStatusMsg& f) { inputs_.activeFaults = f.activeMask; }

// A wheel health that is none of DriveHealth's values refuses the message as a
// whole (kInvalidArgument: the pipe counts it with the malformed, event 938):
// its producer wrote a value it has no meaning for, so its other wheels and its
// interlock flag cannot be trusted either; fault protection keeps acting on the
// last good status (a drive that was faulted stays faulted, none is taken for
// recovered), as it does for a message that does not decode.
core::Status FaultProtectionTask::takeDriveStatus(const msg::DriveStatusMsg& d) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (!msg::isKnownDriveHealth(d.wheels[w].health)) {
            input_.explain("wheel %zu (%s) health %u is no drive state", w, msg::wheelName(w),
                           static_cast<unsigned>(d.wheels[w].health));
            return core::Status::kInvalidArgument;
        }
    }
    inputs_.haveDrives = true;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        inputs_.health[w] = d.wheels[w].health;
    }
    inputs_.interlockTripped = d.interlockTripped != 0;
    return core::Status::kOk;
}

void FaultProtectionTask::takeMode(const msg::ModeMsg& m) { inputs_.autonomous = m.mode == msg::mode::kAutonomous; }

void FaultProtectionTask::publish(core::Status s) {
    if (core::isOk(s)) {
        return;
    }
    ++publishFailed_;
    if (core::isReportableOccurrence(publishFailed_)) {
        events_.report(events::kPublishFailed, core::Severity::kError,
                       "fault protection: the bus refused a message (%s, %u so far)", core::toString(s),
                       static_cast<unsigned>(publishFailed_));
    }
}

void FaultProtectionTask::publishHold(core::TimeNs now, std::uint32_t reasons, bool force) {
    const bool changed = reasons != hold_.reasons;
    if (changed) {
        if (reasons == 0) {
            ++hold_.resumeCount;
            events_.report(events::kHoldChanged, core::Severity::kInfo,
                           "fault protection: mission hold released: resuming (resume %u)",
                           static_cast<unsigned>(hold_.resumeCount));
        } else {
            events_.report(events::kHoldChanged, core::Severity::kWarning,
                           "fault protection: mission hold, reasons 0x%02x: wheels to zero, no new legs",
                           static_cast<unsigned>(reasons));
        }
    }
    hold_.reasons = reasons;
    hold_.estop = reasons != 0 ? 1 : 0;
    if (changed || force) {
        hold_.timeNs = now;
        publish(bus_.publish(hold_));
    }
}

void FaultProtectionTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    input_.drain();
    inputs_.now = now;
    const ResponderLimits limits = responderLimitsFrom(tables_.faultProtection(), tables_.faultResponse());
    ResponderActions actions;
    const std::uint32_t startedBefore = responder_.responsesStarted() + responder_.recoveries() + responder_.gaveUp();
    responder_.step(inputs_, limits, &actions);

    for (std::size_t i = 0; i < actions.driveActions.size(); ++i) {
        publish(bus_.publish(*actions.driveActions.at(i)));
    }
    for (std::size_t i = 0; i < actions.taskRestarts.size(); ++i) {
        msg::TaskRestartMsg m{};
        m.timeNs = now;
        m.row = *actions.taskRestarts.at(i);
        publish(bus_.publish(m));
    }
    for (std::size_t i = 0; i < actions.replans.size(); ++i) {
        publish(bus_.publish(*actions.replans.at(i)));
    }
    if (actions.callHome) {
        ++callHomes_;
        cmdtlm::event_data::FAULT_CALL_HOME data;
        data.reason = static_cast<double>(msg::CallHomeReason::kFaultUnrecovered);
        events_.report(events::kCallHome, core::Severity::kCritical, data.pack(),
                       "fault protection: CALL HOME: a fault response used every attempt: rover to SAFE");
        msg::SafeRequestMsg safe{};
        safe.timeNs = now;
        safe.reason = msg::CallHomeReason::kFaultUnrecovered;
        publish(bus_.publish(safe));
    }
    const bool periodic = ++runsSincePublish_ >= kPublishPeriodRuns;
    publishHold(now, actions.holdReasons, periodic);

    const std::uint32_t after = responder_.responsesStarted() + responder_.recoveries() + responder_.gaveUp();
    const bool statusChanged = after != startedBefore || status_.holdReasons != hold_.reasons ||
                               !actions.driveActions.empty() || !actions.taskRestarts.empty() || !actions.replans.empty();
    if (statusChanged || periodic) {
        runsSincePublish_ = 0;
        status_.timeNs = now;
        status_.holdReasons = hold_.reasons;
        responder_.fillStatus(&status_);
        publish(bus_.publish(status_));
    }
}

}  // namespace rse::fault_protection
