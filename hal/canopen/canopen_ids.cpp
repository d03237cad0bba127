#include "hal/canopen/canopen_ids.hpp"

namespace rse::hal::canopen {

const char* toString(NmtState state) {
    switch (state) {
        case NmtState::kBootUp: return "boot-up";
        case NmtState::kStopped: return "stopped";
        case NmtState::kOperational: return "operational";
        case NmtState::kPreOperational: return "pre-operational";
        case NmtState::kUnknown: return "unknown";
    }
    return "?";
}

bool isValidNmtState(std::uint8_t byte) {
    return byte == 0x00 || byte == 0x04 || byte == 0x05 || byte == 0x7F;
}

}  // namespace rse::hal::canopen
