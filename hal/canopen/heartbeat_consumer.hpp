// CiA 301 heartbeat consumer: tracks each monitored node's NMT state, declares it
// lost when no heartbeat came within its timeout, and counts boot-ups so a device
// client notices a restart (it polls bootUps() and reconfigures). A node given a
// boot timeout that stays silent that long from the first check() (the master's
// first cycle) is declared lost as well (event 407): a device that never boots is
// as absent as one that stopped, and must not go unreported.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/static_vector.hpp"
#include "hal/can/can_frame.hpp"
#include "hal/canopen/canopen_ids.hpp"

namespace rse::hal::canopen {

constexpr std::size_t kMaxMonitoredNodes = 16;

struct NodeHealth {
    std::uint8_t nodeId = 0;
    core::TimeNs timeout = 0;
    core::TimeNs bootTimeout = 0;  // 0: a node never heard is not judged
    core::TimeNs watchedSince = -1;  // first check(); -1 before it
    NmtState state = NmtState::kUnknown;
    core::TimeNs lastSeen = 0;
    bool everSeen = false;
    bool lost = false;
    std::uint32_t heartbeats = 0;
    std::uint32_t bootUps = 0;
    std::uint32_t losses = 0;
};

class HeartbeatConsumer {
public:
    explicit HeartbeatConsumer(core::EventLog& events) : events_(events) {}

    // kNoCapacity beyond kMaxMonitoredNodes, kAlreadyExists, kInvalidArgument for
    // id 0/>127 or a timeout <= 0 or a negative boot timeout (0: none).
    core::Status monitor(std::uint8_t nodeId, core::TimeNs timeout, core::TimeNs bootTimeout = 0);
    // Frame at 0x700 + node; frames of unmonitored nodes are counted, not tracked.
    void onFrame(const CanFrame& frame, core::TimeNs now);
    // Declares nodes lost whose heartbeat is overdue. Once per cycle.
    void check(core::TimeNs now);

    const NodeHealth* node(std::uint8_t nodeId) const;
    std::uint32_t badFrames() const { return badFrames_; }
    std::uint32_t unmonitored() const { return unmonitored_; }

private:
    NodeHealth* find(std::uint8_t nodeId);

    core::EventLog& events_;
    core::StaticVector<NodeHealth, kMaxMonitoredNodes> nodes_;
    std::uint32_t badFrames_ = 0;
    std::uint32_t unmonitored_ = 0;
};

}  // namespace rse::hal::canopen
