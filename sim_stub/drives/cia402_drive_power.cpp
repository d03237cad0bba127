#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include <cmath>

#include "sim_stub/drives/cia402_drive_codes.hpp"

// The CiA 402 power state machine of the wheel drive emulator: controlwords,
// fault detection and reaction, the error register and the statusword
// (cia402_drive_emulator.hpp, "CiA 402 power state machine").

namespace rse::sim {

namespace {

using namespace drive_codes;

// Statusword bits.
constexpr std::uint16_t kSwVoltageEnabled = 0x0010;
constexpr std::uint16_t kSwWarning = 0x0080;
constexpr std::uint16_t kSwRemote = 0x0200;
constexpr std::uint16_t kSwTargetReached = 0x0400;
constexpr std::uint16_t kSwInternalLimit = 0x0800;
constexpr std::uint16_t kSwSpeedZero = 0x1000;  // profile velocity mode: speed = 0

constexpr std::uint16_t kCwFaultReset = 0x0080;

// The transitions a controlword commands from a state with the power stage
// under the master's control (CiA 402 transitions 2-12 and 16, numbered as
// there); the state itself when it commands none.
PowerState commandedState(PowerState state, std::uint16_t controlword) {
    const bool disableVoltage = (controlword & 0x82U) == 0x00U;
    const bool quickStop = (controlword & 0x86U) == 0x02U;
    const bool shutdown = (controlword & 0x87U) == 0x06U;
    const bool switchOn = (controlword & 0x8FU) == 0x07U;  // also "disable operation"
    const bool enableOperation = (controlword & 0x8FU) == 0x0FU;
    switch (state) {
        case PowerState::kSwitchOnDisabled:
            if (shutdown) {
                return PowerState::kReadyToSwitchOn;  // 2
            }
            break;
        case PowerState::kReadyToSwitchOn:
            if (switchOn) {
                return PowerState::kSwitchedOn;  // 3
            } else if (enableOperation) {
                return PowerState::kOperationEnabled;  // 3 + 4
            } else if (disableVoltage || quickStop) {
                return PowerState::kSwitchOnDisabled;  // 7
            }
            break;
        case PowerState::kSwitchedOn:
            if (enableOperation) {
                return PowerState::kOperationEnabled;  // 4
            } else if (shutdown) {
                return PowerState::kReadyToSwitchOn;  // 6
            } else if (disableVoltage || quickStop) {
                return PowerState::kSwitchOnDisabled;  // 10
            }
            break;
        case PowerState::kOperationEnabled:
            if (switchOn) {
                return PowerState::kSwitchedOn;  // 5
            } else if (shutdown) {
                return PowerState::kReadyToSwitchOn;  // 8
            } else if (disableVoltage) {
                return PowerState::kSwitchOnDisabled;  // 9
            } else if (quickStop) {
                return PowerState::kQuickStopActive;  // 11
            }
            break;
        case PowerState::kQuickStopActive:
            if (disableVoltage) {
                return PowerState::kSwitchOnDisabled;  // 12
            } else if (enableOperation) {
                return PowerState::kOperationEnabled;  // 16
            }
            break;
        default:
            break;
    }
    return state;
}

}  // namespace

void Cia402DriveEmulator::applyControlword(std::uint16_t controlword, core::TimeNs) {
    const bool resetEdge = (controlword_ & kCwFaultReset) == 0 && (controlword & kCwFaultReset) != 0;
    controlword_ = controlword;
    switch (power_) {
        case PowerState::kNotReadyToSwitchOn:
        case PowerState::kFaultReactionActive:
            return;
        case PowerState::kFault:
            if (!resetEdge) {
                return;
            }
            if (motorFailed_) {
                ++stats_.faultResetsRefused;  // the cause is still there
                return;
            }
            errors_ = static_cast<std::uint8_t>(errors_ & kErrPdoLength);
            overCurrentTiming_ = false;
            power_ = PowerState::kSwitchOnDisabled;
            ++stats_.faultResets;
            sendEmcy(emcy::kNoError);
            return;
        default:
            break;
    }
    power_ = commandedState(power_, controlword);
}

void Cia402DriveEmulator::detectFaults(core::TimeNs now) {
    if (motorFailed_ && (errors_ & kErrMotor) == 0) {
        raiseError(kErrMotor, emcy::kMotorFailed, now);
    }
    if (injectPending_) {
        injectPending_ = false;
        raiseError(kErrInjected, injectedCode_, now);
    }
    if (power_ == PowerState::kNotReadyToSwitchOn && now > bootedAt_) {
        power_ = PowerState::kSwitchOnDisabled;  // 1: self-test done
    }
    if (power_ == PowerState::kFaultReactionActive && now - faultAt_ >= config_.faultReactionTime) {
        power_ = PowerState::kFault;  // 14
    }
}

void Cia402DriveEmulator::raiseError(std::uint8_t kind, std::uint16_t code, core::TimeNs now) {
    if ((errors_ & kind) != 0 && (kind != kErrInjected || injectedCode_ == code)) {
        return;  // already active and reported
    }
    errors_ = static_cast<std::uint8_t>(errors_ | kind);
    if (kind != kErrPdoLength && power_ != PowerState::kFaultReactionActive && power_ != PowerState::kFault) {
        power_ = PowerState::kFaultReactionActive;  // 13
        faultAt_ = now;
        ++stats_.faults;
    }
    sendEmcy(code);
}

std::uint8_t Cia402DriveEmulator::errorRegister() const {
    std::uint8_t r = 0;
    if (errors_ != 0) {
        r |= 0x01;  // generic
    }
    if ((errors_ & kErrOverCurrent) != 0) {
        r |= 0x02;  // current
    }
    if ((errors_ & kErrInjected) != 0) {
        switch (injectedCode_ >> 12U) {
            case 0x2: r |= 0x02; break;  // current
            case 0x3: r |= 0x04; break;  // voltage
            case 0x4: r |= 0x08; break;  // temperature
            case 0x8: r |= 0x10; break;  // communication
            default: break;
        }
    }
    if ((errors_ & kErrPdoLength) != 0) {
        r |= 0x10;  // communication
    }
    return r;
}

std::uint16_t Cia402DriveEmulator::statusword() const {
    std::uint16_t sw = 0;
    switch (power_) {
        case PowerState::kNotReadyToSwitchOn: return 0x0000;
        case PowerState::kSwitchOnDisabled: sw = 0x0040; break;
        case PowerState::kReadyToSwitchOn: sw = 0x0021; break;
        case PowerState::kSwitchedOn: sw = 0x0023 | kSwVoltageEnabled; break;
        case PowerState::kOperationEnabled: sw = 0x0027 | kSwVoltageEnabled; break;
        case PowerState::kQuickStopActive: sw = 0x0007 | kSwVoltageEnabled; break;
        case PowerState::kFaultReactionActive: sw = 0x000F | kSwVoltageEnabled; break;
        case PowerState::kFault: sw = 0x0008; break;
    }
    sw |= kSwRemote;
    if (overCurrentTiming_) {
        sw |= kSwWarning;
    }
    const std::int32_t v = velocityActualMradS();
    const auto absDiff = [](std::int64_t a, std::int64_t b) { return a > b ? a - b : b - a; };
    if (power_ == PowerState::kOperationEnabled) {
        const std::int64_t target = std::llround(effectiveTargetRadS() * 1000.0);
        if (absDiff(v, target) <= config_.velocityWindowMradS) {
            sw |= kSwTargetReached;
        }
        if (mode_ == kProfileVelocityMode &&
            (targetVelocity_ > config_.speedLimitMradS || targetVelocity_ < -config_.speedLimitMradS)) {
            sw |= kSwInternalLimit;
        }
    }
    if (power_ == PowerState::kQuickStopActive && absDiff(v, 0) <= config_.velocityWindowMradS) {
        sw |= kSwTargetReached;
    }
    if ((power_ == PowerState::kOperationEnabled || power_ == PowerState::kQuickStopActive) &&
        absDiff(v, 0) <= config_.speedZeroThresholdMradS) {
        sw |= kSwSpeedZero;
    }
    return sw;
}

}  // namespace rse::sim
