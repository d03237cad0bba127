// Wheel drives across the hal I/O boundary: status from the drives (every minor
// frame) and the wheel velocity command to them.
#pragma once

#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

constexpr std::size_t kWheelCount = 6;  // 0 FL, 1 ML, 2 RL, 3 FR, 4 MR, 5 RR (docs/icd.md §1.1)

// The wheel's short name in event texts: FL ML RL FR MR RR, "?" beyond.
inline const char* wheelName(std::size_t wheel) {
    static const char* const kNames[kWheelCount] = {"FL", "ML", "RL", "FR", "MR", "RR"};
    return wheel < kWheelCount ? kNames[wheel] : "?";
}

// Mirrors hal::DriveState; numeric values are part of the telemetry format.
enum class DriveHealth : std::uint8_t {
    kWaitingBootUp = 0,
    kConfiguring = 1,
    kStarting = 2,
    kEnabling = 3,
    kOperational = 4,
    kFaulted = 5,
    kFailed = 6,
    kLost = 7,
};

// h is one of DriveHealth's values: a message carrying any other is malformed
// (it reads as neither healthy nor faulted).
constexpr bool isKnownDriveHealth(DriveHealth h) {
    return static_cast<std::uint8_t>(h) <= static_cast<std::uint8_t>(DriveHealth::kLost);
}

struct WheelStatus {
    double targetRadS;       // target velocity sent to the drive this frame (after the interlock)
    double velocityRadS;     // wheel angular velocity actual
    double currentA;         // motor current actual
    std::int64_t feedbackTimeNs;  // when the drive last reported
    std::uint32_t feedbackCount;
    std::uint16_t statusword;
    std::uint16_t lastEmcyCode;
    DriveHealth health;
    std::uint8_t temperatureValid;  // 1: temperatureC was reported by the drive (TPDO2)
    std::uint8_t pad[2];
    float temperatureC;             // motor temperature, degC (0 until valid)
};

struct DriveStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kDriveStatus;
    std::int64_t timeNs;
    WheelStatus wheels[kWheelCount];
    std::uint8_t interlockTripped;  // 1: all drives held at zero (reflexive interlock)
    std::uint8_t pad[7];
};

struct WheelCommandMsg {
    static constexpr core::MsgId kMsgId = ids::kWheelCommand;
    std::int64_t timeNs;
    double velocityRadS[kWheelCount];  // target wheel angular velocities
};

}  // namespace rse::msg
