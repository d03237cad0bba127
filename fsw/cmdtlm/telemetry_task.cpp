#include "fsw/cmdtlm/telemetry_task.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

TelemetryTask::TelemetryTask(core::SoftwareBus& bus, core::EventLog& events, TelemetryOutput& output)
    : log_(events),
      output_(output),
      input_(bus, events,
             core::InputPipeConfig{"telemetry", kTelemetryPipeDepth, events::kBusMessageMalformed, "telemetry"}),
      events_(events, output) {}

core::Status TelemetryTask::add(TelemetryPacker* packer) {
    core::Status status = core::Status::kOk;
    if (packer == nullptr) {
        status = core::Status::kInvalidArgument;
    } else if (input_.ready()) {
        status = core::Status::kAlreadyExists;  // its inputs would not be routed
    } else if (count_ >= kMaxTelemetryPackers) {
        status = core::Status::kNoCapacity;
    }
    if (!core::isOk(status)) {
        log_.report(events::kAppRegistrationRefused, core::Severity::kCritical,
                    "tlm: telemetry packer %u not registered (%s)", static_cast<unsigned>(count_),
                    core::toString(status));
        return status;
    }
    packers_[count_++] = packer;
    return core::Status::kOk;
}

core::Status TelemetryTask::init() {
    core::Status status = input_.create();
    for (std::size_t i = 0; i < count_ && core::isOk(status); ++i) {
        status = packers_[i]->routeInputs(input_);
    }
    return status;
}

void TelemetryTask::run(const core::FrameContext& frame) {
    (void)input_.drain();
    events_.send();
    for (std::size_t i = 0; i < count_; ++i) {
        packers_[i]->pack(frame, output_);
    }
}

}  // namespace rse::cmdtlm
