// An in-process CAN bus: endpoints attached to one MemoryCanBus see every frame
// the others send (never their own, like CAN_RAW without RECV_OWN_MSGS), in send
// order, through per-endpoint acceptance filters and fixed-depth receive queues.
// Used for lockstep simulation (flight code and rse-sim in one process) and for
// unit tests.
//
// Fault injection for tests and scenarios: rules that drop, corrupt or delay the
// next N frames matching an id/mask, and per-endpoint bus-off. A babbling node is
// simply an endpoint that floods; receivers' overflow is counted (rxOverruns).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/ring_buffer.hpp"
#include "fsw/core/static_vector.hpp"
#include "hal/can/can_bus.hpp"

namespace rse::hal {

constexpr std::size_t kMemoryBusMaxEndpoints = 16;
constexpr std::size_t kMemoryBusRxDepth = 256;     // frames queued per endpoint
constexpr std::size_t kMemoryBusMaxDelayed = 128;  // frames held back by delay rules
constexpr std::size_t kMemoryBusMaxFaultRules = 8;

class MemoryCanBus;

class MemoryCanEndpoint final : public CanBus {
public:
    core::Status send(const CanFrame& frame) override;
    core::Status receive(CanFrame* out) override;
    core::Status setFilters(const CanFilter* filters, std::size_t count) override;
    CanBusState state() const override { return state_; }
    const CanBusStats& stats() const override { return stats_; }
    const char* name() const { return name_; }

private:
    friend class MemoryCanBus;
    bool accepts(const CanFrame& frame) const;
    void deliver(const CanFrame& frame);

    MemoryCanBus* hub_ = nullptr;
    const char* name_ = "";
    CanBusState state_ = CanBusState::kDown;
    core::StaticVector<CanFilter, kCanMaxFilters> filters_;
    core::RingBuffer<CanFrame, kMemoryBusRxDepth> rx_;
    CanBusStats stats_;
};

enum class CanFaultKind : std::uint8_t { kDrop, kCorrupt, kDelay };

struct CanFaultRule {
    CanFaultKind kind = CanFaultKind::kDrop;
    std::uint32_t id = 0;          // frames with (frame.id & mask) == (id & mask)
    std::uint32_t mask = 0;        // 0 matches every frame
    std::uint32_t count = 1;       // frames it applies to; 0 = until cleared
    core::TimeNs delay = 0;        // kDelay: how long the frame is held
    std::uint8_t corruptByte = 0;  // kCorrupt: data byte index (mod dlc) ...
    std::uint8_t corruptXor = 0xFF;  // ... XORed with this
};

struct MemoryBusStats {
    std::uint32_t framesCarried = 0;   // sends that reached the wire
    std::uint32_t faultDropped = 0;
    std::uint32_t faultCorrupted = 0;
    std::uint32_t faultDelayed = 0;
    std::uint32_t delayOverflow = 0;   // delayed frames lost: hold queue full
};

class MemoryCanBus {
public:
    explicit MemoryCanBus(const core::Clock& clock) : clock_(clock) {}

    // Attaches another endpoint, error-active; nullptr when kMemoryBusMaxEndpoints are attached.
    MemoryCanEndpoint* attach(const char* name);

    core::Status addFault(const CanFaultRule& rule);  // kFull beyond the rule limit
    void clearFaults() { faults_.clear(); }
    // Bus-off makes the endpoint refuse to send and stop receiving until restored.
    void setBusOff(MemoryCanEndpoint* endpoint, bool busOff);

    const MemoryBusStats& stats() const { return stats_; }

private:
    friend class MemoryCanEndpoint;
    struct HeldFrame {
        CanFrame frame;
        core::TimeNs releaseAt = 0;
        const MemoryCanEndpoint* sender = nullptr;
    };

    void transmit(const MemoryCanEndpoint* sender, const CanFrame& frame);
    void broadcast(const MemoryCanEndpoint* sender, const CanFrame& frame);
    void releaseDueFrames();
    CanFaultRule* matchFault(const CanFrame& frame);

    const core::Clock& clock_;
    MemoryCanEndpoint endpoints_[kMemoryBusMaxEndpoints];
    std::size_t endpointCount_ = 0;
    core::StaticVector<CanFaultRule, kMemoryBusMaxFaultRules> faults_;
    core::StaticVector<HeldFrame, kMemoryBusMaxDelayed> held_;
    MemoryBusStats stats_;
};

}  // namespace rse::hal
