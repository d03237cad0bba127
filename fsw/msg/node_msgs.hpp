// CAN node liveness across the hal I/O boundary: what the heartbeat consumer
// knows of every monitored node, for the health monitor.
#pragma once

#include <cstdint>

#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// Entry order is fixed: the six drives in wheel order (0 FL .. 5 RR), then the
// devices in this order.
enum class DeviceNode : std::uint8_t { kImu = 0, kPower = 1, kHazard = 2, kPositionFix = 3 };
constexpr std::size_t kDeviceNodeCount = 4;
constexpr std::size_t kMonitoredNodeCount = kWheelCount + kDeviceNodeCount;

struct NodeLiveness {
    std::int64_t lastSeenNs;  // when its last heartbeat came (0: never)
    std::uint32_t losses;     // times declared lost since start
    std::uint8_t nodeId;
    std::uint8_t nmtState;    // as in its last heartbeat (0x7F pre-op, 0x05 operational, 0x04 stopped)
    std::uint8_t lost;        // 1: heartbeat overdue (hal/canopen/heartbeat_consumer.hpp)
    std::uint8_t everSeen;
};

struct NodeStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kNodeStatus;
    std::int64_t timeNs;
    std::int64_t heartbeatTimeoutNs;  // silence after which a node counts as lost
    NodeLiveness nodes[kMonitoredNodeCount];
};

}  // namespace rse::msg
