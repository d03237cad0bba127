#include "hal/can/can_bus.hpp"

namespace rse::hal {

const char* toString(CanBusState state) {
    switch (state) {
        case CanBusState::kErrorActive: return "error-active";
        case CanBusState::kErrorWarning: return "error-warning";
        case CanBusState::kErrorPassive: return "error-passive";
        case CanBusState::kBusOff: return "bus-off";
        case CanBusState::kDown: return "down";
    }
    return "?";
}

}  // namespace rse::hal
