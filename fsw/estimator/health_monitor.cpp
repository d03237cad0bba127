#include "fsw/estimator/health_monitor.hpp"

#include <cmath>

#include "fsw/estimator/health_events.hpp"

namespace rse::estimator {

namespace {

const char* const kDeviceNames[msg::kDeviceNodeCount] = {"IMU", "power", "hazard", "position fix"};

long long toMs(core::TimeNs t) { return static_cast<long long>(t / core::kNsPerMs); }

}  // namespace

HealthLimits healthLimitsFrom(const tables::FaultResponseTable& faults, const tables::EstimatorNoiseTable& noise,
                              const tables::CoarseMapTable& site) {
    HealthLimits l;
    l.persist = static_cast<core::TimeNs>(faults.fault_persist_ms) * core::kNsPerMs;
    l.driveOvercurrentA = static_cast<double>(faults.drive_overcurrent_a);
    l.busOvercurrentA = static_cast<double>(faults.overcurrent_a);
    l.batteryLowV = static_cast<double>(faults.battery_low_v);
    l.batteryClearV = static_cast<double>(faults.battery_clear_v);
    l.taskStallPeriods = faults.task_stall_periods;
    l.poseFaultSigmaM = static_cast<double>(noise.pose_fault_sigma_m);
    l.poseClearSigmaM = static_cast<double>(noise.pose_clear_sigma_m);
    l.firstFixWait = static_cast<core::TimeNs>(noise.first_fix_wait_ms) * core::kNsPerMs;
    l.driveOvertempC = static_cast<double>(faults.drive_overtemp_c);
    const std::uint16_t staleMs[msg::kDeviceNodeCount] = {noise.imu_stale_ms, noise.power_stale_ms,
                                                          noise.hazard_stale_ms, noise.fix_stale_ms};
    for (std::size_t i = 0; i < msg::kDeviceNodeCount; ++i) {
        l.sensorStale[i] = static_cast<core::TimeNs>(staleMs[i]) * core::kNsPerMs;
    }
    l.site = geometry::siteBox(site, 0.0);
    return l;
}

void HealthMonitor::start(core::TimeNs now) {
    if (!started_) {
        started_ = true;
        start_ = now;
    }
}

void HealthMonitor::rejectValue(const char* input, const char* field) {
    ++nonFinite_;
    if (core::isReportableOccurrence(nonFinite_)) {
        events_.report(events::kHealthInputRejected, core::Severity::kWarning,
                       "health: %s %s not finite or out of range, ignored (%u so far)", input, field,
                       static_cast<unsigned>(nonFinite_));
    }
}

void HealthMonitor::setHeartbeat(std::uint8_t id, bool lost, const msg::NodeStatusMsg& status, std::size_t node,
                                 core::TimeNs now) {
    const core::TimeNs since = faults_.changedAt(id);
    if (!faults_.set(id, lost, now)) {
        return;
    }
    const bool drive = node < msg::kWheelCount;
    const char* name = drive ? msg::wheelName(node) : kDeviceNames[node - msg::kWheelCount];
    const char* kind = drive ? "drive" : "device";
    if (lost) {
        const msg::NodeLiveness& n = status.nodes[node];
        events_.report(drive ? events::kHealthDriveHeartbeatLost : events::kHealthDeviceHeartbeatLost,
                       core::Severity::kError, "health: fault %u: %s %s (node %u) heartbeat lost, silent %lld ms",
                       static_cast<unsigned>(id), kind, name, static_cast<unsigned>(n.nodeId),
                       toMs(status.timeNs - n.lastSeenNs));
    } else {
        events_.report(drive ? events::kHealthDriveHeartbeatRestored : events::kHealthDeviceHeartbeatRestored,
                       core::Severity::kInfo, "health: fault %u cleared: %s %s heartbeat back after %lld ms lost",
                       static_cast<unsigned>(id), kind, name, toMs(now - since));
    }
}

void HealthMonitor::onNodeStatus(const msg::NodeStatusMsg& status, core::TimeNs now) {
    for (std::size_t i = 0; i < msg::kMonitoredNodeCount; ++i) {
        const std::uint8_t id = static_cast<std::uint8_t>(
            i < msg::kWheelCount ? msg::fault::kDriveHeartbeatLost + i
                                 : msg::fault::kDeviceHeartbeatLost + (i - msg::kWheelCount));
        setHeartbeat(id, status.nodes[i].lost != 0, status, i, now);
    }
}

void HealthMonitor::onDriveStatus(const msg::DriveStatusMsg& status, const HealthLimits& limits, core::TimeNs now) {
    const double raiseA = limits.driveOvercurrentA;
    const double clearA = kOvercurrentClearFraction * limits.driveOvercurrentA;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const double current = status.wheels[w].currentA;
        if (!std::isfinite(current)) {
            rejectValue(msg::wheelName(w), "drive currentA");
            continue;
        }
        const double magnitude = std::fabs(current);
        PersistenceFilter& filter = driveCurrent_[w];
        const core::TimeNs since = filter.pendingSince();
        const PersistenceFilter::Edge edge =
            filter.update(status.timeNs, magnitude > raiseA, magnitude < clearA, limits.persist);
        if (edge == PersistenceFilter::Edge::kNone) {
            continue;
        }
        const auto id = static_cast<std::uint8_t>(msg::fault::kDriveOvercurrent + w);
        const bool raised = edge == PersistenceFilter::Edge::kRaised;
        (void)faults_.set(id, raised, now);
        if (raised) {
            events_.report(events::kHealthDriveOvercurrent, core::Severity::kError,
                           "health: fault %u: drive %s over-current %.2f A > %.2f A for %lld ms",
                           static_cast<unsigned>(id), msg::wheelName(w), current, raiseA,
                           toMs(status.timeNs - since));
        } else {
            events_.report(events::kHealthDriveOvercurrentCleared, core::Severity::kInfo,
                           "health: fault %u cleared: drive %s current %.2f A < %.2f A for %lld ms",
                           static_cast<unsigned>(id), msg::wheelName(w), current, clearA,
                           toMs(status.timeNs - since));
        }
    }
    checkDriveTemperature(status, limits, now);
}

void HealthMonitor::checkDriveTemperature(const msg::DriveStatusMsg& status, const HealthLimits& limits,
                                          core::TimeNs now) {
    const double raiseC = limits.driveOvertempC;
    const double clearC = limits.driveOvertempC - kOvertempClearMarginC;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const msg::WheelStatus& wheel = status.wheels[w];
        if (wheel.temperatureValid == 0) {
            continue;  // not reported yet: no evidence either way
        }
        const double celsius = static_cast<double>(wheel.temperatureC);
        if (!std::isfinite(celsius)) {
            rejectValue(msg::wheelName(w), "drive temperatureC");
            continue;
        }
        PersistenceFilter& filter = driveTemperature_[w];
        const core::TimeNs since = filter.pendingSince();
        const PersistenceFilter::Edge edge = filter.update(status.timeNs, celsius > raiseC, celsius < clearC, limits.persist);
        if (edge == PersistenceFilter::Edge::kNone) {
            continue;
        }
        const auto id = static_cast<std::uint8_t>(msg::fault::kDriveOvertemp + w);
        const bool raised = edge == PersistenceFilter::Edge::kRaised;
        (void)faults_.set(id, raised, now);
        events_.report(raised ? events::kHealthDriveOvertemp : events::kHealthDriveOvertempCleared,
                       raised ? core::Severity::kError : core::Severity::kInfo,
                       raised ? "health: fault %u: drive %s motor %.1f degC > %.1f degC for %lld ms"
                              : "health: fault %u cleared: drive %s motor %.1f degC < %.1f degC for %lld ms",
                       static_cast<unsigned>(id), msg::wheelName(w), celsius, raised ? raiseC : clearC,
                       toMs(status.timeNs - since));
    }
}

void HealthMonitor::onPower(const msg::PowerMsg& power, const HealthLimits& limits, core::TimeNs now) {
    if (!std::isfinite(power.busVoltageV)) {
        rejectValue("power", "busVoltageV");
    } else {
        const core::TimeNs since = batteryLow_.pendingSince();
        const PersistenceFilter::Edge edge =
            batteryLow_.update(power.timeNs, power.busVoltageV < limits.batteryLowV,
                               power.busVoltageV > limits.batteryClearV, limits.persist);
        if (edge == PersistenceFilter::Edge::kRaised) {
            (void)faults_.set(msg::fault::kBatteryLow, true, now);
            events_.report(events::kHealthBatteryLow, core::Severity::kCritical,
                           "health: fault %u: battery low, bus %.2f V < %.2f V for %lld ms",
                           static_cast<unsigned>(msg::fault::kBatteryLow), power.busVoltageV, limits.batteryLowV,
                           toMs(power.timeNs - since));
        } else if (edge == PersistenceFilter::Edge::kCleared) {
            (void)faults_.set(msg::fault::kBatteryLow, false, now);
            events_.report(events::kHealthBatteryLowCleared, core::Severity::kInfo,
                           "health: fault %u cleared: bus %.2f V > %.2f V for %lld ms",
                           static_cast<unsigned>(msg::fault::kBatteryLow), power.busVoltageV,
                           limits.batteryClearV, toMs(power.timeNs - since));
        }
    }
    if (!std::isfinite(power.busCurrentA)) {
        rejectValue("power", "busCurrentA");
        return;
    }
    const double clearA = kOvercurrentClearFraction * limits.busOvercurrentA;
    const core::TimeNs since = busCurrent_.pendingSince();
    const PersistenceFilter::Edge edge = busCurrent_.update(
        power.timeNs, power.busCurrentA > limits.busOvercurrentA, power.busCurrentA < clearA, limits.persist);
    if (edge == PersistenceFilter::Edge::kRaised) {
        (void)faults_.set(msg::fault::kBusOvercurrent, true, now);
        events_.report(events::kHealthBusOvercurrent, core::Severity::kError,
                       "health: fault %u: bus over-current %.2f A > %.2f A for %lld ms",
                       static_cast<unsigned>(msg::fault::kBusOvercurrent), power.busCurrentA,
                       limits.busOvercurrentA, toMs(power.timeNs - since));
    } else if (edge == PersistenceFilter::Edge::kCleared) {
        (void)faults_.set(msg::fault::kBusOvercurrent, false, now);
        events_.report(events::kHealthBusOvercurrentCleared, core::Severity::kInfo,
                       "health: fault %u cleared: bus current %.2f A < %.2f A for %lld ms",
                       static_cast<unsigned>(msg::fault::kBusOvercurrent), power.busCurrentA, clearA,
                       toMs(power.timeNs - since));
    }
}

void HealthMonitor::onPose(const msg::PoseEstimateMsg& pose) {
    if (!std::isfinite(pose.positionSigmaM) || pose.positionSigmaM < 0.0) {
        rejectValue("pose", "positionSigmaM");
        return;
    }
    if (!std::isfinite(pose.xM) || !std::isfinite(pose.yM)) {
        rejectValue("pose", "position");
        return;
    }
    poseX_ = pose.xM;
    poseY_ = pose.yM;
    poseSeen_ = true;
    poseInitialised_ = pose.initialised != 0;
    poseInconsistent_ = pose.inconsistent != 0;
    poseRejections_ = pose.consecutiveFixRejections;
    poseSigmaM_ = pose.positionSigmaM;
}

void HealthMonitor::checkPose(const HealthLimits& limits, core::TimeNs now) {
    // Until an estimate says otherwise, no absolute position is known: no pose
    // message at all counts as not initialised.
    const bool initialised = poseSeen_ && poseInitialised_;
    const bool noFixInTime = !initialised && now - start_ > limits.firstFixWait;
    const bool inconsistent = initialised && poseInconsistent_;
    const bool tooUncertain = initialised && (poseSigmaM_ > limits.poseFaultSigmaM || inconsistent);
    const bool certain = initialised && !inconsistent && poseSigmaM_ < limits.poseClearSigmaM;
    const PersistenceFilter::Edge edge = pose_.update(now, noFixInTime || tooUncertain, certain, 0);
    if (edge == PersistenceFilter::Edge::kRaised) {
        (void)faults_.set(msg::fault::kPoseUncertain, true, now);
        if (noFixInTime) {
            events_.report(events::kHealthPoseUncertain, core::Severity::kError,
                           "health: fault %u: pose uncertain, no position fix %lld ms after start (wait %lld ms)",
                           static_cast<unsigned>(msg::fault::kPoseUncertain), toMs(now - start_),
                           toMs(limits.firstFixWait));
        } else if (inconsistent) {
            events_.report(events::kHealthPoseUncertain, core::Severity::kError,
                           "health: fault %u: pose uncertain, estimate inconsistent with the fixes (%u refused in a row)",
                           static_cast<unsigned>(msg::fault::kPoseUncertain), static_cast<unsigned>(poseRejections_));
        } else {
            events_.report(events::kHealthPoseUncertain, core::Severity::kError,
                           "health: fault %u: pose uncertain, position sigma %.2f m > %.2f m",
                           static_cast<unsigned>(msg::fault::kPoseUncertain), poseSigmaM_, limits.poseFaultSigmaM);
        }
    } else if (edge == PersistenceFilter::Edge::kCleared) {
        (void)faults_.set(msg::fault::kPoseUncertain, false, now);
        events_.report(events::kHealthPoseUncertainCleared, core::Severity::kInfo,
                       "health: fault %u cleared: position sigma %.2f m < %.2f m",
                       static_cast<unsigned>(msg::fault::kPoseUncertain), poseSigmaM_, limits.poseClearSigmaM);
    }
}

void HealthMonitor::checkOffMap(const HealthLimits& limits, core::TimeNs now) {
    const bool known = poseSeen_ && poseInitialised_ && !poseInconsistent_ && poseSigmaM_ <= limits.poseFaultSigmaM;
    const double outside = geometry::outsideBy(limits.site, poseX_, poseY_);
    const PersistenceFilter::Edge edge =
        offMap_.update(now, known && outside > 0.0, known && outside <= -kOffMapClearMarginM, 0);
    if (edge == PersistenceFilter::Edge::kRaised) {
        (void)faults_.set(msg::fault::kOffMap, true, now);
        events_.report(events::kHealthOffMap, core::Severity::kError,
                       "health: fault %u: off the map, pose (%.2f, %.2f) %.2f m outside the site",
                       static_cast<unsigned>(msg::fault::kOffMap), poseX_, poseY_, outside);
    } else if (edge == PersistenceFilter::Edge::kCleared) {
        (void)faults_.set(msg::fault::kOffMap, false, now);
        events_.report(events::kHealthOffMapCleared, core::Severity::kInfo,
                       "health: fault %u cleared: pose (%.2f, %.2f) back on the map, %.2f m inside",
                       static_cast<unsigned>(msg::fault::kOffMap), poseX_, poseY_, -outside);
    }
}

void HealthMonitor::onSensorData(msg::DeviceNode device, core::TimeNs sampleTime) {
    const auto i = static_cast<std::size_t>(device);
    if (i < msg::kDeviceNodeCount && sampleTime > sensorDataAt_[i]) {
        sensorDataAt_[i] = sampleTime;
    }
}

void HealthMonitor::onHazards(const msg::HazardMsg& hazards) {
    if (!hazardFramesSeen_ || hazards.detectorFrames != hazardFrames_) {
        // The first message counts only if the detector has spoken at all.
        if (hazardFramesSeen_ || hazards.detectorFrames != 0) {
            onSensorData(msg::DeviceNode::kHazard, hazards.timeNs);
        }
        hazardFramesSeen_ = true;
        hazardFrames_ = hazards.detectorFrames;
    }
}

void HealthMonitor::checkSensors(const HealthLimits& limits, core::TimeNs now) {
    for (std::size_t i = 0; i < msg::kDeviceNodeCount; ++i) {
        const core::TimeNs reference = sensorDataAt_[i] != 0 ? sensorDataAt_[i] : start_;
        const core::TimeNs silent = now - reference;
        const bool stale = silent > limits.sensorStale[i];
        const auto id = static_cast<std::uint8_t>(msg::fault::kSensorStale + i);
        const core::TimeNs since = faults_.changedAt(id);
        if (!faults_.set(id, stale, now)) {
            continue;
        }
        if (stale) {
            events_.report(events::kHealthSensorStale, core::Severity::kError,
                           "health: fault %u: %s data stale, none for %lld ms (limit %lld ms)",
                           static_cast<unsigned>(id), kDeviceNames[i], toMs(silent), toMs(limits.sensorStale[i]));
        } else {
            events_.report(events::kHealthSensorStaleCleared, core::Severity::kInfo,
                           "health: fault %u cleared: %s data back after %lld ms stale", static_cast<unsigned>(id),
                           kDeviceNames[i], toMs(now - since));
        }
    }
}

void HealthMonitor::checkTasks(const core::Executive& executive, const core::Task* self, const HealthLimits& limits,
                               core::TimeNs now) {
    const std::size_t rows = executive.taskCount() < kWatchedTaskRows ? executive.taskCount() : kWatchedTaskRows;
    for (std::size_t i = 0; i < rows; ++i) {
        const core::RateGroupEntry* entry = executive.entry(i);
        const core::TaskLiveness* liveness = executive.taskLiveness(i);
        // The health task cannot see itself stall (it would have to run to notice);
        // that is the hardware watchdog's job, fed from the executive loop.
        if (entry == nullptr || liveness == nullptr || entry->task == self) {
            continue;
        }
        const core::TimeNs period = static_cast<core::TimeNs>(entry->rateDivisor) * executive.config().minorFramePeriod;
        const core::TimeNs limit = static_cast<core::TimeNs>(limits.taskStallPeriods) * period;
        // lastRunEnd 0 means never ran: it has had since our first run to do so.
        const core::TimeNs reference = liveness->lastRunEnd != 0 ? liveness->lastRunEnd : start_;
        const core::TimeNs silent = now - reference;
        const auto id = static_cast<std::uint8_t>(msg::fault::kTaskStalled + i);
        const core::TimeNs since = faults_.changedAt(id);
        if (!faults_.set(id, silent > limit, now)) {
            continue;
        }
        if (silent > limit) {
            events_.report(events::kHealthTaskStalled, core::Severity::kError,
                           "health: fault %u: task %s stalled, not run for %lld ms (limit %lld ms)%s",
                           static_cast<unsigned>(id), entry->name, toMs(silent), toMs(limit),
                           liveness->enabled ? "" : ", disabled");
        } else {
            events_.report(events::kHealthTaskStalledCleared, core::Severity::kInfo,
                           "health: fault %u cleared: task %s running again after %lld ms stalled",
                           static_cast<unsigned>(id), entry->name, toMs(now - since));
        }
    }
}

}  // namespace rse::estimator
