#include "fsw/habitual/leg_events.hpp"

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/habitual_events.hpp"

namespace rse::habitual {

using geometry::Point2;

void LegEvents::accepted(const msg::LegCommandMsg& leg, double regionM) {
    if (regionM > 0.0) {
        events_.report(events::kLegAccepted, core::Severity::kInfo,
                       "habitual: leg %u to (%.2f, %.2f) within %.2f m: max %.1f m, %.0f J",
                       static_cast<unsigned>(leg.legId), leg.goalXM, leg.goalYM, regionM, leg.maxPathLengthM,
                       leg.maxEnergyJ);
    } else {
        events_.report(events::kLegAccepted, core::Severity::kInfo,
                       "habitual: leg %u to (%.2f, %.2f): max %.1f m, %.0f J", static_cast<unsigned>(leg.legId),
                       leg.goalXM, leg.goalYM, leg.maxPathLengthM, leg.maxEnergyJ);
    }
}

void LegEvents::refused(std::uint32_t legId, const char* why, std::uint32_t refusedSoFar) {
    if (core::isReportableOccurrence(refusedSoFar)) {
        events_.report(events::kLegRefused, core::Severity::kWarning, "habitual: leg %u refused: %s (%u so far)",
                       static_cast<unsigned>(legId), why, static_cast<unsigned>(refusedSoFar));
    }
}

void LegEvents::cancelled(std::uint32_t legId, bool moving) {
    events_.report(events::kLegCancelled, core::Severity::kInfo, "habitual: leg %u cancelled: %s",
                   static_cast<unsigned>(legId), moving ? "rover stopped" : "nothing under way");
}

void LegEvents::leftAutonomous(std::uint8_t mode, std::uint32_t legId, bool moving) {
    events_.report(events::kLeftAutonomous, core::Severity::kInfo,
                   "habitual: left AUTONOMOUS (mode %u): leg %u dropped, %s", static_cast<unsigned>(mode),
                   static_cast<unsigned>(legId), moving ? "rover stopped" : "rover already stopped");
}

void LegEvents::held(std::uint32_t reasons, std::uint32_t legId, bool moving) {
    events_.report(events::kMissionHeld, core::Severity::kWarning,
                   "habitual: mission held (reasons 0x%x): %s, leg %u kept", static_cast<unsigned>(reasons),
                   moving ? "rover stopped" : "nothing under way", static_cast<unsigned>(legId));
}

void LegEvents::released(std::uint32_t resumeCount, std::uint32_t legId, bool driving) {
    events_.report(events::kMissionReleased, core::Severity::kInfo, "habitual: hold released (resume %u): leg %u %s",
                   static_cast<unsigned>(resumeCount), static_cast<unsigned>(legId),
                   driving ? "waits for the re-sent leg" : "goes on");
}

void LegEvents::poseNotReady(std::uint32_t legId, std::uint32_t waits) {
    if (core::isReportableOccurrence(waits)) {
        events_.report(events::kPoseNotReady, core::Severity::kWarning,
                       "habitual: leg %u waits: no fresh initialised pose (%u runs so far)",
                       static_cast<unsigned>(legId), static_cast<unsigned>(waits));
    }
}

void LegEvents::achieved(const msg::LegCommandMsg& leg, Point2 at, double drivenLengthM, double drivenEnergyJ) {
    cmdtlm::event_data::LEG_ACHIEVED data;
    data.leg_id = leg.legId;
    data.x = at.x;
    data.y = at.y;
    data.driven_length = drivenLengthM;
    data.driven_energy = drivenEnergyJ;
    events_.report(events::kLegAchieved, core::Severity::kInfo, data.pack(),
                   "habitual: leg %u achieved at (%.2f, %.2f): %.1f m, %.0f J driven", static_cast<unsigned>(leg.legId),
                   at.x, at.y, drivenLengthM, drivenEnergyJ);
}

void LegEvents::achievedInside(const msg::LegCommandMsg& leg, Point2 at, double arrivalM) {
    cmdtlm::event_data::LEG_ACHIEVED data;  // nothing driven on the leg
    data.leg_id = leg.legId;
    data.x = at.x;
    data.y = at.y;
    events_.report(events::kLegAchieved, core::Severity::kInfo, data.pack(),
                   "habitual: leg %u achieved at (%.2f, %.2f): already within %.2f m of (%.2f, %.2f)",
                   static_cast<unsigned>(leg.legId), at.x, at.y, arrivalM, leg.goalXM, leg.goalYM);
}

void LegEvents::planSent(std::uint32_t legId, std::uint32_t trajectoryId, std::size_t points, const Evaluation& plan,
                         bool marginCut) {
    events_.report(events::kPlanSent, core::Severity::kInfo,
                   "habitual: leg %u trajectory %u: %u pts, %.1f/%.1f m, %.0f/%.0f J%s", static_cast<unsigned>(legId),
                   static_cast<unsigned>(trajectoryId), static_cast<unsigned>(points), plan.lengthM,
                   plan.allowedLengthM, plan.energyJ, plan.allowedEnergyJ, marginCut ? ", margin cut" : "");
}

void LegEvents::minorAnomaly(std::uint32_t legId, PlanTrigger trigger, std::uint8_t attempt) {
    cmdtlm::event_data::MINOR_ANOMALY data;
    data.leg_id = legId;
    data.trigger = static_cast<double>(trigger);
    data.run = attempt;
    events_.report(events::kMinorAnomaly, core::Severity::kWarning, data.pack(),
                   "habitual: leg %u replanned (%s, run %u): constraints hold: minor anomaly",
                   static_cast<unsigned>(legId), triggerName(trigger), static_cast<unsigned>(attempt));
}

void LegEvents::repair(std::uint32_t legId, std::size_t points, const Evaluation& plan, unsigned attempt,
                       unsigned last) {
    if (points >= 2) {
        events_.report(events::kRepairAttempt, core::Severity::kInfo,
                       "habitual: leg %u: plan %.1f m %.0f J violates %s by %.1f: repair %u of %u",
                       static_cast<unsigned>(legId), plan.lengthM, plan.energyJ, constraintName(plan.violated),
                       plan.excess, attempt, last);
    } else {
        events_.report(events::kRepairAttempt, core::Severity::kInfo,
                       "habitual: leg %u: no path found: repair %u of %u", static_cast<unsigned>(legId), attempt, last);
    }
}

void LegEvents::energyRepair(std::uint32_t legId, const Evaluation& remaining, double excessJ, unsigned last) {
    events_.report(events::kRepairAttempt, core::Severity::kInfo,
                   "habitual: leg %u: remaining path %.1f m %.0f J violates energy by %.0f: repair 1 of %u",
                   static_cast<unsigned>(legId), remaining.lengthM, remaining.energyJ, excessJ, last);
}

void LegEvents::escape(std::uint32_t legId, bool offSite, Point2 from, Point2 to, std::uint32_t escapes) {
    events_.report(events::kEscape, core::Severity::kWarning,
                   "habitual: leg %u: %s at (%.2f, %.2f): out %.2f m to (%.2f, %.2f) (%u of %u)",
                   static_cast<unsigned>(legId), offSite ? "off the site" : "in a hazard disc", from.x, from.y,
                   distance(from, to), to.x, to.y, static_cast<unsigned>(escapes),
                   static_cast<unsigned>(kMaxEscapesPerLeg));
}

void LegEvents::failUp(const msg::LegCommandMsg& leg, msg::LegConstraint reason, const Evaluation& figures,
                       unsigned noPathRuns, double powerFactor) {
    const unsigned legId = static_cast<unsigned>(leg.legId);
    cmdtlm::event_data::HABITUAL_FAIL_UP data;
    data.leg_id = legId;
    data.constraint = static_cast<double>(reason);
    switch (reason) {
        case msg::LegConstraint::kPathLength:
            data.predicted = figures.lengthM;
            data.allowed = figures.allowedLengthM;
            data.excess = figures.excess;
            events_.report(events::kFailUp, core::Severity::kError, data.pack(),
                           "habitual: leg %u fail-up: path length %.1f m > allowed %.1f m by %.1f m", legId,
                           figures.lengthM, figures.allowedLengthM, figures.excess);
            break;
        case msg::LegConstraint::kEnergy:
            data.predicted = figures.energyJ;
            data.allowed = figures.allowedEnergyJ;
            data.excess = figures.excess;
            events_.report(events::kFailUp, core::Severity::kError, data.pack(),
                           "habitual: leg %u fail-up: energy %.0f J > allowed %.0f J by %.0f J", legId, figures.energyJ,
                           figures.allowedEnergyJ, figures.excess);
            break;
        case msg::LegConstraint::kNoPath:
            data.planning_runs = noPathRuns;
            events_.report(events::kFailUp, core::Severity::kError, data.pack(),
                           "habitual: leg %u fail-up: no path to (%.2f, %.2f) in %u planning runs", legId, leg.goalXM,
                           leg.goalYM, noPathRuns);
            break;
        case msg::LegConstraint::kPower:
            data.predicted = figures.powerW;
            data.allowed = figures.allowedPowerW;
            data.excess = figures.excess;
            data.power_factor = powerFactor;
            events_.report(events::kFailUp, core::Severity::kError, data.pack(),
                           "habitual: leg %u fail-up: power %.1f W > allowed %.1f W by %.1f W (power factor %.3f)",
                           legId, figures.powerW, figures.allowedPowerW, figures.excess, powerFactor);
            break;
        case msg::LegConstraint::kNone:
        case msg::LegConstraint::kCannotFollow:
        case msg::LegConstraint::kBadLeg:
            events_.report(events::kFailUp, core::Severity::kError, data.pack(), "habitual: leg %u fail-up: %s", legId,
                           constraintName(reason));
            break;
    }
}

}  // namespace rse::habitual
