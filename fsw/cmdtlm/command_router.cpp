#include "fsw/cmdtlm/command_router.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

CommandRouter::CommandRouter(core::SoftwareBus& bus, core::EventLog& events, const RoverMode& mode)
    : events_(events),
      mode_(mode),
      requests_(bus, events,
                core::InputPipeConfig{"mode_requests", kOnboardRequestDepth, events::kBusMessageMalformed, "app"}) {}

core::Status CommandRouter::add(AppCommands* app) {
    core::Status status = core::Status::kOk;
    if (app == nullptr) {
        status = core::Status::kInvalidArgument;
    } else if (ownerOf(app->apid()) != nullptr) {
        status = core::Status::kAlreadyExists;
    } else if (count_ >= kMaxAppCommands) {
        status = core::Status::kNoCapacity;
    }
    if (!core::isOk(status)) {
        events_.report(events::kAppRegistrationRefused, core::Severity::kCritical,
                       "cmd: commands of APID 0x%03x not registered (%s)",
                       static_cast<unsigned>(app == nullptr ? 0 : app->apid()), core::toString(status));
        return status;
    }
    apps_[count_++] = app;
    return core::Status::kOk;
}

AppCommands* CommandRouter::ownerOf(std::uint16_t apid) const {
    for (std::size_t i = 0; i < count_; ++i) {
        if (apps_[i]->apid() == apid) {
            return apps_[i];
        }
    }
    return nullptr;
}

CommandOutcome CommandRouter::execute(const CommandVerdict& verdict) {
    AppCommands* owner = verdict.command == nullptr ? nullptr : ownerOf(verdict.command->apid);
    if (owner == nullptr) {
        ++withoutOwner_;
        events_.report(events::kCommandWithoutOwner, core::Severity::kError,
                       "cmd: %s refused: no application owns APID 0x%03x (%u so far)",
                       verdict.command == nullptr ? "?" : verdict.command->name,
                       static_cast<unsigned>(verdict.header.apid), static_cast<unsigned>(withoutOwner_));
        return commandFailed(-1);
    }
    return owner->execute(verdict);
}

void CommandRouter::serviceOnboardRequests() {
    (void)requests_.drain();  // bounded by the pipe's depth; nothing before init()
    const Mode mode = mode_.mode();  // as the requests left it: every application sees the same
    for (std::size_t i = 0; i < count_; ++i) {
        apps_[i]->serviceOnboardRequests(mode);
    }
}

void CommandRouter::resetAppCounters() {
    for (std::size_t i = 0; i < count_; ++i) {
        apps_[i]->resetCounters();
    }
}

}  // namespace rse::cmdtlm
