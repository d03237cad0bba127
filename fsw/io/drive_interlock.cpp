#include "fsw/io/drive_interlock.hpp"

#include "fsw/io/io_events.hpp"

namespace rse::io {

namespace {
bool unhealthy(msg::DriveHealth h) {
    return h == msg::DriveHealth::kFaulted || h == msg::DriveHealth::kFailed || h == msg::DriveHealth::kLost;
}
}  // namespace

void DriveInterlock::apply(const msg::DriveStatusMsg& status, const double (&command)[msg::kWheelCount],
                           double (&out)[msg::kWheelCount]) {
    if (!tripped_) {
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            if (unhealthy(status.wheels[w].health)) {
                tripped_ = true;
                ++trips_;
                events_.report(events::kInterlockTripped, core::Severity::kCritical,
                               "reflexive: wheel %zu drive unhealthy (health %u, EMCY 0x%04X): all wheels to zero",
                               w, static_cast<unsigned>(status.wheels[w].health),
                               static_cast<unsigned>(status.wheels[w].lastEmcyCode));
                break;
            }
        }
    }
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        out[w] = tripped_ ? 0.0 : command[w];
    }
}

bool DriveInterlock::resetIfHealthy(const msg::DriveStatusMsg& status) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (unhealthy(status.wheels[w].health)) {
            events_.report(events::kInterlockResetRefused, core::Severity::kWarning,
                           "reflexive: interlock reset refused: wheel %zu drive still unhealthy (health %u)%s", w,
                           static_cast<unsigned>(status.wheels[w].health), tripped_ ? "" : " (not tripped)");
            return false;
        }
    }
    reset();
    return true;
}

void DriveInterlock::reset() {
    if (tripped_) {
        events_.report(events::kInterlockReset, core::Severity::kInfo, "reflexive: drive interlock reset");
    }
    tripped_ = false;
}

}  // namespace rse::io
