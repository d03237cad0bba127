#include "sim_stub/scenario/fault_scheduler.hpp"

#include <algorithm>

namespace rse::sim {

FaultScheduler::FaultScheduler(const std::vector<FaultSpec>& faults, FaultTarget& target)
    : target_(target), specs_(faults) {
    events_.reserve(2 * specs_.size());
    for (std::size_t i = 0; i < specs_.size(); ++i) {
        const FaultSpec& f = specs_[i];
        auto add = [this, i](core::TimeNs at, FaultAction action) { events_.push_back(FaultEvent{at, action, i}); };
        auto addEnd = [&add, &f](FaultAction action) {
            if (f.until != kNever) {
                add(f.until, action);
            }
        };
        switch (f.type) {
            case FaultType::kMotorDegradation:
                add(f.at, FaultAction::kDegradeMotor);
                break;
            case FaultType::kMotorFailure:
                add(f.at, FaultAction::kFailMotor);
                break;
            case FaultType::kDriveHeartbeatLoss:
                add(f.at, FaultAction::kHeartbeatLossStart);
                addEnd(FaultAction::kHeartbeatLossEnd);
                break;
            case FaultType::kDriveCrash:
                add(f.at, FaultAction::kCrashDrive);
                addEnd(FaultAction::kRestartDrive);
                break;
            case FaultType::kSensorDropout:
                add(f.at, FaultAction::kDropoutStart);
                addEnd(FaultAction::kDropoutEnd);
                break;
            case FaultType::kDeviceCrash:
                add(f.at, FaultAction::kCrashDevice);
                addEnd(FaultAction::kRestartDevice);
                break;
            case FaultType::kImuBiasStep:
                add(f.at, FaultAction::kImuBiasStep);
                break;
            case FaultType::kBusFault:
                add(f.at, FaultAction::kBusFault);
                break;
            case FaultType::kBabblingNode:
                add(f.at, FaultAction::kBabbleStart);
                addEnd(FaultAction::kBabbleEnd);
                break;
            case FaultType::kPositionFixOutlier:
                add(f.at, FaultAction::kPositionFixOutlier);
                break;
            case FaultType::kMotorOverheat:
                add(f.at, FaultAction::kOverheatMotor);
                break;
            case FaultType::kDriveFault:
                add(f.at, FaultAction::kDriveFault);
                break;
            case FaultType::kSlide:
                add(f.at, FaultAction::kSlide);
                break;
            case FaultType::kTaskStall:
                add(f.at, FaultAction::kTaskStallStart);
                addEnd(FaultAction::kTaskStallEnd);
                break;
            case FaultType::kInstrumentFailure:
                add(f.at, FaultAction::kInstrumentFailStart);
                addEnd(FaultAction::kInstrumentFailEnd);
                break;
        }
    }
    std::stable_sort(events_.begin(), events_.end(),
                     [](const FaultEvent& a, const FaultEvent& b) { return a.at < b.at; });
}

void FaultScheduler::step(core::TimeNs now) {
    while (next_ < events_.size() && events_[next_].at <= now) {  // bounded by the event count
        const FaultEvent& e = events_[next_];
        ++next_;
        fire(e);
    }
}

void FaultScheduler::fire(const FaultEvent& e) {
    const FaultSpec& f = specs_[e.spec];
    switch (e.action) {
        case FaultAction::kDegradeMotor:
            target_.degradeMotor(f.wheel, f.value);
            break;
        case FaultAction::kDriveFault:
            target_.faultDrive(f.wheel, static_cast<std::uint16_t>(f.cobId));
            break;
        case FaultAction::kOverheatMotor:
            target_.overheatMotor(f.wheel, f.value);
            break;
        case FaultAction::kFailMotor:
            target_.failMotor(f.wheel);
            break;
        case FaultAction::kHeartbeatLossStart:
            target_.suppressHeartbeat(f.wheel, true);
            break;
        case FaultAction::kHeartbeatLossEnd:
            target_.suppressHeartbeat(f.wheel, false);
            break;
        case FaultAction::kCrashDrive:
            target_.crashDrive(f.wheel);
            break;
        case FaultAction::kRestartDrive:
            target_.restartDrive(f.wheel);
            break;
        case FaultAction::kDropoutStart:
            target_.setDeviceDropout(f.device, true);
            break;
        case FaultAction::kDropoutEnd:
            target_.setDeviceDropout(f.device, false);
            break;
        case FaultAction::kCrashDevice:
            target_.crashDevice(f.device);
            break;
        case FaultAction::kRestartDevice:
            target_.restartDevice(f.device);
            break;
        case FaultAction::kImuBiasStep:
            target_.stepImuBias(f.value);
            break;
        case FaultAction::kBusFault:
            target_.addBusFault(f.busRule);
            break;
        case FaultAction::kBabbleStart:
            target_.babble(f.cobId, f.value, true);
            break;
        case FaultAction::kBabbleEnd:
            target_.babble(f.cobId, f.value, false);
            break;
        case FaultAction::kPositionFixOutlier:
            target_.positionFixOutlier(f.value, f.bearingRad, f.count);
            break;
        case FaultAction::kSlide:
            target_.slideRover(f.value, f.bearingRad, static_cast<double>(f.until - f.at) * 1e-9);
            break;
        case FaultAction::kTaskStallStart:
            target_.stallFlightTask(f.taskRow, f.taskName, true);
            break;
        case FaultAction::kTaskStallEnd:
            target_.stallFlightTask(f.taskRow, f.taskName, false);
            break;
        case FaultAction::kInstrumentFailStart:
            target_.failInstrument(f.device, f.faultCode, f.silent, true);
            break;
        case FaultAction::kInstrumentFailEnd:
            target_.failInstrument(f.device, f.faultCode, f.silent, false);
            break;
    }
}

}  // namespace rse::sim
