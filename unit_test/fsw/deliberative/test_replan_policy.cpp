// What the layer does when a leg or a plan does not work out
// (replan_policy.hpp): bound relaxation or replan, the replan limit and the
// call-home reason, the replan request and where the next plan starts, and
// the risk relaxation.
#include <cmath>

#include "fsw/core/clock.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/replan_policy.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::FailUpAnswer;
using deliberative::kBoundRelaxHeadroom;
using deliberative::ReplanFrom;
using deliberative::ReplanPolicy;
using msg::LegConstraint;
namespace ev = rse::deliberative::events;

namespace {

msg::LegReportMsg failUp(LegConstraint violated, double predicted, double allowed) {
    msg::LegReportMsg r{};
    r.legId = 7;
    r.state = msg::HabitualState::kFailedUp;
    r.violated = violated;
    if (violated == LegConstraint::kEnergy) {
        r.predictedEnergyJ = predicted;
        r.allowedEnergyJ = allowed;
    } else if (violated == LegConstraint::kPower) {
        r.predictedPowerW = predicted;
        r.allowedPowerW = allowed;
    } else {
        r.predictedLengthM = predicted;
        r.allowedLengthM = allowed;
    }
    r.excess = predicted - allowed;
    return r;
}

msg::PoseEstimateMsg poseAt(double x, double y, core::TimeNs t) {
    msg::PoseEstimateMsg p{};
    p.timeNs = t;
    p.xM = x;
    p.yM = y;
    p.headingRad = 0.5;
    p.covariance[0] = 0.01;
    p.covariance[1] = 0.002;
    p.covariance[3] = 0.003;
    p.covariance[4] = 0.04;
    p.initialised = 1;
    return p;
}

}  // namespace

TEST_GROUP(ReplanPolicy) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventRecord seen{events};
    ReplanPolicy policy{events};
    msg::PoseEstimateMsg pose = poseAt(3.0, 4.0, 10 * core::kNsPerSec);

    ReplanFrom from(core::TimeNs now, std::uint8_t goalIndex = 1, std::uint8_t goalCount = 3) {
        ReplanFrom f;
        f.now = now;
        f.pose = &pose;
        f.goalIndex = goalIndex;
        f.goalCount = goalCount;
        f.seenHazards = 2;
        return f;
    }
};

TEST(ReplanPolicy, AnEnergyOrLengthFailUpWithinTheLimitGrowsTheBoundByWhatWasPredicted) {
    const FailUpAnswer a = policy.answerFailUp(failUp(LegConstraint::kEnergy, 120.0, 100.0), 1.0, 1.0, 1.5);
    CHECK(FailUpAnswer::Action::kRelaxBound == a.action);
    DOUBLES_EQUAL(1.2 * kBoundRelaxHeadroom, a.needed, 1e-12);
    DOUBLES_EQUAL(1.2 * kBoundRelaxHeadroom, a.grown, 1e-12);
    DOUBLES_EQUAL(1.5, a.limit, 0.0);
    LONGS_EQUAL(1, policy.boundRelaxations());
    LONGS_EQUAL(0, policy.powerRelaxations());
    LONGS_EQUAL(1, seen.count(ev::kFailUpReceived));
    CHECK_TRUE(seen.textHas(ev::kFailUpReceived, "leg 7 failed up: energy (predicted 120.0, allowed 100.0"));
    // The leg's growth so far counts against the limit.
    const FailUpAnswer b = policy.answerFailUp(failUp(LegConstraint::kPathLength, 12.0, 10.0), 1.3, 1.0, 1.5);
    CHECK(FailUpAnswer::Action::kReplan == b.action);
    LONGS_EQUAL(1, policy.boundRelaxations());
}

TEST(ReplanPolicy, APowerFailUpGrowsThePlansPowerBoundAgainstItsOwnGrowth) {
    const FailUpAnswer a = policy.answerFailUp(failUp(LegConstraint::kPower, 110.0, 100.0), 1.4, 1.2, 1.5);
    CHECK(FailUpAnswer::Action::kRelaxPower == a.action);
    DOUBLES_EQUAL(1.1 * kBoundRelaxHeadroom, a.needed, 1e-12);
    DOUBLES_EQUAL(1.2 * 1.1 * kBoundRelaxHeadroom, a.grown, 1e-12);
    LONGS_EQUAL(1, policy.boundRelaxations());
    LONGS_EQUAL(1, policy.powerRelaxations());
    const FailUpAnswer b = policy.answerFailUp(failUp(LegConstraint::kPower, 110.0, 100.0), 1.0, 1.4, 1.5);
    CHECK(FailUpAnswer::Action::kReplan == b.action);
}

TEST(ReplanPolicy, NoBoundGrowsForAPathFailUpOrAFigureThatNeedsNoGrowth) {
    const LegConstraint replans[] = {LegConstraint::kNoPath, LegConstraint::kCannotFollow, LegConstraint::kBadLeg};
    for (const LegConstraint c : replans) {
        CHECK(FailUpAnswer::Action::kReplan == policy.answerFailUp(failUp(c, 12.0, 10.0), 1.0, 1.0, 10.0).action);
    }
    // predicted within allowed x 1/1.05, a zero allowance, or no number.
    CHECK(FailUpAnswer::Action::kReplan ==
          policy.answerFailUp(failUp(LegConstraint::kEnergy, 90.0, 100.0), 1.0, 1.0, 10.0).action);
    CHECK(FailUpAnswer::Action::kReplan ==
          policy.answerFailUp(failUp(LegConstraint::kEnergy, 90.0, 0.0), 1.0, 1.0, 10.0).action);
    CHECK(FailUpAnswer::Action::kReplan ==
          policy.answerFailUp(failUp(LegConstraint::kPower, NAN, 100.0), 1.0, 1.0, 10.0).action);
    LONGS_EQUAL(0, policy.boundRelaxations());
    LONGS_EQUAL(6, seen.count(ev::kFailUpReceived));
}

TEST(ReplanPolicy, ReplansAreLimitedPerGoalAndEachRecordsWhereItStarts) {
    CHECK_TRUE(policy.replan(LegConstraint::kNoPath, from(68 * core::kNsPerSec), 2));
    const deliberative::ReplanRequest& rr = policy.request();
    CHECK_TRUE(rr.pending);
    DOUBLES_EQUAL(3.0, rr.xM, 0.0);
    DOUBLES_EQUAL(4.0, rr.yM, 0.0);
    DOUBLES_EQUAL(0.5, rr.headingRad, 0.0);
    DOUBLES_EQUAL(0.002, rr.cov[1], 0.0);
    DOUBLES_EQUAL(0.003, rr.cov[2], 0.0);
    DOUBLES_EQUAL(0.04, rr.cov[3], 0.0);
    LONGS_EQUAL(1, rr.firstGoal);
    LONGS_EQUAL(2, rr.unfinished);
    CHECK(LegConstraint::kNoPath == rr.why);
    STRCMP_EQUAL("deliberative: replan 1/2 (no path) t=68.00 s from (3.00, 4.00): goals 1..2 left, 2 hazards",
                 seen.text(ev::kReplan));
    CHECK_TRUE(policy.replan(LegConstraint::kEnergy, from(69 * core::kNsPerSec), 2));
    CHECK_FALSE(policy.replan(LegConstraint::kEnergy, from(70 * core::kNsPerSec), 2));
    LONGS_EQUAL(2, policy.replans());
    LONGS_EQUAL(2, policy.goalReplans());
    LONGS_EQUAL(2, seen.count(ev::kReplan));
    // An off-map replan counts in PLAN, not against the goal.
    policy.countUnlimitedReplan();
    LONGS_EQUAL(3, policy.replans());
    LONGS_EQUAL(2, policy.goalReplans());
    policy.nextGoal();
    LONGS_EQUAL(0, policy.goalReplans());
    CHECK_TRUE(policy.replan(LegConstraint::kNoPath, from(71 * core::kNsPerSec), 2));
}

TEST(ReplanPolicy, TheReplansSpentCallHomeForPowerOnAnEnergyOrPowerFailUp) {
    CHECK(msg::CallHomeReason::kInsufficientPower == ReplanPolicy::exhaustedReason(LegConstraint::kEnergy));
    CHECK(msg::CallHomeReason::kInsufficientPower == ReplanPolicy::exhaustedReason(LegConstraint::kPower));
    CHECK(msg::CallHomeReason::kReplansExhausted == ReplanPolicy::exhaustedReason(LegConstraint::kNoPath));
    CHECK(msg::CallHomeReason::kReplansExhausted == ReplanPolicy::exhaustedReason(LegConstraint::kPathLength));
}

TEST(ReplanPolicy, ThePlanStartsFromTheRequestOnceAndFromAFreshPoseWhenTheRequestIsStale) {
    const core::TimeNs t0 = 10 * core::kNsPerSec;
    // No request: the pose.
    const msg::PoseEstimateMsg here = poseAt(5.0, 6.0, t0);
    deliberative::StartPoint s = policy.takeStart(t0, here);
    DOUBLES_EQUAL(5.0, s.xM, 0.0);
    DOUBLES_EQUAL(0.04, s.cov[3], 0.0);
    // A request: its position, once.
    policy.capture(LegConstraint::kNone, from(t0));
    s = policy.takeStart(t0 + 500 * core::kNsPerMs, here);
    DOUBLES_EQUAL(3.0, s.xM, 0.0);
    DOUBLES_EQUAL(4.0, s.yM, 0.0);
    CHECK_FALSE(policy.request().pending);
    s = policy.takeStart(t0 + 600 * core::kNsPerMs, here);
    DOUBLES_EQUAL(5.0, s.xM, 0.0);
    // Older than kReplanMaxAgeNs: refreshed from the pose (and recorded so).
    policy.capture(LegConstraint::kNone, from(t0));
    const msg::PoseEstimateMsg later = poseAt(7.0, 8.0, t0 + 2 * core::kNsPerSec);
    s = policy.takeStart(t0 + deliberative::kReplanMaxAgeNs + 1, later);
    DOUBLES_EQUAL(7.0, s.xM, 0.0);
    DOUBLES_EQUAL(7.0, policy.request().xM, 0.0);
    // A new goal list drops a pending request.
    policy.capture(LegConstraint::kNone, from(t0));
    policy.newGoals();
    s = policy.takeStart(t0, here);
    DOUBLES_EQUAL(5.0, s.xM, 0.0);
}

TEST(ReplanPolicy, NoPlanRelaxesTheRiskTenfoldUpToTheLimitAndBelowTheCap) {
    DOUBLES_EQUAL(1e-3, policy.riskInForce(1e-3), 0.0);
    CHECK_TRUE(policy.relaxRisk(1e-3, 1e-3, 10.0));
    DOUBLES_EQUAL(1e-2, policy.riskInForce(1e-3), 1e-15);
    STRCMP_EQUAL("deliberative: risk bound relaxed to 0.01 (the operator's 0.001 x10, limit x10)",
                 seen.text(ev::kRiskRelaxed));
    CHECK_FALSE(policy.relaxRisk(1e-2, 1e-3, 10.0));  // at the limit
    LONGS_EQUAL(1, policy.riskRelaxations());
    // A limit between steps is reached exactly; the cap below 0.5 is named.
    policy.nextGoal();
    CHECK_TRUE(policy.relaxRisk(0.1, 0.1, 4.9));
    DOUBLES_EQUAL(deliberative::kMaxRiskInForce, policy.riskInForce(0.1), 0.0);
    CHECK_TRUE(seen.textHas(ev::kRiskRelaxed, "relaxed to 0.49 (the operator's 0.1 x4.9, capped below 0.5"));
    CHECK_FALSE(policy.relaxRisk(deliberative::kMaxRiskInForce, 0.1, 100.0));  // already at the cap
    policy.newGoals();
    DOUBLES_EQUAL(1.0, policy.riskFactor(), 0.0);
}

TEST(ReplanPolicy, ConstraintsAndReasonsHaveNames) {
    STRCMP_EQUAL("path length", deliberative::constraintName(LegConstraint::kPathLength));
    STRCMP_EQUAL("leg refused", deliberative::constraintName(LegConstraint::kBadLeg));
    STRCMP_EQUAL("?", deliberative::constraintName(static_cast<LegConstraint>(99)));
    STRCMP_EQUAL("mobility lost", deliberative::callHomeReasonName(msg::CallHomeReason::kMobilityLost));
    STRCMP_EQUAL("?", deliberative::callHomeReasonName(static_cast<msg::CallHomeReason>(99)));
}
