// The health tests' rig: a real executive on a virtual clock running, in
// order, a feed task standing in for the CAN I/O and pose estimator tasks (a
// real heartbeat consumer fed with heartbeat frames, drive status, power at
// 10 Hz, pose and IMU every frame, a fix at 1 Hz, hazards at 10 Hz), an idle 100 Hz worker, the health task, an idle
// 10 Hz task and an idle 100 Hz task after the health task. Nothing here
// touches the heap after construction, so the zero-allocation test can use it.
#pragma once

#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/estimator/health_task.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/msg_ids.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "hal/can/can_frame.hpp"
#include "hal/canopen/heartbeat_consumer.hpp"

namespace rse::test {

constexpr std::uint8_t kNodeIds[msg::kMonitoredNodeCount] = {1, 2, 3, 4, 5, 6, 32, 33, 34, 35};

class FeedTask final : public core::Task {
public:
    FeedTask(core::SoftwareBus& bus, core::EventLog& events) : bus_(bus), heartbeats(events) {
        for (bool& a : alive) {
            a = true;
        }
        pose.initialised = 1;
        pose.positionSigmaM = 0.1;
        power.busVoltageV = 28.0;
        power.busCurrentA = 5.0;
        power.stateOfCharge = 0.9;
    }

    bool monitorNodes(core::TimeNs timeout) {
        for (std::uint8_t id : kNodeIds) {
            if (!core::isOk(heartbeats.monitor(id, timeout))) {
                return false;
            }
        }
        return true;
    }

    void run(const core::FrameContext& frame) override {
        const core::TimeNs now = frame.actualStart;
        // Each node heartbeats every 100 ms, node i in frames with frame % 10 == i.
        for (std::size_t i = 0; i < msg::kMonitoredNodeCount; ++i) {
            if (alive[i] && frame.frame % 10 == i % 10) {
                hal::CanFrame f;
                f.id = 0x700U + kNodeIds[i];
                f.dlc = 1;
                f.data[0] = 0x05;
                heartbeats.onFrame(f, now);
                lastHeartbeat[i] = now;
            }
        }
        heartbeats.check(now);
        nodes.timeNs = now;
        nodes.heartbeatTimeoutNs = heartbeats.node(kNodeIds[0])->timeout;
        for (std::size_t i = 0; i < msg::kMonitoredNodeCount; ++i) {
            const hal::canopen::NodeHealth* h = heartbeats.node(kNodeIds[i]);
            nodes.nodes[i].nodeId = kNodeIds[i];
            nodes.nodes[i].lastSeenNs = h->lastSeen;
            nodes.nodes[i].losses = h->losses;
            nodes.nodes[i].nmtState = static_cast<std::uint8_t>(h->state);
            nodes.nodes[i].lost = h->lost ? 1 : 0;
            nodes.nodes[i].everSeen = h->everSeen ? 1 : 0;
        }
        if (publishNodes) {
            (void)bus_.publish(nodes);
        }
        if (publishDrives) {
            drives.timeNs = now;
            (void)bus_.publish(drives);
        }
        if (publishPower && frame.frame % 10 == 0) {
            power.timeNs = now;
            (void)bus_.publish(power);
            lastPowerSample = now;
        }
        if (publishPose) {
            pose.timeNs = now;
            (void)bus_.publish(pose);
        }
        // Sensor data as CAN I/O publishes it: IMU every frame, a fix at 1 Hz,
        // HazardMsg every 100 ms with the detector's frame count, which moves
        // only when the detector speaks (1 Hz here: its "clear" reports).
        if (publishImu) {
            const msg::ImuMsg imu{now, 0.0, 1, {}};
            (void)bus_.publish(imu);
            lastImuSample = now;
        }
        if (publishFix && frame.frame % 100 == 50) {
            const msg::PositionFixMsg fix{now, 1.0, 2.0, 0.0, 0.05};
            (void)bus_.publish(fix);
            lastFixSample = now;
        }
        if (frame.frame % 10 == 0) {
            if (hazardSpeaks && frame.frame % 100 == 0) {
                ++hazard.detectorFrames;
                lastHazardFrame = now;
            }
            hazard.timeNs = now;
            (void)bus_.publish(hazard);
        }
    }

    bool alive[msg::kMonitoredNodeCount];
    core::TimeNs lastHeartbeat[msg::kMonitoredNodeCount] = {};
    core::TimeNs lastPowerSample = 0;
    msg::NodeStatusMsg nodes{};
    msg::DriveStatusMsg drives{};
    msg::PowerMsg power{};
    msg::PoseEstimateMsg pose{};
    bool publishNodes = true;
    bool publishDrives = true;
    bool publishPower = true;
    bool publishPose = true;
    bool publishImu = true;
    bool publishFix = true;
    bool hazardSpeaks = true;
    core::TimeNs lastImuSample = 0;
    core::TimeNs lastFixSample = 0;
    core::TimeNs lastHazardFrame = 0;
    msg::HazardMsg hazard{};

private:
    core::SoftwareBus& bus_;

public:
    hal::canopen::HeartbeatConsumer heartbeats;
};

class IdleTask final : public core::Task {
public:
    void run(const core::FrameContext&) override { ++runs; }
    std::uint32_t runs = 0;
};

// What the rig saw of one health event id.
struct EventSeen {
    unsigned count = 0;
    core::TimeNs firstTime = -1;
    core::TimeNs lastTime = -1;
    core::Severity lastSeverity = core::Severity::kDebug;
    char lastText[core::kEventTextSize] = {};
};

class HealthRig {
public:
    static constexpr core::TimeNs kEpoch = 5 * core::kNsPerSec;  // not 0: "never ran" must not hide in it
    static constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;
    static constexpr core::EventId kFirstId = 720;
    static constexpr core::EventId kLastId = 759;
    enum Row : std::size_t { kFeedRow = 0, kWorkerRow = 1, kHealthRow = 2, kSlowRow = 3, kAfterRow = 4 };

    core::VirtualClock clock{kEpoch};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    core::Executive exec{clock, events};
    FeedTask feed{bus, events};
    IdleTask worker;
    IdleTask slow;
    IdleTask after;
    estimator::HealthTask health{bus, events, tables, exec};
    core::PipeId statusPipe = 0;

    // Status messages seen on the bus, and the latest.
    std::uint32_t statusSeen = 0;
    msg::FaultStatusMsg lastStatus{};
    core::TimeNs lastStatusTime = -1;
    EventSeen seen[kLastId - kFirstId + 1];
    unsigned eventsDrained = 0;

    bool init() {
        if (!core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount))) {
            return false;
        }
        const core::TimeNs timeout =
            static_cast<core::TimeNs>(tables.canNodeMap().heartbeat_timeout_ms) * core::kNsPerMs;
        if (!feed.monitorNodes(timeout) || !core::isOk(health.init())) {
            return false;
        }
        if (!core::isOk(bus.createPipe("probe", 8, &statusPipe)) ||
            !core::isOk(bus.subscribe(statusPipe, msg::ids::kFaultStatus))) {
            return false;
        }
        const core::RateGroupEntry table[] = {
            {"feed", &feed, 1, 0, 1000},     {"worker", &worker, 1, 0, 1000}, {"health", &health, 1, 0, 1000},
            {"slow", &slow, 10, 0, 1000},    {"after", &after, 1, 0, 1000},
        };
        return core::isOk(exec.init(core::ExecutiveConfig{}, table, sizeof table / sizeof table[0]));
    }

    // Runs one frame; afterwards now() is that frame's start.
    void step() {
        exec.runFrame();
        drain();
    }
    void steps(int n) {
        for (int i = 0; i < n; ++i) {
            step();
        }
    }
    core::TimeNs now() const { return clock.now(); }

    // Steps until the fault is in the wanted state; returns the start of the
    // frame in which it got there, or -1 if it did not within maxFrames.
    core::TimeNs stepUntil(std::uint8_t faultId, bool active, int maxFrames) {
        for (int i = 0; i < maxFrames; ++i) {
            step();
            if (health.active(faultId) == active) {
                return now();
            }
        }
        return -1;
    }

    const EventSeen& event(core::EventId id) const { return seen[id - kFirstId]; }
    unsigned eventCount(core::EventId id) const { return event(id).count; }
    void forgetEvents() {
        for (EventSeen& s : seen) {
            s = EventSeen{};
        }
    }

private:
    void drain() {
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            ++eventsDrained;
            if (e.id >= kFirstId && e.id <= kLastId) {
                EventSeen& s = seen[e.id - kFirstId];
                ++s.count;
                if (s.firstTime < 0) {
                    s.firstTime = e.time;
                }
                s.lastTime = e.time;
                s.lastSeverity = e.severity;
                std::memcpy(s.lastText, e.text, sizeof s.lastText);
            }
        }
        core::Message m;
        while (core::isOk(bus.receive(statusPipe, &m))) {
            if (core::isOk(m.decode(&lastStatus))) {
                ++statusSeen;
                lastStatusTime = now();
            }
        }
    }
};

}  // namespace rse::test
