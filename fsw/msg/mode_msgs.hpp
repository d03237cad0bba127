// Rover mode, software e-stop and manual driving across the bus.
#pragma once

#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// ModeMsg::mode values (cmdtlm::Mode mirrors them; layers below cmdtlm use these).
namespace mode {
constexpr std::uint8_t kSafe = 0;
constexpr std::uint8_t kStandby = 1;
constexpr std::uint8_t kAutonomous = 2;
constexpr std::uint8_t kManual = 3;
constexpr std::uint8_t kCount = 4;  // a value from here up is no mode
}  // namespace mode

// Published on every change of mode or e-stop, and once at start-up.
struct ModeMsg {
    static constexpr core::MsgId kMsgId = ids::kMode;
    std::int64_t timeNs;
    std::uint8_t mode;    // cmdtlm::Mode: 0 SAFE, 1 STANDBY, 2 AUTONOMOUS, 3 MANUAL
    std::uint8_t estop;   // 1: every drive held at zero until ESTOP_CLEAR
    std::uint8_t pad[6];
};

// RESET_INTERLOCK from ground: release the drive interlock if every drive is healthy.
struct InterlockResetMsg {
    static constexpr core::MsgId kMsgId = ids::kInterlockReset;
    std::int64_t timeNs;
};

// A manual DRIVE command, already range-checked against the dictionary.
struct ManualDriveMsg {
    static constexpr core::MsgId kMsgId = ids::kManualDrive;
    std::int64_t timeNs;
    double speedMS;       // body forward speed
    double turnRateRadS;  // body turn rate, counter-clockwise positive
    double durationS;
};

}  // namespace rse::msg
