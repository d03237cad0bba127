// Linux SocketCAN (CAN_RAW) behind the CanBus interface.
//
// Non-blocking socket; error frames enabled so the controller's state (warning,
// passive, bus-off, restarted) is tracked and counted; kernel receive timestamps
// (SO_TIMESTAMPNS, mapped onto CLOCK_MONOTONIC); the kernel's own drop counter
// (SO_RXQ_OVFL) feeds rxOverruns. Bus-off recovery is the kernel's: configure the
// interface with `ip link set canX type can restart-ms 100`; while bus-off, send()
// refuses and the state returns to error-active on the controller's "restarted"
// report. All of this works on vcan too, which never reports bus errors.
#pragma once

#include <cstdint>

#include "hal/can/can_bus.hpp"

namespace rse::hal {

constexpr std::size_t kCanInterfaceNameSize = 16;  // IFNAMSIZ

class SocketCanBus final : public CanBus {
public:
    SocketCanBus() = default;
    ~SocketCanBus();
    SocketCanBus(const SocketCanBus&) = delete;
    SocketCanBus& operator=(const SocketCanBus&) = delete;

    // kUnavailable when the kernel has no CAN or the interface does not exist;
    // lastErrno() says which. kInvalidArgument for an empty or too long name.
    core::Status open(const char* interfaceName);
    void close();
    bool isOpen() const { return fd_ >= 0; }
    int lastErrno() const { return lastErrno_; }
    const char* interfaceName() const { return name_; }

    core::Status send(const CanFrame& frame) override;
    // Error frames are consumed here (state and counters), never returned.
    core::Status receive(CanFrame* out) override;
    core::Status setFilters(const CanFilter* filters, std::size_t count) override;
    CanBusState state() const override { return state_; }
    const CanBusStats& stats() const override { return stats_; }

private:
    void handleErrorFrame(std::uint32_t canId, const std::uint8_t* data, std::uint8_t dlc);

    int fd_ = -1;
    int lastErrno_ = 0;
    char name_[kCanInterfaceNameSize] = {};
    CanBusState state_ = CanBusState::kDown;
    CanBusStats stats_;
    std::uint32_t kernelDropsSeen_ = 0;
};

}  // namespace rse::hal
