// Event ids raised by the RSE device clients in hal/devices (range 450-469).
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::hal::events {

constexpr core::EventId kDeviceBadFrame = 450;  // device frame with the wrong DLC or RTR
constexpr core::EventId kDeviceBadValue = 451;  // device frame with a field out of its range

}  // namespace rse::hal::events
