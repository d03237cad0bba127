#include "fsw/deliberative/horizon_look_ahead.hpp"

#include <cmath>

#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

std::size_t HorizonLookAhead::stepsToGo(const CcPlan& plan, geometry::Point2 at) {
    const std::size_t n = plan.steps <= kMaxPlanSteps ? plan.steps : kMaxPlanSteps;
    std::size_t nearest = 0;
    double best = INFINITY;
    for (std::size_t t = 0; t <= n; ++t) {
        const double d = geometry::distanceSquared(at, geometry::Point2{plan.meanX[t], plan.meanY[t]});
        if (d < best) {
            best = d;
            nearest = t;
        }
    }
    const std::size_t steps = n - nearest + 1;
    return steps < n ? steps : n;
}

void HorizonLookAhead::startCovariance(const double poseCov[4], std::size_t steps, double sigmaM, double out[4]) {
    const double growth = static_cast<double>(steps) * sigmaM * sigmaM;
    out[0] = poseCov[0] + growth;
    out[1] = poseCov[1];
    out[2] = poseCov[2];
    out[3] = poseCov[3] + growth;
}

void HorizonLookAhead::begin(geometry::Point2 from, double startSigmaM, std::size_t steps,
                             std::size_t progressBefore, std::uint32_t hazardRevision, std::uint32_t siteRevision,
                             double riskBound) {
    state_ = State::kPlanning;
    hazardRevision_ = hazardRevision;
    siteRevision_ = siteRevision;
    progressBefore_ = progressBefore;
    riskBound_ = riskBound;
    ++counters_.started;
    if (restarts_ > 0) {
        return;   // planned again after a sighting: told once, at the handover (event 997)
    }
    events_.report(events::kLookAheadStarted, core::Severity::kInfo,
                   "deliberative: look-ahead to (%.1f, %.1f) from this horizon's end (%.1f, %.1f), sigma0 %.2f m, %u steps",
                   next_.goal.x, next_.goal.y, from.x, from.y, startSigmaM, static_cast<unsigned>(steps));
}

Handover HorizonLookAhead::handover(geometry::Point2 at, std::uint32_t hazardRevision, std::uint32_t siteRevision,
                                    bool planFound) {
    const State was = state_;
    const bool isStale = active() && stale(hazardRevision, siteRevision);
    state_ = State::kNone;
    const unsigned tries = restarts_ + (was == State::kNone || was == State::kRefused ? 0U : 1U);
    restarts_ = 0;
    if (was == State::kPlanned && planFound && !isStale) {
        ++counters_.handedOver;
        events_.report(events::kHorizonEnd, core::Severity::kInfo,
                       "deliberative: horizon end (%.1f, %.1f): driven through, the next planned ahead (%u tries)",
                       at.x, at.y, tries);
        return Handover::kTake;
    }
    if (was == State::kPlanning && !isStale) {
        ++counters_.finishedStopped;
        events_.report(events::kHorizonEnd, core::Severity::kInfo,
                       "deliberative: horizon end (%.1f, %.1f): stopped while its look-ahead finishes (%u tries)",
                       at.x, at.y, tries);
        return Handover::kFinish;
    }
    ++counters_.fromPose;
    if (isStale) {
        ++counters_.dropped;
        ++counters_.stale;
    }
    const char* why = isStale                    ? "look-ahead stale"
                      : was == State::kPlanned   ? "look-ahead found no plan"
                      : was == State::kRefused   ? "look-ahead refused"
                                                 : "no look-ahead";
    events_.report(events::kHorizonEnd, core::Severity::kInfo,
                   "deliberative: horizon end (%.1f, %.1f): stopped, the next planned from here (%s)", at.x, at.y,
                   why);
    return Handover::kPlanFromPose;
}

bool HorizonLookAhead::drop(const char* why, bool isStale, std::size_t* progressBefore) {
    if (!active()) {
        state_ = State::kNone;
        return false;
    }
    state_ = State::kNone;
    *progressBefore = progressBefore_;
    ++counters_.dropped;
    if (isStale) {
        // Planned again at once: counted, and told at the handover.
        ++counters_.stale;
        ++restarts_;
        return true;
    }
    restarts_ = 0;
    events_.report(events::kLookAheadDropped, core::Severity::kInfo,
                   "deliberative: look-ahead to (%.2f, %.2f) dropped: %s", next_.goal.x, next_.goal.y, why);
    return true;
}

}  // namespace rse::deliberative
