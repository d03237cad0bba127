// The one CAN bus interface the flight code sees. Two implementations:
// SocketCanBus (Linux CAN_RAW: real controllers, vcan) and MemoryCanEndpoint
// (an in-process bus for lockstep simulation and unit tests).
//
// Both are non-blocking: send() queues or refuses, receive() returns a frame or
// kEmpty. Drivers only count; CanLinkMonitor turns counter and state changes into
// events, so every backend is reported the same way.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "hal/can/can_frame.hpp"

namespace rse::hal {

// ISO 11898 fault confinement as the controller reports it, plus kDown for a
// link that is not open (or whose interface went away).
enum class CanBusState : std::uint8_t { kErrorActive = 0, kErrorWarning, kErrorPassive, kBusOff, kDown };
const char* toString(CanBusState state);

struct CanBusStats {
    std::uint32_t txFrames = 0;      // accepted for transmission
    std::uint32_t rxFrames = 0;      // handed to the caller
    std::uint32_t txInvalid = 0;     // refused: bad id or dlc
    std::uint32_t txUnavailable = 0; // refused: link down or bus-off
    std::uint32_t txBufferFull = 0;  // refused: transmit queue full
    std::uint32_t rxOverruns = 0;    // frames lost before the caller read them
    std::uint32_t rxFiltered = 0;    // frames dropped by the acceptance filters
    std::uint32_t errorFrames = 0;   // error reports from the controller
    std::uint32_t busOffCount = 0;   // times the controller went bus-off
};

constexpr std::size_t kCanMaxFilters = 16;

class CanBus {
public:
    // kOk, kInvalidArgument (frame), kUnavailable (down/bus-off), kFull (tx queue).
    virtual core::Status send(const CanFrame& frame) = 0;
    // kOk with a frame, kEmpty when none is waiting, kUnavailable when down.
    virtual core::Status receive(CanFrame* out) = 0;
    // No filters (count 0) accepts everything; more than kCanMaxFilters is kNoCapacity.
    virtual core::Status setFilters(const CanFilter* filters, std::size_t count) = 0;
    virtual CanBusState state() const = 0;
    virtual const CanBusStats& stats() const = 0;

protected:
    ~CanBus() = default;
};

}  // namespace rse::hal
