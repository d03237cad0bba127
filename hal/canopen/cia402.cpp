#include "hal/canopen/cia402.hpp"

namespace rse::hal::cia402 {

const char* toString(PowerState state) {
    switch (state) {
        case PowerState::kNotReadyToSwitchOn: return "not-ready";
        case PowerState::kSwitchOnDisabled: return "switch-on-disabled";
        case PowerState::kReadyToSwitchOn: return "ready-to-switch-on";
        case PowerState::kSwitchedOn: return "switched-on";
        case PowerState::kOperationEnabled: return "operation-enabled";
        case PowerState::kQuickStopActive: return "quick-stop";
        case PowerState::kFaultReactionActive: return "fault-reaction";
        case PowerState::kFault: return "fault";
    }
    return "?";
}

PowerState decodeStatusword(std::uint16_t sw) {
    // Patterns from CiA 402 (docs/icd.md §1.4): three states use mask 0x4F, the rest 0x6F.
    switch (sw & 0x4FU) {
        case 0x00: return PowerState::kNotReadyToSwitchOn;
        case 0x40: return PowerState::kSwitchOnDisabled;
        case 0x0F: return PowerState::kFaultReactionActive;
        case 0x08: return PowerState::kFault;
        default: break;
    }
    switch (sw & 0x6FU) {
        case 0x21: return PowerState::kReadyToSwitchOn;
        case 0x23: return PowerState::kSwitchedOn;
        case 0x27: return PowerState::kOperationEnabled;
        case 0x07: return PowerState::kQuickStopActive;
        default: break;
    }
    return PowerState::kNotReadyToSwitchOn;  // no defined pattern: treat as not ready
}

std::uint16_t controlwordTowardsEnabled(PowerState state) {
    switch (state) {
        case PowerState::kSwitchOnDisabled: return controlword::kShutdown;
        case PowerState::kReadyToSwitchOn: return controlword::kSwitchOn;
        case PowerState::kSwitchedOn:
        case PowerState::kOperationEnabled: return controlword::kEnableOperation;
        case PowerState::kQuickStopActive:
        case PowerState::kNotReadyToSwitchOn:
        case PowerState::kFaultReactionActive:
        case PowerState::kFault: return controlword::kDisableVoltage;
    }
    return controlword::kDisableVoltage;
}

}  // namespace rse::hal::cia402
