// The telemetry task (every minor frame): the scheduler of the telemetry
// packers. It knows no packet: each application packs its own packet family
// (telemetry_packer.hpp) from the bus messages it routes on this task's one
// input pipe, and sends what is due through the sink (TelemetryOutput).
//   start-up  add() each packer, in the order its packets go within a frame;
//             init() creates the pipe and has each packer route its inputs
//   each run  1 drain the pipe: each message to the packers that routed its
//               id, in arrival order (a packer that sends on receipt, PLAN_PATH,
//               sends here); a message that does not decode, or that a
//               packer refuses, is counted (malformed()) and evented (211)
//             2 EVENT packets, each followed by its EVENT_DATA when it
//               carries numbers (event_downlink.hpp)
//             3 each packer's pack(), in registration order
// Which packets go when: docs/icd.md "Telemetry", and each packer's header.
// The order fsw/app registers them in (HK and TASK_TIMING, DRIVES, ROVER_STATE
// and HEALTH, FAULT_PROTECTION, INSTRUMENTS, PLAN_EXEC, POWER, HAZARDS, PLAN)
// is the order of the packets within a frame.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/event_downlink.hpp"
#include "fsw/cmdtlm/telemetry_output.hpp"
#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"

namespace rse::cmdtlm {

// The task drains its pipe every frame, so the pipe holds one frame's inputs:
// each of the packers' 18 message ids at most once a frame (the follower's
// status among them since DRIVES carries the contact reflex's counts), the
// instrument status twice (one per instrument), the route's chunks up to 4 in
// a deliberative run: 24, with room. A copy lost to a full pipe is counted and
// evented by the bus (event 101). The flight's pipes take 216 of the bus's
// 264 slots (kBusTotalQueueSlots: 48 left for the probes the lockstep tests
// subscribe, as before the follower's status came here).
constexpr std::uint16_t kTelemetryPipeDepth = 24;
// Packers the task schedules: nine in the flight today (fsw/app/fsw_app.cpp), three spare.
constexpr std::size_t kMaxTelemetryPackers = 12;

class TelemetryTask final : public core::Task {
public:
    TelemetryTask(core::SoftwareBus& bus, core::EventLog& events, TelemetryOutput& output);
    TelemetryTask(const TelemetryTask&) = delete;
    TelemetryTask& operator=(const TelemetryTask&) = delete;

    // Before init: a packer, scheduled after those added before it.
    // kInvalidArgument (null), kNoCapacity (kMaxTelemetryPackers), kAlreadyExists
    // (after init): refused and evented (509).
    core::Status add(TelemetryPacker* packer);
    // The pipe, then each packer's routes, in registration order.
    core::Status init();
    void run(const core::FrameContext& frame) override;

    std::size_t packerCount() const { return count_; }
    std::uint32_t eventsSent() const { return events_.eventsSent(); }
    std::uint32_t eventDataSent() const { return events_.dataSent(); }
    std::uint32_t eventDataWithheld() const { return events_.dataWithheld(); }
    std::uint32_t malformed() const { return input_.malformed(); }  // inputs refused by the pipe or a packer

private:
    core::EventLog& log_;
    TelemetryOutput& output_;
    core::InputPipe input_;
    EventDownlink events_;
    TelemetryPacker* packers_[kMaxTelemetryPackers] = {};
    std::size_t count_ = 0;
};

}  // namespace rse::cmdtlm
