// A small CiA 301 NMT master: owns the cycle on one CAN bus.
//
// Every cycle (one minor frame): read the waiting frames (bounded) and hand each
// to its owner by COB-ID: heartbeats to the consumer; EMCY, TPDO and SDO answers
// of a registered node to that node; frames registered by exact id (RSE devices,
// the ISO-TP ground link) to their sink. Then check heartbeat timeouts, step every
// node, let each send its RPDOs, and send SYNC. At the first cycle it resets the
// communication of every node so each announces itself with a boot-up message.
// Frames nobody owns are counted and evented.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/static_vector.hpp"
#include "hal/can/can_bus.hpp"
#include "hal/canopen/canopen_ids.hpp"
#include "hal/canopen/heartbeat_consumer.hpp"

namespace rse::hal::canopen {

constexpr std::size_t kMaxCanOpenNodes = 8;
constexpr std::size_t kMaxFrameSinks = 16;
constexpr std::size_t kMaxFramesPerCycle = 128;  // more waiting frames wait for the next cycle

// A device client the master drives (e.g. WheelDrive).
class CanOpenNode {
public:
    virtual std::uint8_t nodeId() const = 0;
    virtual void onFrame(const CanFrame& frame, core::TimeNs now) = 0;  // EMCY, TPDOs, SDO answers
    virtual void step(core::TimeNs now) = 0;
    virtual void sendCyclic(core::TimeNs now) = 0;  // RPDOs, before SYNC

protected:
    ~CanOpenNode() = default;
};

// Takes frames of one exact COB-ID (RSE device frames, ISO-TP).
class CanFrameSink {
public:
    virtual void onFrame(const CanFrame& frame, core::TimeNs now) = 0;

protected:
    ~CanFrameSink() = default;
};

struct MasterStats {
    std::uint32_t cycles = 0;
    std::uint32_t framesIn = 0;
    std::uint32_t unknownCobId = 0;
    std::uint32_t syncSent = 0;
    std::uint32_t syncFailed = 0;
    std::uint32_t nmtSent = 0;
    std::uint32_t backlogCycles = 0;  // cycles that left frames waiting (kMaxFramesPerCycle hit)
};

class CanOpenMaster {
public:
    CanOpenMaster(CanBus& bus, core::EventLog& events) : bus_(bus), events_(events), heartbeats_(events) {}

    // bootTimeout: see HeartbeatConsumer::monitor (0: none).
    core::Status addNode(CanOpenNode* node, core::TimeNs heartbeatTimeout, core::TimeNs bootTimeout = 0);
    core::Status addSink(std::uint32_t cobId, CanFrameSink* sink);
    // Monitors a heartbeat-only node (RSE devices).
    core::Status monitor(std::uint8_t nodeId, core::TimeNs heartbeatTimeout) {
        return heartbeats_.monitor(nodeId, heartbeatTimeout);
    }

    void cycle(core::TimeNs now);
    core::Status sendNmt(NmtCommand command, std::uint8_t nodeId);

    const HeartbeatConsumer& heartbeats() const { return heartbeats_; }
    const MasterStats& stats() const { return stats_; }

private:
    struct Sink {
        std::uint32_t cobId;
        CanFrameSink* sink;
    };
    void dispatch(const CanFrame& frame, core::TimeNs now);
    CanOpenNode* findNode(std::uint8_t nodeId);

    CanBus& bus_;
    core::EventLog& events_;
    HeartbeatConsumer heartbeats_;
    core::StaticVector<CanOpenNode*, kMaxCanOpenNodes> nodes_;
    core::StaticVector<Sink, kMaxFrameSinks> sinks_;
    MasterStats stats_;
    bool started_ = false;
};

}  // namespace rse::hal::canopen
