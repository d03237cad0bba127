// Site mode's receding horizon (docs/deliberative.md, "Site mode"): the next
// horizon is planned while the rover drives the end of the current one, so
// that a horizon's end is a leg end like any other and the rover does not
// stop there to plan.
//
// - When (the task asks due()): the plan in hand is a horizon short of the
//   goal, its last leg is in force or the rover is within PLANNER.site_look_ahead_m of
//   its end, nothing holds the mission, no back-up, the pose usable. One
//   look-ahead at a time, started again when it goes stale.
// - From: the horizon's end (the plan's last mean, where its last leg ends),
//   with the covariance the planner's model gives the rover there: the pose's
//   now plus k sigma^2 I for the k steps of the plan in hand still to drive
//   (stepsToGo: one more than from the nearest mean), so the two plans are one
//   open-loop model and the look-ahead's certified risk holds for the rover
//   arriving there as that model predicts. The risk: the operator's, not
//   relaxed (a horizon's relaxations are its own).
// - Stale: the seen hazards changed since it started (the habitual layer's
//   revision moved: a disc new, refined or forgotten) or the site map was
//   replaced: dropped, and planned again (the task starts it anew in the same
//   run). Taken, a look-ahead's plan was therefore made with everything the
//   rover knows at the handover, as a plan made there would be. In a boulder
//   field the revision moves every second or so while the next horizon's
//   rocks come into view, so a look-ahead is often planned several times,
//   each within the task's slice; one still planning at the handover is
//   finished with the rover stopped (as a plan from the pose would be).
//   Events: 995 when a horizon's look-ahead first starts, 996 when one is
//   dropped for good (a replan, new goals, ...), 997 at each horizon's end
//   with what happened and how often it was planned again.
// - Handover (the horizon's last leg reached): a finished look-ahead is taken
//   (kTake: the task finishes its plan and sends the first leg in the same
//   run; a look-ahead that found no plan falls back to a plan from the pose);
//   one still planning is finished with the rover stopped at the horizon's
//   end (kFinish); none (a short last leg, a hold, a drop): the next horizon is
//   planned from the pose as before (kPlanFromPose). Event 997 says which;
//   LookAheadCounters and PLAN telemetry count them.
// - Dropped (drop()): a fail-up's replan, a back-up, a new goal list, leaving
//   AUTONOMOUS, an off-map replan, a call home, a stale look-ahead: the task
//   puts back the route progress the look-ahead moved (progressBefore), so a
//   replan's horizon is the one it would have been without it.
//
// Owns no planner: the task's PlanMaker plans the look-ahead (one plan at a
// time: a replan of the horizon in hand drops it). Static: the next horizon
// is a member (about 0.5 KB). Events 995,
// 996, 997.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/deliberative/route_horizons.hpp"
#include "fsw/geometry/geometry2d.hpp"

namespace rse::deliberative {

enum class Handover : std::uint8_t {
    kTake,          // a finished look-ahead: its plan, the first leg sent at once
    kFinish,        // still planning: finished with the rover stopped at the end
    kPlanFromPose,  // none: the next horizon planned from the pose (the rover stops)
};

struct LookAheadCounters {
    std::uint32_t started = 0;         // look-aheads begun (event 995)
    std::uint32_t dropped = 0;         // ... dropped before their handover (event 996)
    std::uint32_t stale = 0;           // ... of them stale: the seen hazards or the site map changed
    std::uint32_t handedOver = 0;      // horizon ends driven through: the look-ahead finished in time
    std::uint32_t finishedStopped = 0; // ... the rover stopped while the look-ahead finished
    std::uint32_t fromPose = 0;        // ... no look-ahead: planned from the pose (a stop)
};

class HorizonLookAhead {
public:
    explicit HorizonLookAhead(core::EventLog& events) : events_(events) {}

    // The rover at distanceToEndM of the horizon's end, lastLeg: the plan's
    // last leg is in force; startM: PLANNER.site_look_ahead_m (0: never; 10 m
    // by default, about 45 s of driving at the demo's pace: room for a plan
    // and its restarts, and about 8 open-loop steps of growth in its start
    // covariance). The task checks the rest (site mode, a horizon short of
    // the goal, no hold, no back-up, a usable pose).
    bool due(double distanceToEndM, bool lastLeg, double startM) const {
        return state_ == State::kNone && startM > 0.0 && (lastLeg || distanceToEndM <= startM);
    }

    // Steps of plan still to drive from `at`: N - t for its mean t nearest
    // `at`, plus one for the step the rover is in (at most N).
    static std::size_t stepsToGo(const CcPlan& plan, geometry::Point2 at);
    // The start covariance at the horizon's end (row major): the pose's
    // (x, y) block plus stepsToGo x sigma^2 on the diagonal.
    static void startCovariance(const double poseCov[4], std::size_t steps, double sigmaM, double out[4]);

    // The look-ahead to horizonSlot() (filled by RouteHorizons::next) has
    // started from `from` (event 995). progressBefore: the route progress
    // before next() moved it; hazardRevision, siteRevision: what its problem holds.
    void begin(geometry::Point2 from, double startSigmaM, std::size_t steps, std::size_t progressBefore,
               std::uint32_t hazardRevision, std::uint32_t siteRevision, double riskBound);
    // Its planning has ended (the plan maker's step returned true).
    void planned() { state_ = state_ == State::kPlanning ? State::kPlanned : state_; }
    // Stale against what the rover knows now (see the header).
    bool stale(std::uint32_t hazardRevision, std::uint32_t siteRevision) const {
        return hazardRevision != hazardRevision_ || siteRevision != siteRevision_;
    }
    // The horizon's last leg reached: what to do (event 997; counted). The
    // look-ahead is spent either way (kTake / kFinish: its horizon is the task's).
    // planFound: the finished look-ahead has a path (PlanMaker::hasCandidatePath);
    // one without is no look-ahead.
    Handover handover(geometry::Point2 at, std::uint32_t hazardRevision, std::uint32_t siteRevision,
                      bool planFound);
    // Its plan could not be started (the plan maker refused the problem):
    // none this horizon; the horizon's end plans from the pose.
    void refused() { state_ = State::kRefused; }
    // Dropped before its handover (event 996, why; a stale one is only
    // counted, as it is planned again at once, and event 997 says how often):
    // true when there was one, with *progressBefore the route progress to put back.
    bool drop(const char* why, bool isStale, std::size_t* progressBefore);

    bool active() const { return state_ == State::kPlanning || state_ == State::kPlanned; }
    bool planning() const { return state_ == State::kPlanning; }
    // The next horizon: filled by the task before begin(), kept while the
    // plan maker plans it (its corridor is the problem's).
    const Horizon& horizon() const { return next_; }
    Horizon* horizonSlot() { return &next_; }
    std::uint32_t hazardRevision() const { return hazardRevision_; }
    // The route progress before the look-ahead's next() moved it.
    std::size_t progressBefore() const { return progressBefore_; }
    double riskBound() const { return riskBound_; }
    const LookAheadCounters& counters() const { return counters_; }

private:
    enum class State : std::uint8_t { kNone, kPlanning, kPlanned, kRefused };

    core::EventLog& events_;
    State state_ = State::kNone;
    Horizon next_{};
    std::uint32_t hazardRevision_ = 0;  // the seen hazards its problem holds
    std::uint32_t siteRevision_ = 0;
    std::size_t progressBefore_ = 0;
    double riskBound_ = 0.0;
    unsigned restarts_ = 0;   // stale drops since this horizon's first look-ahead (event 997 tells them)
    LookAheadCounters counters_{};
};

}  // namespace rse::deliberative
