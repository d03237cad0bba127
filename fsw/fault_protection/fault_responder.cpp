#include "fsw/fault_protection/fault_responder.hpp"

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"

namespace rse::fault_protection {

using msg::FaultClass;
using msg::FaultResponseKind;
using msg::ResponseState;

namespace {

std::size_t idx(FaultClass c) { return static_cast<std::size_t>(c); }

bool bit(std::uint64_t mask, std::uint32_t id) { return ((mask >> id) & 1u) != 0; }

std::uint32_t holdBitFor(FaultClass c) {
    switch (c) {
        case FaultClass::kDriveLost:
        case FaultClass::kDriveFaulted:
        case FaultClass::kDriveOvercurrent: return msg::hold::kDriveRecovery;
        case FaultClass::kSensorLost: return msg::hold::kSensorLost;
        case FaultClass::kBatteryLow: return msg::hold::kBatteryLow;
        case FaultClass::kBusOvercurrent: return msg::hold::kDriveRecovery;
        case FaultClass::kPoseUncertain: return msg::hold::kPoseUncertain;
        case FaultClass::kTaskStalled: return msg::hold::kTaskRestart;
        case FaultClass::kDriveOvertemp: return msg::hold::kDriveOvertemp;
        case FaultClass::kOffMap: return msg::hold::kOffMap;
    }
    return msg::hold::kDriveRecovery;
}

// What a response kind means for a class it cannot apply to: a drive recovery
// needs a drive, a task restart a task, a replan from the pose a rover off the
// map (a replan mends no drive or sensor). Such a class is held instead (the
// table's description says so), never ignored.
FaultResponseKind effectiveKind(FaultClass c, FaultResponseKind k) {
    const bool drive = c == FaultClass::kDriveLost || c == FaultClass::kDriveFaulted;
    if ((k == FaultResponseKind::kRecoverDrive && !drive) ||
        (k == FaultResponseKind::kRestartTask && c != FaultClass::kTaskStalled) ||
        (k == FaultResponseKind::kReplanFromPose && c != FaultClass::kOffMap)) {
        return FaultResponseKind::kHoldUntilClear;
    }
    return k;
}

bool healthyDrive(msg::DriveHealth h) { return h == msg::DriveHealth::kOperational; }

// The drive a fault id is about (its place in a per-wheel range: heartbeat lost,
// over-current, over-temperature), -1 for a fault of no drive: event 933's wheel.
double wheelOfFault(std::uint8_t id) {
    namespace f = msg::fault;
    for (const std::uint8_t first : {f::kDriveHeartbeatLost, f::kDriveOvercurrent, f::kDriveOvertemp}) {
        if (id >= first && id < first + msg::kWheelCount) {
            return static_cast<double>(id - first);
        }
    }
    return -1.0;
}

}  // namespace

bool classOf(std::uint8_t id, FaultClass* out) {
    namespace f = msg::fault;
    if (id >= f::kDriveHeartbeatLost && id < f::kDriveHeartbeatLost + msg::kWheelCount) {
        *out = FaultClass::kDriveLost;
    } else if (id >= f::kDeviceHeartbeatLost && id < f::kDeviceHeartbeatLost + msg::kDeviceNodeCount) {
        *out = FaultClass::kSensorLost;
    } else if (id >= f::kDriveOvercurrent && id < f::kDriveOvercurrent + msg::kWheelCount) {
        *out = FaultClass::kDriveOvercurrent;
    } else if (id == f::kBatteryLow) {
        *out = FaultClass::kBatteryLow;
    } else if (id == f::kBusOvercurrent) {
        *out = FaultClass::kBusOvercurrent;
    } else if (id == f::kPoseUncertain) {
        *out = FaultClass::kPoseUncertain;
    } else if (id >= f::kTaskStalled && id < f::kTaskStalled + f::kTaskStalledCount) {
        *out = FaultClass::kTaskStalled;
    } else if (id >= f::kSensorStale && id < f::kSensorStale + msg::kDeviceNodeCount) {
        *out = FaultClass::kSensorLost;
    } else if (id >= f::kDriveOvertemp && id < f::kDriveOvertemp + msg::kWheelCount) {
        *out = FaultClass::kDriveOvertemp;
    } else if (id == f::kOffMap) {
        *out = FaultClass::kOffMap;
    } else {
        return false;
    }
    return true;
}

const char* toString(FaultClass c) {
    switch (c) {
        case FaultClass::kDriveLost: return "drive lost";
        case FaultClass::kDriveFaulted: return "drive faulted";
        case FaultClass::kDriveOvercurrent: return "drive over-current";
        case FaultClass::kSensorLost: return "sensor lost";
        case FaultClass::kBatteryLow: return "battery low";
        case FaultClass::kBusOvercurrent: return "bus over-current";
        case FaultClass::kPoseUncertain: return "pose uncertain";
        case FaultClass::kTaskStalled: return "task stalled";
        case FaultClass::kDriveOvertemp: return "drive over-temperature";
        case FaultClass::kOffMap: return "off the map";
    }
    return "?";
}

const char* toString(FaultResponseKind k) {
    switch (k) {
        case FaultResponseKind::kEventOnly: return "event only";
        case FaultResponseKind::kHoldUntilClear: return "hold until clear";
        case FaultResponseKind::kRecoverDrive: return "recover the drive";
        case FaultResponseKind::kRestartTask: return "restart the task";
        case FaultResponseKind::kSafeAndCallHome: return "safe and call home";
        case FaultResponseKind::kReplanFromPose: return "replan from the pose";
    }
    return "?";
}

ResponderLimits responderLimitsFrom(const tables::FaultProtectionTable& protection,
                                    const tables::FaultResponseTable& faults) {
    ResponderLimits l;
    for (std::size_t c = 0; c < msg::kFaultClassCount; ++c) {
        // The table's ranges were checked when it was validated.
        l.response[c] = static_cast<FaultResponseKind>(protection.response[c]);
        l.attempts[c] = protection.attempts[c];
        l.maxWait[c] = static_cast<core::TimeNs>(protection.max_wait_ms[c]) * core::kNsPerMs;
    }
    l.attemptMemory = static_cast<core::TimeNs>(protection.attempt_memory_ms) * core::kNsPerMs;
    l.driveLostSettle = static_cast<core::TimeNs>(faults.heartbeat_loss_ms) * core::kNsPerMs;
    return l;
}

void FaultResponder::enter(Response& r, ResponseState state, core::TimeNs now) {
    r.tlm.state = state;
    r.tlm.sinceNs = now;
}

void FaultResponder::begin(Response& r, FaultClass c, std::uint8_t faultId, ResponseState state,
                           const ResponderLimits& limits, core::TimeNs now) {
    // Attempts are remembered across a quick return of the fault, forgotten after attempt_memory_ms clear.
    if (r.tlm.state != ResponseState::kRecovered || now - r.clearSince >= limits.attemptMemory) {
        r.tlm.attemptsUsed = 0;
    }
    r.tlm.faultId = faultId;
    r.tlm.faultClass = c;
    r.tlm.lastAction = 0;
    ++started_;
    enter(r, state, now);
    events_.report(events::kResponseStarted, core::Severity::kWarning,
                   "fault protection: %s (fault %u): %s (%u of %u tries used)", toString(c),
                   static_cast<unsigned>(faultId), toString(effectiveKind(c, limits.response[idx(c)])),
                   static_cast<unsigned>(r.tlm.attemptsUsed), static_cast<unsigned>(limits.attempts[idx(c)]));
}

void FaultResponder::recovered(Response& r, core::TimeNs now, const char* what) {
    ++recoveries_;
    events_.report(events::kRecovered, core::Severity::kInfo,
                   "fault protection: %s (fault %u) %s, try %u, %lld ms",
                   toString(r.tlm.faultClass), static_cast<unsigned>(r.tlm.faultId), what,
                   static_cast<unsigned>(r.tlm.attemptsUsed), static_cast<long long>((now - r.tlm.sinceNs) / core::kNsPerMs));
    r.clearSince = now;
    enter(r, ResponseState::kRecovered, now);
}

void FaultResponder::giveUp(Response& r, core::TimeNs now, const char* what, ResponderActions* out, bool callHome) {
    ++gaveUp_;
    cmdtlm::event_data::FAULT_GAVE_UP data;
    data.fault_class = static_cast<double>(r.tlm.faultClass);
    data.fault_id = r.tlm.faultId;
    data.wheel = wheelOfFault(r.tlm.faultId);
    data.attempts = r.tlm.attemptsUsed;
    data.call_home = callHome ? 1.0 : 0.0;
    events_.report(events::kGaveUp, core::Severity::kCritical, data.pack(),
                   "fault protection: %s (fault %u): %u tries used: %s", toString(r.tlm.faultClass),
                   static_cast<unsigned>(r.tlm.faultId), static_cast<unsigned>(r.tlm.attemptsUsed), what);
    out->callHome = out->callHome || callHome;
    enter(r, ResponseState::kGaveUp, now);
}

void FaultResponder::askInterlockReset(const ResponderInputs& in, ResponderActions* out) {
    if (interlockAskedAt_ >= 0 && in.now - interlockAskedAt_ < kInterlockResetRetry) {
        return;
    }
    msg::DriveRecoveryMsg m{};
    m.timeNs = in.now;
    m.action = msg::DriveRecoveryAction::kResetInterlock;
    if (core::isOk(out->driveActions.push_back(m))) {
        interlockAskedAt_ = in.now;
        ++actions_;
        ++interlockAsks_;
        if (core::isReportableOccurrence(interlockAsks_)) {
            events_.report(events::kInterlockReset, core::Severity::kInfo,
                           "fault protection: every drive healthy: interlock reset asked (%u times)",
                           static_cast<unsigned>(interlockAsks_));
        }
    }
}

void FaultResponder::driveAct(std::size_t w, Response& r, const ResponderInputs& in, const ResponderLimits& limits,
                              ResponderActions* out) {
    const FaultClass c = r.tlm.faultClass;
    if (r.tlm.attemptsUsed >= limits.attempts[idx(c)]) {
        giveUp(r, in.now, "drive failed, deliberative decides", out, false);
        return;
    }
    ++r.tlm.attemptsUsed;
    // A faulted drive first gets a fault reset; a lost one, or one a fault
    // reset did not bring back, a node reset (it reboots and is configured anew).
    const bool faultReset = c == FaultClass::kDriveFaulted && r.tlm.attemptsUsed == 1;
    msg::DriveRecoveryMsg m{};
    m.timeNs = in.now;
    m.wheel = static_cast<std::uint8_t>(w);
    m.action = faultReset ? msg::DriveRecoveryAction::kFaultReset : msg::DriveRecoveryAction::kResetNode;
    r.tlm.lastAction = static_cast<std::uint8_t>(m.action);
    if (core::isOk(out->driveActions.push_back(m))) {
        ++actions_;
    }
    events_.report(events::kDriveAction, core::Severity::kWarning,
                   "fault protection: wheel %zu (%s): %s, attempt %u of %u", w, msg::wheelName(w),
                   faultReset ? "CiA 402 fault reset" : "NMT reset node", static_cast<unsigned>(r.tlm.attemptsUsed),
                   static_cast<unsigned>(limits.attempts[idx(c)]));
    enter(r, ResponseState::kWaiting, in.now);
}

FaultResponder::WheelReading FaultResponder::readWheel(std::size_t w, const ResponderInputs& in,
                                                       const ResponderLimits& limits) {
    WheelReading d;
    d.lostId = static_cast<std::uint8_t>(msg::fault::kDriveHeartbeatLost + w);
    const bool lostFault = bit(in.activeFaults, d.lostId);
    d.health = in.health[w];
    const bool lost = lostFault || (in.haveDrives && d.health == msg::DriveHealth::kLost);
    const bool faulted =
        in.haveDrives && (d.health == msg::DriveHealth::kFaulted || d.health == msg::DriveHealth::kFailed);
    if (lostFault && in.haveDrives && healthyDrive(d.health)) {
        // The heartbeat says lost, the drive status says operational: a fault wins.
        ++conflicts_;
        if (core::isReportableOccurrence(conflicts_)) {
            events_.report(events::kConflictingReport, core::Severity::kWarning,
                           "fault protection: wheel %zu reported operational and heartbeat-lost at once: taken as lost "
                           "(%u so far)", w, static_cast<unsigned>(conflicts_));
        }
    }
    d.trouble = lost || faulted;
    d.healthy = in.haveDrives && healthyDrive(d.health) && !lostFault;
    d.faultClass = lost ? FaultClass::kDriveLost : FaultClass::kDriveFaulted;
    d.kind = effectiveKind(d.faultClass, limits.response[idx(d.faultClass)]);
    return d;
}

void FaultResponder::beginWheel(Response& r, const WheelReading& d, const ResponderInputs& in,
                                const ResponderLimits& limits, ResponderActions* out) {
    const FaultClass c = d.faultClass;
    if (d.kind == FaultResponseKind::kRecoverDrive) {
        // A drive back in trouble within attempt_memory_ms of its last
        // recovery spends a try even when it recovers by itself again (a
        // worn motor tripping on every turn must not loop for ever).
        const bool again = r.tlm.state == ResponseState::kRecovered && in.now - r.clearSince < limits.attemptMemory;
        begin(r, c, d.lostId, ResponseState::kSettling, limits, in.now);
        if (again && r.tlm.attemptsUsed >= limits.attempts[idx(c)]) {
            giveUp(r, in.now, "back too soon: drive failed, deliberative decides", out, false);
        } else if (again) {
            ++r.tlm.attemptsUsed;
        }
        return;
    }
    begin(r, c, d.lostId, ResponseState::kWaiting, limits, in.now);
    ++r.tlm.attemptsUsed;
    if (d.kind == FaultResponseKind::kSafeAndCallHome) {
        giveUp(r, in.now, "call home", out, true);
    }
}

void FaultResponder::judgeWheel(std::size_t w, Response& r, const WheelReading& d, const ResponderInputs& in,
                                const ResponderLimits& limits, ResponderActions* out) {
    const FaultClass c = d.faultClass;
    switch (r.tlm.state) {
        case ResponseState::kIdle:
        case ResponseState::kRecovered:
            break;
        case ResponseState::kSettling:
        case ResponseState::kWaiting:
            if (d.healthy) {
                if (!in.interlockTripped) {
                    recovered(r, in.now, "drive healthy");
                }
                break;  // the interlock reset is asked for in step(), once every drive is healthy
            }
            if (d.kind != FaultResponseKind::kRecoverDrive) {
                if (!d.trouble) {
                    break;  // e.g. configuring after a reboot: wait for operational
                }
                if (d.kind == FaultResponseKind::kHoldUntilClear && in.now - r.tlm.sinceNs >= limits.maxWait[idx(c)]) {
                    if (r.tlm.attemptsUsed >= limits.attempts[idx(c)]) {
                        giveUp(r, in.now, "call home", out, true);
                    } else {
                        ++r.tlm.attemptsUsed;
                        enter(r, ResponseState::kWaiting, in.now);
                    }
                }
                break;
            }
            if (r.tlm.state == ResponseState::kSettling) {
                // The drive's own recovery first: a lost drive may come back by
                // itself; a faulted one is being reset by the CAN master until it
                // reports failed.
                const core::TimeNs settle = c == FaultClass::kDriveLost            ? limits.driveLostSettle
                                            : d.health == msg::DriveHealth::kFailed ? 0
                                                                                    : limits.maxWait[idx(c)];
                if (d.trouble && in.now - r.tlm.sinceNs >= settle) {
                    r.tlm.faultClass = c;  // lost may have turned into faulted while settling
                    driveAct(w, r, in, limits, out);
                }
                break;
            }
            if (in.now - r.tlm.sinceNs >= limits.maxWait[idx(r.tlm.faultClass)]) {
                r.tlm.faultClass = d.trouble ? c : r.tlm.faultClass;
                driveAct(w, r, in, limits, out);
            }
            break;
        case ResponseState::kGaveUp:
            if (d.healthy && !in.interlockTripped) {
                recovered(r, in.now, "drive healthy after giving up");
            }
            break;
    }
}

void FaultResponder::stepWheel(std::size_t w, const ResponderInputs& in, const ResponderLimits& limits,
                               ResponderActions* out) {
    Response& r = wheels_[w];
    const WheelReading d = readWheel(w, in, limits);
    const bool resting = r.tlm.state == ResponseState::kIdle || r.tlm.state == ResponseState::kRecovered;
    if (resting && d.trouble) {
        beginWheel(r, d, in, limits, out);
    } else if (r.tlm.state == ResponseState::kRecovered && in.now - r.clearSince >= limits.attemptMemory) {
        r.tlm.attemptsUsed = 0;
        enter(r, ResponseState::kIdle, in.now);
    }
    // A response begun above is judged in the same run: a drive already
    // failed gets its first try at once.
    judgeWheel(w, r, d, in, limits, out);
    const bool holding = (r.tlm.state == ResponseState::kSettling || r.tlm.state == ResponseState::kWaiting) &&
                         d.kind != FaultResponseKind::kEventOnly;
    if (holding) {
        out->holdReasons |= 1u << msg::hold::kDriveRecovery;
    }
}

void FaultResponder::stepFault(std::uint8_t id, FaultClass c, const ResponderInputs& in, const ResponderLimits& limits,
                               ResponderActions* out) {
    Response& r = faults_[id];
    const bool active = bit(in.activeFaults, id);
    const FaultResponseKind kind = effectiveKind(c, limits.response[idx(c)]);
    // A hold or a replan is a mission response: outside AUTONOMOUS there is no
    // mission to hold or replan, and a rover booting in SAFE before its first
    // fix must not call home.
    const bool missionOnly = kind == FaultResponseKind::kHoldUntilClear || kind == FaultResponseKind::kReplanFromPose;
    if (missionOnly && !in.autonomous) {
        if (r.tlm.state == ResponseState::kWaiting) {
            enter(r, ResponseState::kIdle, in.now);
        }
        return;
    }
    const auto row = static_cast<std::uint8_t>(id - msg::fault::kTaskStalled);
    auto restart = [&]() {
        if (core::isOk(out->taskRestarts.push_back(row))) {
            ++actions_;
        }
        r.tlm.lastAction = 2;
        events_.report(events::kTaskRestart, core::Severity::kWarning,
                       "fault protection: rate-group row %u stalled: restart, attempt %u of %u",
                       static_cast<unsigned>(row), static_cast<unsigned>(r.tlm.attemptsUsed),
                       static_cast<unsigned>(limits.attempts[idx(c)]));
    };
    auto replan = [&]() {
        if (core::isOk(out->replans.push_back(
                msg::ReplanRequestMsg{in.now, id, r.tlm.attemptsUsed, {}}))) {
            ++actions_;
        }
        r.tlm.lastAction = 3;
        events_.report(events::kReplanRequested, core::Severity::kWarning,
                       "fault protection: %s (fault %u): waypoint cancelled, replan from the pose asked, attempt %u of %u",
                       toString(c), static_cast<unsigned>(id), static_cast<unsigned>(r.tlm.attemptsUsed),
                       static_cast<unsigned>(limits.attempts[idx(c)]));
    };
    switch (r.tlm.state) {
        case ResponseState::kIdle:
        case ResponseState::kRecovered:
            if (active) {
                begin(r, c, id, ResponseState::kWaiting, limits, in.now);
                if (kind == FaultResponseKind::kEventOnly) {
                    break;  // evented by begin(); nothing to try, nothing to give up
                }
                if (r.tlm.attemptsUsed >= limits.attempts[idx(c)]) {
                    giveUp(r, in.now, "back too soon: call home", out, true);
                    break;
                }
                ++r.tlm.attemptsUsed;
                if (kind == FaultResponseKind::kSafeAndCallHome) {
                    giveUp(r, in.now, "call home", out, true);
                } else if (kind == FaultResponseKind::kRestartTask) {
                    restart();
                } else if (kind == FaultResponseKind::kReplanFromPose) {
                    replan();
                } else if (kind == FaultResponseKind::kHoldUntilClear) {
                    r.tlm.lastAction = 1;
                }
            } else if (r.tlm.state == ResponseState::kRecovered && in.now - r.clearSince >= limits.attemptMemory) {
                r.tlm.attemptsUsed = 0;
                enter(r, ResponseState::kIdle, in.now);
            }
            break;
        case ResponseState::kSettling:  // not used for per-fault responses
        case ResponseState::kWaiting:
            if (!active) {
                recovered(r, in.now, "cleared");
                break;
            }
            if (kind == FaultResponseKind::kEventOnly || in.now - r.tlm.sinceNs < limits.maxWait[idx(c)]) {
                break;
            }
            if (r.tlm.attemptsUsed >= limits.attempts[idx(c)]) {
                giveUp(r, in.now, "call home", out, true);
                break;
            }
            ++r.tlm.attemptsUsed;
            enter(r, ResponseState::kWaiting, in.now);
            if (kind == FaultResponseKind::kRestartTask) {
                restart();
            } else if (kind == FaultResponseKind::kReplanFromPose) {
                replan();
            }
            break;
        case ResponseState::kGaveUp:
            if (!active) {
                recovered(r, in.now, "cleared after giving up");
            }
            break;
    }
    if (r.tlm.state == ResponseState::kWaiting &&
        (kind == FaultResponseKind::kHoldUntilClear || kind == FaultResponseKind::kRestartTask)) {
        out->holdReasons |= 1u << holdBitFor(c);
    }
}

void FaultResponder::step(const ResponderInputs& in, const ResponderLimits& limits, ResponderActions* out) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        stepWheel(w, in, limits, out);
    }
    for (std::uint8_t id = 1; id < msg::fault::kCount; ++id) {
        FaultClass c{};
        if (classOf(id, &c) && c != FaultClass::kDriveLost) {
            stepFault(id, c, in, limits, out);
        }
    }
    // The interlock latches on any unhealthy drive; once every drive is
    // operational again it may be released, whoever brought them back.
    bool allHealthy = in.haveDrives;
    for (std::size_t w = 0; w < msg::kWheelCount && allHealthy; ++w) {
        allHealthy = healthyDrive(in.health[w]) &&
                     !bit(in.activeFaults, static_cast<std::uint32_t>(msg::fault::kDriveHeartbeatLost + w));
    }
    // A drive given up on stays out: its interlock stays latched for the
    // deliberative layer to decide (replan or call home), until it recovers.
    bool gaveUpOnADrive = false;
    for (const Response& w : wheels_) {
        gaveUpOnADrive = gaveUpOnADrive || w.tlm.state == ResponseState::kGaveUp;
    }
    if (in.interlockTripped && allHealthy && !gaveUpOnADrive) {
        askInterlockReset(in, out);
    } else if (!in.interlockTripped) {
        interlockAskedAt_ = -1;
        interlockAsks_ = 0;
    }
}

void FaultResponder::fillStatus(msg::FaultProtectionStatusMsg* status) const {
    status->activeCount = 0;
    auto add = [&](const Response& r) {
        if (r.tlm.state != ResponseState::kIdle && status->activeCount < msg::kResponseSlots) {
            status->responses[status->activeCount++] = r.tlm;
        }
    };
    for (const Response& r : wheels_) {
        add(r);
    }
    for (const Response& r : faults_) {
        add(r);
    }
    for (std::size_t i = status->activeCount; i < msg::kResponseSlots; ++i) {
        status->responses[i] = msg::ResponseTlm{};
    }
    status->responsesStarted = started_;
    status->recoveries = recoveries_;
    status->gaveUp = gaveUp_;
    status->actionsSent = actions_;
}

}  // namespace rse::fault_protection
