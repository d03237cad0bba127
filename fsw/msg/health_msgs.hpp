// What the health monitor and the drive mode estimator tell the executive and
// the layers (fsw/estimator/): active faults, and each drive's mode belief.
#pragma once

#include <cstdint>

#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// Fault ids: bit `id` of FaultStatusMsg::activeMask. The list, the detection
// time bound of each and its events are in docs/estimator.md ("Faults").
namespace fault {
constexpr std::uint8_t kDriveHeartbeatLost = 1;   // + wheel 0..5      -> 1..6
constexpr std::uint8_t kDeviceHeartbeatLost = 7;  // + DeviceNode 0..3 -> 7..10
constexpr std::uint8_t kDriveOvercurrent = 11;    // + wheel 0..5      -> 11..16
constexpr std::uint8_t kBatteryLow = 17;
constexpr std::uint8_t kBusOvercurrent = 18;
constexpr std::uint8_t kPoseUncertain = 19;
constexpr std::uint8_t kTaskStalled = 20;         // + rate-group row 0..15 -> 20..35
constexpr std::uint8_t kTaskStalledCount = 16;
constexpr std::uint8_t kSensorStale = 36;         // + DeviceNode 0..3 -> 36..39: heartbeat on, data silent
constexpr std::uint8_t kDriveOvertemp = 40;       // + wheel 0..5      -> 40..45
constexpr std::uint8_t kOffMap = 46;              // the pose estimate lies outside the site (COARSE_MAP bounds)
constexpr std::uint8_t kCount = 47;               // ids 1..46; 0 is "no fault"
}  // namespace fault

struct FaultStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kFaultStatus;
    std::int64_t timeNs;
    std::uint64_t activeMask;     // bit id set: fault id active
    std::uint32_t raisedTotal;    // raise transitions since start
    std::uint32_t clearedTotal;   // clear transitions since start
    std::uint8_t lastFaultId;     // fault of the latest transition (0: none yet)
    std::uint8_t lastRaised;      // 1: that transition raised it, 0: cleared it
    std::uint8_t pad[6];
};

// Modes of a wheel drive as the mode estimator believes them (Livingstone style:
// unknown stands for every failure the model does not describe).
enum class DriveMode : std::uint8_t { kNominal = 0, kDegraded = 1, kFailed = 2, kUnknown = 3 };
constexpr std::size_t kDriveModeCount = 4;

struct DriveModeBelief {
    float probability[kDriveModeCount];  // indexed by DriveMode, sums to 1
    float powerFactor;                   // estimated current (power) draw relative to a nominal drive, 1 = nominal
    DriveMode declared;                  // latest mode whose probability reached the declare threshold
    std::uint8_t pad[3];
};

struct DriveModesMsg {
    static constexpr core::MsgId kMsgId = ids::kDriveModes;
    std::int64_t timeNs;
    DriveModeBelief drives[kWheelCount];
    std::uint32_t updates;  // belief updates since start (each 100 ms)
    std::uint8_t pad[4];
};

}  // namespace rse::msg
