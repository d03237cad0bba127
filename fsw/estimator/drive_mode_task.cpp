#include "fsw/estimator/drive_mode_task.hpp"

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/estimator/drive_mode_events.hpp"

namespace rse::estimator {

namespace {

core::Severity severityOf(msg::DriveMode declared) {
    switch (declared) {
        case msg::DriveMode::kNominal:
            return core::Severity::kInfo;
        case msg::DriveMode::kDegraded:
            return core::Severity::kWarning;
        default:
            return core::Severity::kError;
    }
}

}  // namespace

DriveModeTask::DriveModeTask(core::SoftwareBus& bus, core::EventLog& events, const tables::TableService& tables)
    : bus_(bus),
      events_(events),
      tables_(tables),
      input_(bus, events,
             core::InputPipeConfig{"drive_modes", kDriveModePipeDepth, events::kDriveModeMalformedInput, "drive_modes"}) {
    fillLatest(0);
}

core::Status DriveModeTask::init() {
    core::Status status = input_.create();
    if (core::isOk(status)) {
        status = input_.route<&DriveModeTask::takeStatus>(this);
    }
    if (!core::isOk(status)) {
        events_.report(events::kDriveModeInitFailed, core::Severity::kError,
                       "drive_modes: start-up failed: pipe or subscription refused (%s)", core::toString(status));
        return status;
    }
    initialised_ = true;
    return status;
}

msg::DriveMode DriveModeTask::declared(std::size_t wheel) const {
    return wheel < msg::kWheelCount ? latest_.drives[wheel].declared : msg::DriveMode::kUnknown;
}

void DriveModeTask::run(const core::FrameContext& frame) {
    if (!initialised_) {
        return;
    }
    input_.drain();
    ++runs_;
    if (runs_ % kDriveModeUpdateRuns == 0) {
        update(frame, tables_.driveHealthModel());
    }
}

core::Status DriveModeTask::takeStatus(const msg::DriveStatusMsg& status) {
    // The table is the one of this run: tables change only between tasks.
    const core::Status added = estimator_.addStatus(status, tables_.driveHealthModel());
    if (core::isOk(added)) {
        ++taken_;
    }
    return added;
}

void DriveModeTask::update(const core::FrameContext& frame, const DriveHealthModel& model) {
    if (estimator_.framesInWindow() == 0) {
        ++emptyWindows_;
        if (core::isReportableOccurrence(emptyWindows_)) {
            events_.report(events::kDriveModeNoDriveStatus, core::Severity::kWarning,
                           "drive_modes: no drive status in an update window, no evidence (%u so far)",
                           static_cast<unsigned>(emptyWindows_));
        }
    }
    ModeChange changes[msg::kWheelCount];
    estimator_.update(model, changes);
    fillLatest(frame.actualStart);
    (void)bus_.publish(latest_);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const ModeChange& c = changes[w];
        if (!c.changed) {
            continue;
        }
        ++modeChanges_;
        cmdtlm::event_data::DRIVE_MODE_DECLARED data;
        data.wheel = static_cast<double>(w);
        data.from = static_cast<double>(c.from);
        data.to = static_cast<double>(c.to);
        data.probability = c.probability;
        data.power_factor = estimator_.drive(w).powerFactor();
        events_.report(events::declaredModeEventId(c.to), severityOf(c.to), data.pack(),
                       "drive_modes: %s %s -> %s (p=%.3f, power x%.2f)", msg::wheelName(w), driveModeName(c.from),
                       driveModeName(c.to), c.probability, estimator_.drive(w).powerFactor());
    }
}

void DriveModeTask::fillLatest(core::TimeNs time) {
    latest_.timeNs = time;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const DriveModeFilter& filter = estimator_.drive(w);
        msg::DriveModeBelief& belief = latest_.drives[w];
        for (std::size_t m = 0; m < msg::kDriveModeCount; ++m) {
            belief.probability[m] = static_cast<float>(filter.probability(static_cast<msg::DriveMode>(m)));
        }
        belief.powerFactor = static_cast<float>(filter.powerFactor());
        belief.declared = filter.declared();
    }
    latest_.updates = estimator_.updates();
}

}  // namespace rse::estimator
