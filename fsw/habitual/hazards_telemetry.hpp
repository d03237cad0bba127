// HAZARDS (docs/icd.md §5.5), packed from the habitual layer's hazard map
// (KnownHazardsMsg: published at 1 Hz and on change; a telemetry packer,
// cmdtlm/telemetry_packer.hpp): in slot kHazardsSlot of every fifth second,
// and in slot kHazardsSlot of a second in which the map's revision changed
// (so at most 1 Hz: the map may change at every habitual run, 10 Hz, and a
// HAZARDS packet is 433 bytes, about 62 ISO-TP frames on CAN). A message
// holding more hazards than it can carry is refused (counted by the pipe).
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/habitual_msgs.hpp"

namespace rse::habitual {

constexpr std::uint32_t kHazardsSlot = 45;            // HAZARDS: in this slot, on change or ...
constexpr std::uint32_t kHazardsPeriodFrames = 500;   // ... every 5 s

class HazardsTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override {
        return pipe.route<&HazardsTelemetry::takeHazards>(this);
    }
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

    std::uint32_t hazardsSent() const { return hazardsSent_; }

private:
    core::Status takeHazards(const msg::KnownHazardsMsg& hazards);
    void send(cmdtlm::TelemetrySink& sink);

    msg::KnownHazardsMsg hazards_{};
    bool changed_ = false;  // a revision not yet sent
    std::uint32_t hazardsSent_ = 0;
    cmdtlm::HAZARDS_Tlm tlm_{};  // kept off the telemetry task's stack
};

}  // namespace rse::habitual
