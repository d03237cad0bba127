#include "fsw/habitual/hazards_telemetry.hpp"

#include <algorithm>

namespace rse::habitual {

core::Status HazardsTelemetry::takeHazards(const msg::KnownHazardsMsg& hazards) {
    if (hazards.count > msg::kMaxKnownHazards) {
        return core::Status::kInvalidArgument;  // more hazards than the message holds
    }
    // Published at 1 Hz and on change: only a new revision is news.
    changed_ = changed_ || hazards.revision != hazards_.revision;
    hazards_ = hazards;
    return core::Status::kOk;
}

void HazardsTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot == kHazardsSlot && (changed_ || frame.frame % kHazardsPeriodFrames == kHazardsSlot)) {
        changed_ = false;
        send(sink);
    }
}

void HazardsTelemetry::send(cmdtlm::TelemetrySink& sink) {
    static_assert(sizeof tlm_.x / sizeof tlm_.x[0] == msg::kMaxKnownHazards,
                  "HAZARDS holds every hazard the message can carry");
    static_assert(cmdtlm::kHAZARDS_TlmSize + cmdtlm::kTelemetryHeaderSize <= cmdtlm::kMaxTelemetryPacket,
                  "HAZARDS fits in one telemetry packet");
    tlm_ = cmdtlm::HAZARDS_Tlm{};
    cmdtlm::HAZARDS_Tlm& t = tlm_;
    t.revision = hazards_.revision;
    const std::size_t count = std::min<std::size_t>(hazards_.count, msg::kMaxKnownHazards);  // checked on receipt
    t.count = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count; ++i) {
        const msg::KnownHazard& h = hazards_.hazards[i];
        t.x[i] = h.xM;
        t.y[i] = h.yM;
        t.radius[i] = h.radiusM;
        t.obstacle_id[i] = h.obstacleId;
    }
    sink.send(t);
    ++hazardsSent_;
}

}  // namespace rse::habitual
