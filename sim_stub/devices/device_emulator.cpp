#include "sim_stub/devices/device_emulator.hpp"

#include <cmath>

namespace rse::sim {

using hal::CanFrame;
using hal::canopen::NmtCommand;
using hal::canopen::NmtState;

std::size_t PeriodicSchedule::take(core::TimeNs now, std::size_t max, std::uint32_t* skipped) {
    std::size_t due = 0;
    while (now >= next_ && due < max) {
        next_ += period_;
        ++due;
    }
    if (now >= next_) {
        const core::TimeNs behind = (now - next_) / period_ + 1;
        next_ += behind * period_;
        if (skipped != nullptr) {
            *skipped += static_cast<std::uint32_t>(behind);
        }
    }
    return due;
}

void DeviceEmulator::crash() {
    crashed_ = true;
    state_ = NmtState::kUnknown;
}

void DeviceEmulator::restart() {
    crashed_ = false;
    bootPending_ = true;
    resetApplicationPending_ = true;
}

void DeviceEmulator::onFrame(const CanFrame& frame) {
    if (!poweredOn_ || crashed_) {
        return;
    }
    if (frame.id != hal::canopen::kNmt || frame.extended() || frame.remote() || frame.dlc != 2) {
        onDataFrame(frame);
        return;
    }
    const std::uint8_t target = frame.data[1];
    if (target != 0 && target != nodeId_) {
        return;
    }
    ++stats_.nmtCommands;
    switch (static_cast<NmtCommand>(frame.data[0])) {
        case NmtCommand::kStart:
            state_ = NmtState::kOperational;
            break;
        case NmtCommand::kStop:
            state_ = NmtState::kStopped;
            break;
        case NmtCommand::kEnterPreOperational:
            state_ = NmtState::kPreOperational;
            break;
        case NmtCommand::kResetNode:
            bootPending_ = true;
            resetApplicationPending_ = true;
            break;
        case NmtCommand::kResetCommunication:
            bootPending_ = true;
            break;
        default:
            break;  // unknown command: ignored, as a CANopen slave does
    }
}

void DeviceEmulator::step(core::TimeNs now) {
    poweredOn_ = true;
    if (pollsBus_) {
        CanFrame frame;
        for (std::size_t i = 0; i < kDeviceMaxRxPerStep && core::isOk(bus_.receive(&frame)); ++i) {
            onFrame(frame);
        }
    }
    if (crashed_) {
        return;
    }
    if (bootPending_) {
        boot(now);
    }
    produce(now);
    std::uint32_t skipped = 0;
    if (heartbeat_.take(now, 1, &skipped) > 0) {
        sendState(state_);
    }
}

void DeviceEmulator::boot(core::TimeNs now) {
    const bool resetApplication = resetApplicationPending_;
    bootPending_ = false;
    resetApplicationPending_ = false;
    sendState(NmtState::kBootUp);
    state_ = NmtState::kPreOperational;
    heartbeat_.start(now + kDeviceHeartbeatPeriodNs, kDeviceHeartbeatPeriodNs);
    onBoot(now, resetApplication);
}

bool DeviceEmulator::sendRaw(const CanFrame& frame) {
    if (core::isOk(bus_.send(frame))) {
        return true;
    }
    ++stats_.sendFailures;
    return false;
}

void DeviceEmulator::sendState(NmtState state) {
    CanFrame f;
    f.id = hal::canopen::kHeartbeat + nodeId_;
    f.dlc = 1;
    f.data[0] = static_cast<std::uint8_t>(state);
    if (sendRaw(f)) {
        if (state == NmtState::kBootUp) {
            ++stats_.bootUps;
        } else {
            ++stats_.heartbeats;
        }
    }
}

void DeviceEmulator::sendData(const CanFrame& frame) {
    if (dropout_ || state_ == NmtState::kStopped) {
        ++stats_.suppressed;
        return;
    }
    if (sendRaw(frame)) {
        ++stats_.dataFrames;
    }
}

std::int32_t saturateI32(double value) {
    const double r = std::nearbyint(value);
    if (!(r > -2147483648.0)) {
        return r < 0.0 ? INT32_MIN : 0;  // also NaN -> 0
    }
    if (r > 2147483647.0) {
        return INT32_MAX;
    }
    return static_cast<std::int32_t>(r);
}

std::int16_t saturateI16(double value) {
    const double r = std::nearbyint(value);
    if (!(r > -32768.0)) {
        return r < 0.0 ? INT16_MIN : 0;
    }
    if (r > 32767.0) {
        return INT16_MAX;
    }
    return static_cast<std::int16_t>(r);
}

std::uint16_t saturateU16(double value) {
    const double r = std::nearbyint(value);
    if (!(r > 0.0)) {
        return 0;
    }
    if (r > 65535.0) {
        return UINT16_MAX;
    }
    return static_cast<std::uint16_t>(r);
}

}  // namespace rse::sim
