#include "fsw/deliberative/mission_hold.hpp"

#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

MissionHold::Change MissionHold::take(const msg::MissionHoldMsg& hold, std::uint32_t legInForce, bool driving) {
    reasons_ = hold.reasons;
    resumeCount_ = hold.resumeCount;
    if (hold.reasons != 0U) {
        if (held_) {
            return Change::kNone;
        }
        held_ = true;
        ++holds_;
        events_.report(events::kMissionHeld, core::Severity::kWarning,
                       "deliberative: mission held (reasons 0x%x%s): no new legs, leg %u kept",
                       static_cast<unsigned>(hold.reasons), hold.estop != 0 ? ", e-stop" : "",
                       static_cast<unsigned>(legInForce));
        return Change::kHeld;
    }
    if (!held_) {
        return Change::kNone;
    }
    held_ = false;
    ++resumes_;
    events_.report(events::kMissionResumed, core::Severity::kInfo, "deliberative: hold released (resume %u): %s",
                   static_cast<unsigned>(hold.resumeCount),
                   driving ? "current leg re-sent from the current pose" : "nothing to re-send");
    return Change::kReleased;
}

}  // namespace rse::deliberative
