#include "fsw/cmdtlm/rover_mode.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/msg/mode_msgs.hpp"

namespace rse::cmdtlm {

void RoverMode::setMode(Mode mode) {
    events_.report(events::kModeChanged, core::Severity::kInfo, "app: mode %s -> %s", toString(mode_),
                   toString(mode));
    mode_ = mode;
    publish();
}

void RoverMode::setEstop(bool set) {
    if (set) {
        events_.report(events::kEstopSet, core::Severity::kWarning,
                       "app: software e-stop SET: all drives commanded to zero and held");
    } else {
        events_.report(events::kEstopCleared, core::Severity::kInfo,
                       "app: software e-stop cleared (drives stay at zero until commanded)");
    }
    estop_ = set;
    publish();
}

void RoverMode::takeSafeRequest(const msg::SafeRequestMsg& request) {
    ++safeRequests_;
    event_data::SAFED_ON_REQUEST data;
    data.reason = static_cast<double>(request.reason);
    data.mode_before = static_cast<double>(mode_);
    events_.report(events::kSafedOnRequest, core::Severity::kWarning, data.pack(),
                   "app: onboard call home (reason %u): mode %s -> SAFE", static_cast<unsigned>(request.reason),
                   toString(mode_));
    if (mode_ != Mode::kSafe) {
        setMode(Mode::kSafe);
    }
}

void RoverMode::publish() {
    msg::ModeMsg m{};
    m.timeNs = clock_.now();
    m.mode = static_cast<std::uint8_t>(mode_);
    m.estop = estop_ ? 1 : 0;
    (void)bus_.publish(m);  // a refusal is counted and evented by the bus
}

void RoverMode::fillHousekeeping(HK_Tlm& hk) const {
    hk.mode = static_cast<std::uint8_t>(mode_);
    hk.estop = estop_ ? 1 : 0;
}

}  // namespace rse::cmdtlm
