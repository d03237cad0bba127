#include "hal/devices/wheel_drive.hpp"

#include "hal/canopen/canopen_events.hpp"
#include "hal/canopen/le_codec.hpp"

namespace rse::hal {

using canopen::NmtCommand;
using canopen::NmtState;
using canopen::SdoResult;
using core::Severity;

namespace {

// The start-up checks and settings of docs/icd.md §1.4, in order.
struct ConfigStep {
    bool write;
    std::uint16_t index;
    std::uint8_t subIndex;
    std::uint32_t value;  // written, or expected (under mask) when read
    std::uint8_t size;    // bytes written
    std::uint32_t mask;   // bits compared when read
    const char* what;
};

constexpr ConfigStep kConfigSteps[] = {
    {false, 0x1000, 0, 0x0192, 0, 0xFFFF, "device type is CiA 402"},
    {true, 0x1017, 0, 100, 2, 0, "heartbeat producer 100 ms"},
    {true, 0x6060, 0, 3, 1, 0, "profile velocity mode"},
    {false, 0x6061, 0, 3, 0, 0xFF, "mode display is profile velocity"},
    {false, 0x1600, 0, 2, 0, 0xFF, "RPDO1 maps 2 objects"},
    {false, 0x1600, 1, 0x60400010, 0, 0xFFFFFFFF, "RPDO1 entry 1 is controlword"},
    {false, 0x1600, 2, 0x60FF0020, 0, 0xFFFFFFFF, "RPDO1 entry 2 is target velocity"},
    {false, 0x1A00, 0, 3, 0, 0xFF, "TPDO1 maps 3 objects"},
    {false, 0x1A00, 1, 0x60410010, 0, 0xFFFFFFFF, "TPDO1 entry 1 is statusword"},
    {false, 0x1A00, 2, 0x606C0020, 0, 0xFFFFFFFF, "TPDO1 entry 2 is velocity actual"},
    {false, 0x1A00, 3, 0x60780010, 0, 0xFFFFFFFF, "TPDO1 entry 3 is current actual"},
    {false, 0x1800, 2, 1, 0, 0xFF, "TPDO1 is synchronous"},
};
constexpr std::uint32_t kConfigStepCount = sizeof kConfigSteps / sizeof kConfigSteps[0];

}  // namespace

const char* toString(DriveState state) {
    switch (state) {
        case DriveState::kWaitingBootUp: return "waiting-boot-up";
        case DriveState::kConfiguring: return "configuring";
        case DriveState::kStarting: return "starting";
        case DriveState::kEnabling: return "enabling";
        case DriveState::kOperational: return "operational";
        case DriveState::kFaulted: return "faulted";
        case DriveState::kFailed: return "failed";
        case DriveState::kLost: return "lost";
    }
    return "?";
}

WheelDrive::WheelDrive(CanBus& bus, core::EventLog& events, const canopen::HeartbeatConsumer& heartbeats,
                       std::uint8_t nodeId, const char* name)
    : bus_(bus), events_(events), heartbeats_(heartbeats), nodeId_(nodeId), name_(name),
      sdo_(bus, events, nodeId) {}

core::Status WheelDrive::configure(std::uint8_t nodeId, const DriveConfig& config) {
    if (nodeId == 0 || nodeId > canopen::kMaxNodeId || config.sdoTimeout <= 0 || config.faultResetWait <= 0) {
        return core::Status::kInvalidArgument;
    }
    nodeId_ = nodeId;
    config_ = config;
    sdo_.configure(nodeId, config.sdoTimeout);
    return core::Status::kOk;
}

core::Status WheelDrive::requestFaultReset(core::TimeNs now) {
    if (state_ != DriveState::kFaulted && state_ != DriveState::kFailed) {
        return core::Status::kUnavailable;
    }
    ++stats_.resetRequests;
    events_.report(events::kDriveResetRequested, Severity::kInfo,
                   "drive %s (node %u): fault reset requested (was %s): %u more resets", name_,
                   static_cast<unsigned>(nodeId_), toString(state_), static_cast<unsigned>(config_.faultResets));
    enterFaulted(now);
    return core::Status::kOk;
}

void WheelDrive::enterFaulted(core::TimeNs now) {
    // Only an NMT-operational node acts on RPDO1; any other state (boot-up just
    // seen, configuring, starting, stopped, or a configuration that failed) gets
    // its reset by SDO.
    const canopen::NodeHealth* health = heartbeats_.node(nodeId_);
    const bool operational = health != nullptr && health->state == NmtState::kOperational &&
                             (state_ == DriveState::kEnabling || state_ == DriveState::kOperational ||
                              state_ == DriveState::kFaulted || state_ == DriveState::kFailed);
    enter(DriveState::kFaulted, now);
    resetBySdo_ = !operational;
}

void WheelDrive::enter(DriveState next, core::TimeNs now) {
    state_ = next;
    enteredAt_ = now;
    if (next == DriveState::kConfiguring) {
        configStep_ = 0;
        stepAttempts_ = 0;
        stepRequested_ = false;
        ++stats_.configAttempts;
        sdo_.clear();
    }
    if (next == DriveState::kFaulted) {
        resetsTried_ = 0;
        resetEdge_ = false;
        sdoReset_ = SdoReset::kIdle;
    }
}

void WheelDrive::fault(const char* why, std::uint16_t code, core::TimeNs now) {
    if (state_ == DriveState::kFaulted || state_ == DriveState::kFailed) {
        return;
    }
    ++stats_.faults;
    events_.report(events::kDriveFault, Severity::kError, "drive %s (node %u): fault, %s, code 0x%04X (was %s)", name_,
                   static_cast<unsigned>(nodeId_), why, static_cast<unsigned>(code), toString(state_));
    enterFaulted(now);
}

void WheelDrive::onFrame(const CanFrame& frame, core::TimeNs now) {
    const std::uint32_t function = canopen::functionOf(frame.id);
    if (function == canopen::kSdoResponse) {
        sdo_.onFrame(frame, now);
        return;
    }
    if (function == canopen::kEmcy) {
        if (frame.dlc != 8) {
            ++stats_.badPdo;
            return;
        }
        ++stats_.emcyCount;
        lastEmcyCode_ = le::getU16(&frame.data[0]);
        errorRegister_ = frame.data[2];
        events_.report(events::kEmcyReceived, lastEmcyCode_ == 0 ? Severity::kInfo : Severity::kError,
                       "drive %s (node %u): EMCY 0x%04X, error register 0x%02X", name_,
                       static_cast<unsigned>(nodeId_), static_cast<unsigned>(lastEmcyCode_),
                       static_cast<unsigned>(errorRegister_));
        // 0x8xxx codes report communication trouble (e.g. 0x8210, a PDO of the
        // wrong length) that the drive survives: a warning, not a fault. Any
        // other non-zero code faults the drive at once, a frame before its
        // statusword would show it.
        if (lastEmcyCode_ != 0 && (lastEmcyCode_ & 0xF000) != 0x8000) {
            fault("EMCY", lastEmcyCode_, now);
        }
        return;
    }
    if (function == canopen::kTpdo2) {
        if (frame.dlc != 2) {
            ++stats_.badPdo;
            if (core::isReportableOccurrence(stats_.badPdo)) {
                events_.report(events::kBadPdo, Severity::kWarning,
                               "drive %s (node %u): TPDO2 with dlc %u, expected 2 (%u so far)", name_,
                               static_cast<unsigned>(nodeId_), static_cast<unsigned>(frame.dlc),
                               static_cast<unsigned>(stats_.badPdo));
            }
            return;
        }
        feedback_.temperatureDeciC = le::getI16(&frame.data[0]);
        feedback_.temperatureTime = now;
        ++feedback_.temperatureCount;
        return;
    }
    if (function == canopen::kTpdo1) {
        if (frame.dlc != 8) {
            ++stats_.badPdo;
            if (core::isReportableOccurrence(stats_.badPdo)) {
                events_.report(events::kBadPdo, Severity::kWarning,
                               "drive %s (node %u): TPDO1 with dlc %u, expected 8 (%u so far)", name_,
                               static_cast<unsigned>(nodeId_), static_cast<unsigned>(frame.dlc),
                               static_cast<unsigned>(stats_.badPdo));
            }
            return;
        }
        feedback_.statusword = le::getU16(&frame.data[0]);
        feedback_.velocityMradS = le::getI32(&frame.data[2]);
        feedback_.currentMa = le::getI16(&frame.data[6]);
        feedback_.power = cia402::decodeStatusword(feedback_.statusword);
        feedback_.time = now;
        ++feedback_.count;
        const bool faultState = feedback_.power == cia402::PowerState::kFault ||
                                feedback_.power == cia402::PowerState::kFaultReactionActive;
        if (faultState && (state_ == DriveState::kEnabling || state_ == DriveState::kOperational)) {
            fault("statusword reports fault", lastEmcyCode_, now);
        }
    }
}

// Returns false when the drive is (or just became) lost and step() should stop.
bool WheelDrive::checkHeartbeat(core::TimeNs now) {
    const canopen::NodeHealth* health = heartbeats_.node(nodeId_);
    if (health == nullptr) {
        return false;
    }
    if (health->bootUps != seenBootUps_) {
        seenBootUps_ = health->bootUps;
        if (state_ == DriveState::kFaulted && enteredAt_ >= health->lastSeen) {
            // The EMCY came with (or after) the boot-up: the new boot's fault.
            // Configuring would forget it; clear it first (by SDO: pre-operational).
            enter(DriveState::kFaulted, now);
            resetBySdo_ = true;
            return true;
        }
        // Booted (first time, or restarted under us): configure from scratch.
        enter(DriveState::kConfiguring, now);
        return true;
    }
    // Waiting for boot-up included: the consumer's boot timeout declares a node
    // that never booted lost, and the drive must say so too.
    if (health->lost && state_ != DriveState::kLost) {
        ++stats_.losses;
        events_.report(events::kDriveLost, Severity::kError, "drive %s (node %u): lost (was %s)", name_,
                       static_cast<unsigned>(nodeId_), toString(state_));
        // No PDOs go to a lost node, so one that is alive but unheard would
        // keep turning at its last target while every other wheel stops:
        // send it to pre-operational, where a CiA 402 drive aborts the
        // connection (0x6007) and disables its output. Heard again, it is
        // configured and started afresh.
        sendNmt(NmtCommand::kEnterPreOperational);
        enter(DriveState::kLost, now);
        return false;
    }
    if (state_ == DriveState::kLost) {
        if (health->lost) {
            return false;
        }
        enter(DriveState::kConfiguring, now);  // heard again without a reboot: verify everything
    }
    if (state_ == DriveState::kWaitingBootUp && health->everSeen && !health->lost) {
        enter(DriveState::kConfiguring, now);  // already running (no boot-up seen): configure
    }
    return true;
}

void WheelDrive::sendNmt(NmtCommand command) {
    CanFrame f;
    f.id = canopen::kNmt;
    f.dlc = 2;
    f.data[0] = static_cast<std::uint8_t>(command);
    f.data[1] = nodeId_;
    (void)bus_.send(f);  // refusals are counted by the bus and evented by its link monitor
}

void WheelDrive::stepConfiguring(core::TimeNs now) {
    if (configStep_ >= kConfigStepCount) {
        events_.report(events::kDriveConfigured, Severity::kInfo, "drive %s (node %u): configured",
                       name_, static_cast<unsigned>(nodeId_));
        sendNmt(NmtCommand::kStart);  // checked by waiting for the operational heartbeat
        enter(DriveState::kStarting, now);
        return;
    }
    const ConfigStep& step = kConfigSteps[configStep_];
    if (!stepRequested_) {
        const core::Status s = step.write ? sdo_.download(step.index, step.subIndex, step.value, step.size, now)
                                          : sdo_.upload(step.index, step.subIndex, now);
        stepRequested_ = core::isOk(s);
        return;
    }
    const SdoResult r = sdo_.result();
    if (r == SdoResult::kInProgress) {
        return;
    }
    const std::uint32_t value = sdo_.value();
    const std::uint32_t abortCode = sdo_.abortCode();
    const bool ok = r == SdoResult::kDone && (step.write || (value & step.mask) == (step.value & step.mask));
    sdo_.clear();
    stepRequested_ = false;
    if (ok) {
        ++configStep_;
        stepAttempts_ = 0;
        return;
    }
    if (stepAttempts_ < config_.sdoRetries) {
        ++stepAttempts_;
        return;  // try the same step again next cycle
    }
    ++stats_.configFailures;
    // Index and sub-index name the step (docs/icd.md §1.4); the text must keep
    // the abort code whole within kEventTextSize, so no step description here.
    const unsigned tries = static_cast<unsigned>(stepAttempts_ + 1);
    if (r == SdoResult::kDone) {
        events_.report(events::kDriveConfigFailed, Severity::kError,
                       "drive %s (node %u): config 0x%04X:%u failed (%u tries): read 0x%08X", name_,
                       static_cast<unsigned>(nodeId_), static_cast<unsigned>(step.index),
                       static_cast<unsigned>(step.subIndex), tries, static_cast<unsigned>(value));
    } else if (r == SdoResult::kAborted) {
        events_.report(events::kDriveConfigFailed, Severity::kError,
                       "drive %s (node %u): config 0x%04X:%u failed (%u tries): abort code 0x%08X", name_,
                       static_cast<unsigned>(nodeId_), static_cast<unsigned>(step.index),
                       static_cast<unsigned>(step.subIndex), tries, static_cast<unsigned>(abortCode));
    } else {
        events_.report(events::kDriveConfigFailed, Severity::kError,
                       "drive %s (node %u): config 0x%04X:%u failed (%u tries): %s", name_,
                       static_cast<unsigned>(nodeId_), static_cast<unsigned>(step.index),
                       static_cast<unsigned>(step.subIndex), tries, canopen::toString(r));
    }
    enter(DriveState::kFailed, now);
}

void WheelDrive::declareFailed(core::TimeNs now) {
    events_.report(events::kDriveFailed, Severity::kCritical,
                   "drive %s (node %u): still faulted after %u resets (EMCY 0x%04X): out of service", name_,
                   static_cast<unsigned>(nodeId_), static_cast<unsigned>(resetsTried_),
                   static_cast<unsigned>(lastEmcyCode_));
    enter(DriveState::kFailed, now);
}

void WheelDrive::stepFaulted(core::TimeNs now) {
    if (resetBySdo_) {
        stepFaultedBySdo(now);
        return;
    }
    const bool cleared = feedback_.time > enteredAt_ && feedback_.power != cia402::PowerState::kFault &&
                         feedback_.power != cia402::PowerState::kFaultReactionActive;
    if (resetsTried_ > 0 && cleared) {
        events_.report(events::kDriveFaultCleared, Severity::kInfo, "drive %s (node %u): fault cleared after %u resets",
                       name_, static_cast<unsigned>(nodeId_), static_cast<unsigned>(resetsTried_));
        enter(DriveState::kEnabling, now);
        return;
    }
    if (now - enteredAt_ < static_cast<core::TimeNs>(resetsTried_) * config_.faultResetWait) {
        return;  // give the last reset its time
    }
    if (resetsTried_ >= config_.faultResets) {
        declareFailed(now);
        return;
    }
    ++resetsTried_;
    ++stats_.faultResets;
    resetEdge_ = true;  // sendCyclic: 0x0000 this cycle, 0x0080 the next
}

void WheelDrive::stepFaultedBySdo(core::TimeNs now) {
    const SdoResult r = sdo_.result();
    if (r == SdoResult::kInProgress) {
        return;  // ours, or a configuration transfer the fault interrupted
    }
    const std::uint32_t value = sdo_.value();
    switch (sdoReset_) {
        case SdoReset::kIdle:
            if (resetsTried_ >= config_.faultResets) {
                declareFailed(now);
                return;
            }
            sdo_.clear();
            ++resetsTried_;
            ++stats_.faultResets;
            ++stats_.sdoFaultResets;
            if (core::isOk(sdo_.download(0x6040, 0, cia402::controlword::kDisableVoltage, 2, now))) {
                sdoReset_ = SdoReset::kBitLow;  // bit 7 low first, so the next write is a rising edge
            }
            return;  // a write the bus refused used up this attempt; the next one comes next cycle
        case SdoReset::kBitLow:
            sdo_.clear();
            if (r == SdoResult::kDone &&
                core::isOk(sdo_.download(0x6040, 0, cia402::controlword::kFaultReset, 2, now))) {
                sdoReset_ = SdoReset::kBitHigh;
            } else {
                sdoReset_ = SdoReset::kIdle;
            }
            return;
        case SdoReset::kBitHigh:
            sdo_.clear();
            settleUntil_ = now + config_.faultResetWait;
            sdoReset_ = r == SdoResult::kDone ? SdoReset::kSettle : SdoReset::kIdle;
            return;
        case SdoReset::kSettle:
            if (now < settleUntil_) {
                return;
            }
            sdo_.clear();
            sdoReset_ = core::isOk(sdo_.upload(0x6041, 0, now)) ? SdoReset::kReadStatus : SdoReset::kIdle;
            return;
        case SdoReset::kReadStatus: {
            sdo_.clear();
            sdoReset_ = SdoReset::kIdle;
            const cia402::PowerState power = cia402::decodeStatusword(static_cast<std::uint16_t>(value));
            if (r == SdoResult::kDone && power != cia402::PowerState::kFault &&
                power != cia402::PowerState::kFaultReactionActive) {
                events_.report(events::kDriveFaultCleared, Severity::kInfo,
                               "drive %s (node %u): fault cleared by SDO after %u resets: configuring again", name_,
                               static_cast<unsigned>(nodeId_), static_cast<unsigned>(resetsTried_));
                enter(DriveState::kConfiguring, now);
            }
            return;
        }
    }
}

void WheelDrive::step(core::TimeNs now) {
    sdo_.poll(now);
    if (!checkHeartbeat(now)) {
        return;
    }
    switch (state_) {
        case DriveState::kWaitingBootUp:
        case DriveState::kFailed:
        case DriveState::kLost:
            return;
        case DriveState::kConfiguring:
            stepConfiguring(now);
            return;
        case DriveState::kStarting: {
            const canopen::NodeHealth* health = heartbeats_.node(nodeId_);
            if (health != nullptr && health->state == NmtState::kOperational) {
                enter(DriveState::kEnabling, now);
            } else if (now - enteredAt_ > kStartTimeout) {
                enter(DriveState::kConfiguring, now);  // NMT start lost or refused: again
            }
            return;
        }
        case DriveState::kEnabling:
            if (feedback_.power == cia402::PowerState::kOperationEnabled && feedback_.time > enteredAt_) {
                events_.report(events::kDriveEnabled, Severity::kInfo, "drive %s (node %u): operation enabled",
                               name_, static_cast<unsigned>(nodeId_));
                enter(DriveState::kOperational, now);
            } else if (now - enteredAt_ > kEnableTimeout) {
                fault("did not reach operation enabled", 0, now);
            }
            return;
        case DriveState::kOperational:
            return;
        case DriveState::kFaulted:
            stepFaulted(now);
            return;
    }
}

void WheelDrive::sendCyclic(core::TimeNs) {
    std::int32_t velocity = 0;
    switch (state_) {
        case DriveState::kEnabling:
            controlword_ = cia402::controlwordTowardsEnabled(feedback_.power);
            break;
        case DriveState::kOperational:
            controlword_ = cia402::controlword::kEnableOperation;
            velocity = target_;
            break;
        case DriveState::kFaulted:
            if (resetEdge_ && controlword_ != cia402::controlword::kDisableVoltage) {
                controlword_ = cia402::controlword::kDisableVoltage;  // bit 7 low first
            } else if (resetEdge_) {
                controlword_ = cia402::controlword::kFaultReset;      // then the rising edge
                resetEdge_ = false;
            } else {
                controlword_ = cia402::controlword::kDisableVoltage;
            }
            break;
        case DriveState::kFailed:
            controlword_ = cia402::controlword::kDisableVoltage;
            break;
        case DriveState::kWaitingBootUp:
        case DriveState::kConfiguring:
        case DriveState::kStarting:
        case DriveState::kLost:
            return;  // no PDOs before NMT start, none to a lost node
    }
    CanFrame f;
    f.id = canopen::kRpdo1 + nodeId_;
    f.dlc = 6;
    le::putU16(&f.data[0], controlword_);
    le::putI32(&f.data[2], velocity);
    (void)bus_.send(f);  // refusals are counted by the bus and evented by its link monitor
}

}  // namespace rse::hal
