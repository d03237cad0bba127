#include "hal/canopen/heartbeat_consumer.hpp"

#include "hal/canopen/canopen_events.hpp"

namespace rse::hal::canopen {

using core::Severity;
using core::Status;

Status HeartbeatConsumer::monitor(std::uint8_t nodeId, core::TimeNs timeout, core::TimeNs bootTimeout) {
    if (nodeId == 0 || nodeId > kMaxNodeId || timeout <= 0 || bootTimeout < 0) {
        return Status::kInvalidArgument;
    }
    if (find(nodeId) != nullptr) {
        return Status::kAlreadyExists;
    }
    NodeHealth n;
    n.nodeId = nodeId;
    n.timeout = timeout;
    n.bootTimeout = bootTimeout;
    return nodes_.push_back(n) == Status::kOk ? Status::kOk : Status::kNoCapacity;
}

NodeHealth* HeartbeatConsumer::find(std::uint8_t nodeId) {
    for (NodeHealth& n : nodes_) {
        if (n.nodeId == nodeId) {
            return &n;
        }
    }
    return nullptr;
}

const NodeHealth* HeartbeatConsumer::node(std::uint8_t nodeId) const {
    for (const NodeHealth& n : nodes_) {
        if (n.nodeId == nodeId) {
            return &n;
        }
    }
    return nullptr;
}

void HeartbeatConsumer::onFrame(const CanFrame& frame, core::TimeNs now) {
    const std::uint8_t id = nodeOf(frame.id);
    if (frame.dlc != 1 || frame.remote() || !isValidNmtState(frame.data[0])) {
        ++badFrames_;
        if (core::isReportableOccurrence(badFrames_)) {
            events_.report(events::kBadHeartbeat, Severity::kWarning,
                           "canopen: bad heartbeat from node %u (dlc %u, byte 0x%02X), %u so far",
                           static_cast<unsigned>(id), static_cast<unsigned>(frame.dlc),
                           static_cast<unsigned>(frame.data[0]), static_cast<unsigned>(badFrames_));
        }
        return;
    }
    NodeHealth* n = find(id);
    if (n == nullptr) {
        ++unmonitored_;
        return;
    }
    const auto state = static_cast<NmtState>(frame.data[0]);
    ++n->heartbeats;
    n->lastSeen = now;
    n->everSeen = true;
    if (n->lost) {
        n->lost = false;
        events_.report(events::kNodeRecovered, Severity::kInfo, "canopen: node %u heard again (%s)",
                       static_cast<unsigned>(id), toString(state));
    }
    if (state == NmtState::kBootUp) {
        ++n->bootUps;
        events_.report(events::kNodeBootUp, n->bootUps > 1 ? Severity::kWarning : Severity::kInfo,
                       "canopen: node %u boot-up (%u)", static_cast<unsigned>(id),
                       static_cast<unsigned>(n->bootUps));
        n->state = NmtState::kPreOperational;  // CiA 301: boot-up leads to pre-operational
        return;
    }
    if (state != n->state) {
        events_.report(events::kNodeStateChanged, Severity::kInfo, "canopen: node %u %s -> %s",
                       static_cast<unsigned>(id), toString(n->state), toString(state));
        n->state = state;
    }
}

void HeartbeatConsumer::check(core::TimeNs now) {
    for (NodeHealth& n : nodes_) {
        if (n.watchedSince < 0) {
            n.watchedSince = now;
        }
        if (!n.everSeen && !n.lost && n.bootTimeout > 0 && now - n.watchedSince > n.bootTimeout) {
            n.lost = true;
            ++n.losses;
            events_.report(events::kNodeNeverBooted, Severity::kError,
                           "canopen: node %u lost, no boot-up or heartbeat in %lld ms since start",
                           static_cast<unsigned>(n.nodeId),
                           static_cast<long long>((now - n.watchedSince) / core::kNsPerMs));
            continue;
        }
        if (!n.everSeen || n.lost) {
            continue;
        }
        if (now - n.lastSeen > n.timeout) {
            n.lost = true;
            ++n.losses;
            n.state = NmtState::kUnknown;
            events_.report(events::kNodeLost, Severity::kError,
                           "canopen: node %u lost, no heartbeat for %lld ms (loss %u)",
                           static_cast<unsigned>(n.nodeId),
                           static_cast<long long>((now - n.lastSeen) / core::kNsPerMs),
                           static_cast<unsigned>(n.losses));
        }
    }
}

}  // namespace rse::hal::canopen
