// The deliberative layer's packets (docs/icd.md §5.5), packed from what it and
// the plan executive's goal commands publish (a telemetry packer,
// cmdtlm/telemetry_packer.hpp):
//   PLAN       the goal list (GoalListMsg) and the plan in force
//              (PlanStatusMsg): in the run after either changed (a goal list
//              announced; a plan status whose state, leg, plans made, call
//              homes, current leg or risk in force changed), and every 5 s
//   PLAN_PATH  one per PlanPathMsg (one per plan the deliberative layer makes),
//              sent on receipt: in the telemetry run that takes it off the bus,
//              before that run's events (so it is given the sink when built).
//              One with more means than the message holds is refused (counted
//              by the pipe).
//   ROUTE      one per RouteChunkMsg (site mode: a route found, in chunks), on
//              receipt as PLAN_PATH; a chunk of more points than it holds is
//              refused (counted by the pipe).
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"

namespace rse::deliberative {

constexpr std::uint16_t kPlanPeriodFrames = 500;  // PLAN repeats every 5 s

class PlanTelemetry final : public cmdtlm::TelemetryPacker {
public:
    // sink: where PLAN_PATH goes on receipt.
    explicit PlanTelemetry(cmdtlm::TelemetrySink& sink) : sink_(sink) {}

    core::Status routeInputs(core::InputPipe& pipe) override;
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

    std::uint32_t planPathsSent() const { return planPathsSent_; }
    std::uint32_t routeChunksSent() const { return routeChunksSent_; }

private:
    void takeGoals(const msg::GoalListMsg& goals);
    void takePlanStatus(const msg::PlanStatusMsg& status);
    core::Status takePlanPath(const msg::PlanPathMsg& path);
    core::Status takeRouteChunk(const msg::RouteChunkMsg& chunk);
    void sendPlan(cmdtlm::TelemetrySink& sink);

    cmdtlm::TelemetrySink& sink_;
    msg::GoalListMsg goals_{};
    msg::PlanStatusMsg planStatus_{};
    bool changed_ = true;  // PLAN goes in the first run
    std::uint32_t planPathsSent_ = 0;
    std::uint32_t routeChunksSent_ = 0;
    // Packet structs kept off the telemetry task's stack.
    cmdtlm::PLAN_Tlm plan_{};
    cmdtlm::PLAN_PATH_Tlm planPath_{};
    cmdtlm::ROUTE_Tlm route_{};
};

}  // namespace rse::deliberative
