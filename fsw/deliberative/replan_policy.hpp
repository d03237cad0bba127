// What the deliberative layer does when a leg or a plan does not work out
// (docs/deliberative.md, "Fail-ups" and "No plan within the risk bound"):
//
// - a fail-up (LegReportMsg kFailedUp, or a refused leg) on a leg's length or
//   energy: the violated bound grows by what the habitual layer predicted it
//   needs (x kBoundRelaxHeadroom) and the leg is resent, while the leg's total
//   growth stays within PLANNER.bound_relax_limit; on power: every leg's power
//   bound grows so, for the rest of the plan (the drives' power is the same on
//   every leg), within the same limit; otherwise (beyond the limit, no path,
//   cannot follow, leg refused) a replan;
// - a replan: at most PLANNER.replan_limit per goal, each a ReplanRequest (the
//   unfinished goals, the time, the position and covariance at the fail-up)
//   that the next plan starts from (refreshed from the pose when older than
//   kReplanMaxAgeNs); with the replans spent, a call home (kInsufficientPower
//   when it was energy or power, kReplansExhausted otherwise) unless the task
//   backs up first (BackUpManoeuvre, "no path" only);
// - no plan within the risk in force: the risk bound relaxed x kRiskRelaxStep,
//   at most to Delta x PLANNER.risk_relax_limit (and below kMaxRiskInForce);
//   at the limit, a call home (kNoPlanWithinRisk).
//
// Owns the goal's risk factor and replan count and the replan request; the
// bounds it grows are the LegSequencer's (it is told their growth so far and
// answers what to grow them by). Events 904, 909, 911. No bus; the table's
// limits come as arguments.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"

namespace rse::deliberative {

constexpr double kRiskRelaxStep = 10.0;       // each relaxation multiplies the risk bound by this
constexpr double kMaxRiskInForce = 0.49;      // the planner needs Delta < 0.5
constexpr double kBoundRelaxHeadroom = 1.05;  // a relaxed bound: what was predicted + 5 %
// A replan request's position older than this when planning starts is
// refreshed from the pose (the pose was stale at the fail-up, or the rover
// moved while planning waited for a usable pose).
constexpr core::TimeNs kReplanMaxAgeNs = 1000 * core::kNsPerMs;

// What a replan starts from: the unfinished goals, the time and the position.
struct ReplanRequest {
    core::TimeNs timeNs = 0;         // when the replan was asked for
    core::TimeNs poseTimeNs = 0;     // when the rover was at (xM, yM)
    double xM = 0.0, yM = 0.0, headingRad = 0.0;
    double cov[4] = {};              // (x, y) covariance at that time
    std::uint8_t firstGoal = 0;      // goals_[firstGoal .. firstGoal + unfinished) remain
    std::uint8_t unfinished = 0;
    msg::LegConstraint why = msg::LegConstraint::kNone;
    bool pending = false;            // consumed when the plan starts
};

// Where the mission stands when a replan is asked for.
struct ReplanFrom {
    core::TimeNs now = 0;
    const msg::PoseEstimateMsg* pose = nullptr;  // the latest estimate
    std::uint8_t goalIndex = 0;                  // the goal in hand, in the list given
    std::uint8_t goalCount = 0;
    std::uint8_t seenHazards = 0;                // for event 911
    // Site mode: hazards were seen since the plan in force was started (the
    // known-hazard revision moved): the replan has new knowledge to plan with,
    // so it is not one of replan_limit's (at most kMaxInformedReplans a plan's).
    bool informed = false;
};

// Replans with new sightings a goal (site mode: a horizon) may take beyond
// replan_limit: each follows new knowledge, and this bounds them all the same
// (a disc that grows at every sighting moves the revision every time).
constexpr std::uint32_t kMaxInformedReplans = 8;

// Where a plan starts: a mean and its (x, y) covariance, row major.
struct StartPoint {
    double xM = 0.0;
    double yM = 0.0;
    double cov[4] = {};
};

// The answer to a fail-up.
struct FailUpAnswer {
    enum class Action : std::uint8_t {
        kReplan,      // replan (the bounds cannot grow enough)
        kRelaxPower,  // every leg's power bound grows to `grown` x planned; the leg resent
        kRelaxBound,  // the violated bound of the leg grows x `needed`; the leg resent
    };
    Action action = Action::kReplan;
    double needed = 1.0;  // this growth: predicted / allowed x kBoundRelaxHeadroom
    double grown = 1.0;   // the total growth it makes (the leg's, or the plan's power bound's)
    double limit = 1.0;   // PLANNER.bound_relax_limit
};

class ReplanPolicy {
public:
    explicit ReplanPolicy(core::EventLog& events) : events_(events) {}

    // A new goal list: risk factor 1, no replans, no replan pending.
    void newGoals();
    // The next goal of the list: risk factor 1, no replans.
    void nextGoal();

    // The operator's bound x the goal's risk factor, below kMaxRiskInForce: what a plan uses.
    double riskInForce(double operatorBound) const;

    // A fail-up of the leg in force (event 909), the leg's bounds grown by
    // legGrowth so far and every leg's power bound by powerGrowth.
    FailUpAnswer answerFailUp(const msg::LegReportMsg& report, double legGrowth, double powerGrowth,
                              double boundRelaxLimit);

    // A replan of the goal in hand: true (counted, the request recorded,
    // event 911) while the goal has replans left of replanLimit; false when spent.
    bool replan(msg::LegConstraint why, const ReplanFrom& from, std::uint32_t replanLimit);
    // Records a replan request without counting it against the goal (a
    // back-up reached, off the map).
    void capture(msg::LegConstraint why, const ReplanFrom& from);
    // A replan not counted against the goal (fault protection's off-map
    // request): counted in PLAN's replans all the same.
    void countUnlimitedReplan() { ++replans_; }
    // Where the next plan starts: the pending request's position (refreshed
    // from pose when older than kReplanMaxAgeNs at now), else the pose. The
    // request is consumed.
    StartPoint takeStart(core::TimeNs now, const msg::PoseEstimateMsg& pose);

    // No plan within plannedRisk: true when the risk factor could grow (event
    // 904), false at riskRelaxLimit (PLANNER.risk_relax_limit) or the cap.
    bool relaxRisk(double plannedRisk, double operatorBound, double riskRelaxLimit);

    // Why to call home when the replans are spent on a fail-up of `why`.
    static msg::CallHomeReason exhaustedReason(msg::LegConstraint why);

    const ReplanRequest& request() const { return request_; }
    std::uint32_t goalReplans() const { return goalReplans_; }
    double riskFactor() const { return riskFactor_; }
    std::uint32_t replans() const { return replans_; }
    std::uint32_t riskRelaxations() const { return riskRelaxations_; }
    std::uint32_t boundRelaxations() const { return boundRelaxations_; }
    std::uint32_t powerRelaxations() const { return powerRelaxations_; }

private:
    core::EventLog& events_;
    double riskFactor_ = 1.0;        // risk in force = Delta x riskFactor_
    std::uint32_t goalReplans_ = 0;  // replans of the current goal (counted against replan_limit)
    std::uint32_t goalInformedReplans_ = 0;  // ... with new sightings (site mode; at most kMaxInformedReplans)
    ReplanRequest request_{};
    std::uint32_t replans_ = 0;
    std::uint32_t riskRelaxations_ = 0;
    std::uint32_t boundRelaxations_ = 0;  // power relaxations included
    std::uint32_t powerRelaxations_ = 0;
};

// Names for the events.
const char* constraintName(msg::LegConstraint c);
const char* callHomeReasonName(msg::CallHomeReason r);

}  // namespace rse::deliberative
