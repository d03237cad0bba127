// HK and TASK_TIMING (docs/icd.md §5.5): the command and telemetry service's
// packets, the executive's face in telemetry. A telemetry packer
// (telemetry_packer.hpp) that reads no bus message:
//   HK           slot 0 of every second, and in the run after REQUEST_HK. The
//                executive's, bus's and event log's counters from a fresh
//                housekeeping collection (HousekeepingTask::collect, the
//                HousekeepingMsg fields); every other field from its owner
//                (HousekeepingContributor, in registration order); the time
//                correlation and the time scale, set at start-up
//   TASK_TIMING  row i in slot kTaskTimingSlot + i, from the collection of the
//                last HK, so all rows are of one instant
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/cmdtlm/housekeeping_contributor.hpp"
#include "fsw/cmdtlm/housekeeping_task.hpp"
#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/housekeeping_msg.hpp"

namespace rse::cmdtlm {

constexpr std::uint32_t kTaskTimingSlot = 10;  // TASK_TIMING of task i in slot 10 + i
// Owners of HK fields: the command service, the mode owner, CAN I/O, tables,
// telemetry output today; three spare.
constexpr std::size_t kMaxHousekeepingContributors = 8;

class HousekeepingTelemetry final : public TelemetryPacker {
public:
    explicit HousekeepingTelemetry(const HousekeepingTask& collection) : collection_(collection) {}

    // Start-up: an owner of HK fields. kInvalidArgument (null), kNoCapacity.
    core::Status addContributor(const HousekeepingContributor* contributor);
    void setUtcAtMetZero(double utc) { utcAtMetZero_ = utc; }
    void setTimeScale(std::uint8_t factor) { timeScale_ = factor; }
    // REQUEST_HK: HK and TASK_TIMING on the next run.
    void requestHousekeeping() { requested_ = true; }

    core::Status routeInputs(core::InputPipe&) override { return core::Status::kOk; }  // no bus input
    void pack(const core::FrameContext& frame, TelemetrySink& sink) override;

    std::uint32_t housekeepingSent() const { return housekeepingSent_; }

private:
    void sendHousekeeping(core::TimeNs now, TelemetrySink& sink);
    void sendTaskTiming(std::size_t index, TelemetrySink& sink) const;

    const HousekeepingTask& collection_;
    const HousekeepingContributor* contributors_[kMaxHousekeepingContributors] = {};
    std::size_t contributorCount_ = 0;
    double utcAtMetZero_ = 0.0;   // time correlation, fixed at start-up
    std::uint8_t timeScale_ = 1;  // HK.time_scale: 1 real time, N the timeline slowed N times (lab)
    bool requested_ = false;
    std::uint32_t housekeepingSent_ = 0;
    // Kept out of the telemetry task's stack.
    msg::HousekeepingMsg collected_{};
    HK_Tlm hk_{};
};

}  // namespace rse::cmdtlm
