// Fault protection's mission hold as the deliberative layer keeps it
// (MissionHoldMsg; docs/deliberative.md, "Mission hold"). While reasons != 0
// the mission is held (event 920 when it begins): no leg is sent and no plan
// started, fail-ups and mobility loss are ignored (fault protection owns the
// response; a drive under recovery trips the interlock on purpose). Reasons 0
// releases it (event 921) whether or not resumeCount moved: a lost or
// inconsistent count must not leave the mission held for good. What a release
// re-sends is the task's (the current leg, from the current pose).
//
// Nothing is timed: held time counts against nothing. No bus.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"

namespace rse::deliberative {

class MissionHold {
public:
    enum class Change : std::uint8_t { kNone, kHeld, kReleased };

    explicit MissionHold(core::EventLog& events) : events_(events) {}

    // A MissionHoldMsg (checked: msg::holdUsable). legInForce: the leg kept
    // (event 920); driving: a leg will be re-sent on a release (event 921).
    // kHeld when a hold begins, kReleased when one ends, else kNone.
    Change take(const msg::MissionHoldMsg& hold, std::uint32_t legInForce, bool driving);

    bool held() const { return held_; }
    std::uint32_t reasons() const { return reasons_; }
    std::uint32_t resumeCount() const { return resumeCount_; }
    std::uint32_t holds() const { return holds_; }      // holds begun
    std::uint32_t resumes() const { return resumes_; }  // holds released

private:
    core::EventLog& events_;
    bool held_ = false;
    std::uint32_t reasons_ = 0;
    std::uint32_t resumeCount_ = 0;
    std::uint32_t holds_ = 0;
    std::uint32_t resumes_ = 0;
};

}  // namespace rse::deliberative
