// What the habitual task tells the ground about its legs: the events its state
// machine raises (habitual_events.hpp), their texts, severities and
// throttling in one place, so the task's logic reads as decisions. The parts
// raise their own (the hazard memory 813-817, the planning session 818, the
// drive supervisor 804, 809, 810). The texts are what people (and the recorded
// missions' consoles) read: change them only on purpose. The ground decides on
// the numbers 805, 807 and 808 carry (event data, dictionary.def), set here by name.
// No bus, no state: every figure comes from the caller.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/habitual/planning_session.hpp"
#include "fsw/msg/habitual_msgs.hpp"

namespace rse::habitual {

class LegEvents {
public:
    explicit LegEvents(core::EventLog& events) : events_(events) {}

    // 800: regionM > 0 for a region leg (the arrival radius is said), 0 for a point.
    void accepted(const msg::LegCommandMsg& leg, double regionM);
    // 801, throttled on refusedSoFar.
    void refused(std::uint32_t legId, const char* why, std::uint32_t refusedSoFar);
    // 802; moving: a leg was under way.
    void cancelled(std::uint32_t legId, bool moving);
    // 811.
    void leftAutonomous(std::uint8_t mode, std::uint32_t legId, bool moving);
    // 820 and 821; driving: the leg was being driven (it waits to be re-sent).
    void held(std::uint32_t reasons, std::uint32_t legId, bool moving);
    void released(std::uint32_t resumeCount, std::uint32_t legId, bool driving);
    // 812, throttled on waits.
    void poseNotReady(std::uint32_t legId, std::uint32_t waits);
    // 808: reached at `at` after driving, or standing within arrivalM of the point.
    void achieved(const msg::LegCommandMsg& leg, geometry::Point2 at, double drivenLengthM, double drivenEnergyJ);
    void achievedInside(const msg::LegCommandMsg& leg, geometry::Point2 at, double arrivalM);
    // 803, then 805 when the plan is a replan.
    void planSent(std::uint32_t legId, std::uint32_t trajectoryId, std::size_t points, const Evaluation& plan,
                  bool marginCut);
    void minorAnomaly(std::uint32_t legId, PlanTrigger trigger, std::uint8_t attempt);
    // 806: a run's plan violated a bound (points >= 2) or found none; or new
    // power factors broke the remaining path's energy bound (energyRepair).
    void repair(std::uint32_t legId, std::size_t points, const Evaluation& plan, unsigned attempt, unsigned last);
    void energyRepair(std::uint32_t legId, const Evaluation& remaining, double excessJ, unsigned last);
    // 822.
    void escape(std::uint32_t legId, bool offSite, geometry::Point2 from, geometry::Point2 to, std::uint32_t escapes);
    // 807: the figures of the reason; noPathRuns for kNoPath, powerFactor for kPower.
    void failUp(const msg::LegCommandMsg& leg, msg::LegConstraint reason, const Evaluation& figures,
                unsigned noPathRuns, double powerFactor);

private:
    core::EventLog& events_;
};

}  // namespace rse::habitual
