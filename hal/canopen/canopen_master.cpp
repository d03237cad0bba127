#include "hal/canopen/canopen_master.hpp"

#include "hal/canopen/canopen_events.hpp"

namespace rse::hal::canopen {

using core::Severity;
using core::Status;

Status CanOpenMaster::addNode(CanOpenNode* node, core::TimeNs heartbeatTimeout, core::TimeNs bootTimeout) {
    if (node == nullptr) {
        return Status::kInvalidArgument;
    }
    const Status s = heartbeats_.monitor(node->nodeId(), heartbeatTimeout, bootTimeout);
    if (!core::isOk(s)) {
        return s;
    }
    return nodes_.push_back(node) == Status::kOk ? Status::kOk : Status::kNoCapacity;
}

Status CanOpenMaster::addSink(std::uint32_t cobId, CanFrameSink* sink) {
    if (sink == nullptr || cobId > kCanMaxStandardId) {
        return Status::kInvalidArgument;
    }
    for (const Sink& s : sinks_) {
        if (s.cobId == cobId) {
            return Status::kAlreadyExists;
        }
    }
    return sinks_.push_back(Sink{cobId, sink}) == Status::kOk ? Status::kOk : Status::kNoCapacity;
}

CanOpenNode* CanOpenMaster::findNode(std::uint8_t nodeId) {
    for (CanOpenNode* n : nodes_) {
        if (n->nodeId() == nodeId) {
            return n;
        }
    }
    return nullptr;
}

Status CanOpenMaster::sendNmt(NmtCommand command, std::uint8_t nodeId) {
    CanFrame f;
    f.id = kNmt;
    f.dlc = 2;
    f.data[0] = static_cast<std::uint8_t>(command);
    f.data[1] = nodeId;
    const Status s = bus_.send(f);
    if (core::isOk(s)) {
        ++stats_.nmtSent;
    }
    return s;
}

void CanOpenMaster::dispatch(const CanFrame& frame, core::TimeNs now) {
    if (frame.extended()) {
        ++stats_.unknownCobId;  // the rover bus is 11-bit only
        return;
    }
    for (const Sink& s : sinks_) {
        if (s.cobId == frame.id) {
            s.sink->onFrame(frame, now);
            return;
        }
    }
    const std::uint32_t function = functionOf(frame.id);
    const std::uint8_t node = nodeOf(frame.id);
    if (function == kHeartbeat && node != 0) {
        heartbeats_.onFrame(frame, now);
        return;
    }
    const bool perNode =
        (function == kEmcy && node != 0) || function == kTpdo1 || function == kTpdo2 || function == kSdoResponse;
    CanOpenNode* owner = perNode ? findNode(node) : nullptr;
    if (owner != nullptr) {
        owner->onFrame(frame, now);
        return;
    }
    ++stats_.unknownCobId;
    if (core::isReportableOccurrence(stats_.unknownCobId)) {
        events_.report(events::kUnknownCobId, Severity::kWarning,
                       "canopen: frame 0x%03X (dlc %u) has no owner, %u so far", static_cast<unsigned>(frame.id),
                       static_cast<unsigned>(frame.dlc), static_cast<unsigned>(stats_.unknownCobId));
    }
}

void CanOpenMaster::cycle(core::TimeNs now) {
    ++stats_.cycles;
    if (!started_) {
        // Every node restarts its communication and announces itself (boot-up),
        // so the master configures from a known state whatever ran before.
        started_ = core::isOk(sendNmt(NmtCommand::kResetCommunication, 0));
    }
    CanFrame frame;
    std::size_t taken = 0;
    while (taken < kMaxFramesPerCycle && core::isOk(bus_.receive(&frame))) {
        ++taken;
        ++stats_.framesIn;
        dispatch(frame, now);
    }
    if (taken == kMaxFramesPerCycle) {
        ++stats_.backlogCycles;
    }
    heartbeats_.check(now);
    for (CanOpenNode* n : nodes_) {
        n->step(now);
    }
    for (CanOpenNode* n : nodes_) {
        n->sendCyclic(now);
    }
    CanFrame sync;
    sync.id = kSync;
    sync.dlc = 0;
    if (core::isOk(bus_.send(sync))) {
        ++stats_.syncSent;
    } else {
        ++stats_.syncFailed;
    }
}

}  // namespace rse::hal::canopen
