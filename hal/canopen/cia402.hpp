// CiA 402 power state machine, as seen by the master: decode the statusword,
// choose the controlword that moves the drive one step towards "operation
// enabled" (docs/icd.md §1.4).
#pragma once

#include <cstdint>

namespace rse::hal::cia402 {

enum class PowerState : std::uint8_t {
    kNotReadyToSwitchOn,
    kSwitchOnDisabled,
    kReadyToSwitchOn,
    kSwitchedOn,
    kOperationEnabled,
    kQuickStopActive,
    kFaultReactionActive,
    kFault,
};
const char* toString(PowerState state);

PowerState decodeStatusword(std::uint16_t statusword);

namespace controlword {
constexpr std::uint16_t kDisableVoltage = 0x0000;
constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOn = 0x0007;
constexpr std::uint16_t kEnableOperation = 0x000F;
constexpr std::uint16_t kFaultReset = 0x0080;  // acts on the rising edge of bit 7
}  // namespace controlword

// The controlword that takes a drive in `state` one step towards operation
// enabled. Fault states answer kDisableVoltage: resetting a fault is a decision
// (with retry limits) the caller makes, not this table.
std::uint16_t controlwordTowardsEnabled(PowerState state);

}  // namespace rse::hal::cia402
