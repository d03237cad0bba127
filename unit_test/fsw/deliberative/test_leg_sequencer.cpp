// The plan's legs and the leg in force (leg_sequencer.hpp): sending one leg at
// a time with new ids, the goal's region on its last leg, holds, leg ends merged
// past a seen hazard, relaxations kept on a re-send, the back-up leg, and
// claiming the goal only from a certain pose.
#include <cmath>

#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/leg_sequencer.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::FailUpAnswer;
using deliberative::GoalArrival;
using deliberative::GoalClaim;
using deliberative::LegEndClearance;
using deliberative::LegSequencer;
namespace ev = rse::deliberative::events;

namespace {

// A straight plan (0, 0) -> (18, 0) in 3 steps: legs of 6 m at spacing 6.
deliberative::CcPlan straightPlan() {
    deliberative::CcPlan p{};
    p.status = deliberative::CcStatus::kOptimal;
    p.steps = 3;
    for (std::size_t t = 0; t <= 3; ++t) {
        p.meanX[t] = 6.0 * static_cast<double>(t);
    }
    for (std::size_t t = 0; t < 3; ++t) {
        p.segmentRisk[t] = 1e-4;
        p.riskUsed += 1e-4;
    }
    return p;
}

deliberative::LegParams params(double heading = 0.0) {
    deliberative::LegParams lp;
    lp.spacingM = 6.0;
    lp.power = rover_model::PowerModel{940.0, 1370.0, 4.5};
    lp.meanPowerFactor = 1.0;
    lp.headingRad = heading;
    return lp;
}

msg::PoseEstimateMsg poseAt(double x, double y, double sigma = 0.1) {
    msg::PoseEstimateMsg p{};
    p.xM = x;
    p.yM = y;
    p.initialised = 1;
    p.positionSigmaM = sigma;
    return p;
}

tables::CoarseMapTable openSite() {
    tables::CoarseMapTable map{};
    map.x_min_m = -50.0F;
    map.x_max_m = 50.0F;
    map.y_min_m = -50.0F;
    map.y_max_m = 50.0F;
    return map;
}

}  // namespace

TEST_GROUP(LegSequencer) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::EventRecord seen{events};
    deliberative::Publisher out{bus, events};
    LegSequencer legs{events, out};
    tables::CoarseMapTable map = openSite();
    msg::KnownHazardsMsg hazards{};
    LegEndClearance clear{map, 0.6, hazards};
    core::PipeId probe = 0;
    msg::Goal goal{};

    void setup() override {
        CHECK(core::isOk(bus.createPipe("probe", 16, &probe)));
        CHECK(core::isOk(bus.subscribe(probe, msg::ids::kLegCommand)));
        CHECK_TRUE(legs.split(straightPlan(), params()));
        legs.begin();
        goal.xM = 18.0;
    }
    // The legs published since the last call: how many, the latest in *last.
    unsigned published(msg::LegCommandMsg* last) {
        unsigned n = 0;
        core::Message m;
        while (core::isOk(bus.receive(probe, &m))) {
            CHECK(core::isOk(m.decode(last)));
            ++n;
        }
        return n;
    }
    GoalArrival arrival(const msg::PoseEstimateMsg& pose, bool uncertain, double arrivalM = 0.5) {
        GoalArrival a;
        a.goal = &goal;
        a.number = 2;
        a.arrivalM = arrivalM;
        a.pose = &pose;
        a.poseUncertain = uncertain;
        return a;
    }
};

TEST(LegSequencer, LegsGoOutOneAtATimeWithNewIdsAndOnlyTheLastCarriesTheGoalsRegion) {
    LONGS_EQUAL(3, legs.legs().count);
    msg::LegCommandMsg leg{};
    legs.send(100, false, 2.5, clear);
    LONGS_EQUAL(1, published(&leg));
    LONGS_EQUAL(1, leg.legId);
    LONGS_EQUAL(0, leg.finalLeg);
    DOUBLES_EQUAL(6.0, leg.goalXM, 1e-12);
    DOUBLES_EQUAL(0.0, leg.arriveWithinM, 0.0);
    DOUBLES_EQUAL(legs.legs().legs[0].powerW, leg.maxPowerW, 0.0);
    LONGS_EQUAL(1, legs.legInForce().legId);
    CHECK_TRUE(seen.textHas(ev::kLegSent, "leg 1 (1 of 3) to (6.00, 0.00)"));
    CHECK_TRUE(legs.achieved());
    LONGS_EQUAL(0, legs.legInForce().legId);
    CHECK_TRUE(seen.textHas(ev::kLegAchieved, "leg 1 reached (1 of 3)"));
    legs.send(200, false, 2.5, clear);
    CHECK_TRUE(legs.achieved());
    legs.send(300, false, 2.5, clear);
    LONGS_EQUAL(2, published(&leg));
    LONGS_EQUAL(3, leg.legId);
    LONGS_EQUAL(1, leg.finalLeg);
    DOUBLES_EQUAL(2.5, leg.arriveWithinM, 0.0);
    CHECK_FALSE(legs.achieved());
    LONGS_EQUAL(3, legs.counters().legsSent);
    LONGS_EQUAL(3, legs.counters().legsAchieved);
}

TEST(LegSequencer, DuringAHoldNoLegGoesOutAndTheLegInForceIsCleared) {
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    legs.send(200, true, 0.0, clear);
    LONGS_EQUAL(1, published(&leg));
    LONGS_EQUAL(0, legs.legInForce().legId);
    LONGS_EQUAL(1, legs.counters().legsSent);
    CHECK_TRUE(legs.legToDrive());
}

TEST(LegSequencer, ACancelIsLegIdZero) {
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    legs.cancel(150);
    LONGS_EQUAL(2, published(&leg));
    LONGS_EQUAL(0, leg.legId);
    LONGS_EQUAL(150, leg.timeNs);
    LONGS_EQUAL(0, legs.legInForce().legId);
}

TEST(LegSequencer, ALegEndNearASeenHazardIsMergedIntoTheNextButNeverTheLast) {
    hazards.count = 2;
    hazards.hazards[0] = msg::KnownHazard{6.2F, 0.5F, 0.4F, 1, {}};
    hazards.hazards[1] = msg::KnownHazard{18.0F, 0.5F, 0.4F, 2, {}};
    CHECK_TRUE(legs.legEndTooClose(clear));
    const double first = legs.legs().legs[0].lengthM;
    const double second = legs.legs().legs[1].lengthM;
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    LONGS_EQUAL(1, published(&leg));
    LONGS_EQUAL(1, legs.index());
    DOUBLES_EQUAL(12.0, leg.goalXM, 1e-12);
    DOUBLES_EQUAL(first + second, leg.maxPathLengthM, 1e-9);
    DOUBLES_EQUAL(12.0, legs.legs().plannedLengthM[1], 1e-9);
    LONGS_EQUAL(1, legs.counters().legEndsSkipped);
    CHECK_TRUE(seen.textHas(ev::kLegEndSkipped, "leg end (6.00, 0.00) too near a rock: merged into leg 2 of 3"));
    // The last leg ends at the goal, however near.
    CHECK_TRUE(legs.achieved());
    legs.send(200, false, 0.0, clear);
    LONGS_EQUAL(2, legs.index());
    CHECK_FALSE(legs.legEndTooClose(clear));
}

TEST(LegSequencer, ARelaxedBoundIsKeptWhenTheLegIsReSentFromThePose) {
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    FailUpAnswer energy;
    energy.action = FailUpAnswer::Action::kRelaxBound;
    energy.needed = 1.2;
    energy.grown = 1.2;
    energy.limit = 1.5;
    const double planned = legs.legs().legs[0].energyJ;
    legs.relax(energy, msg::LegConstraint::kEnergy);
    DOUBLES_EQUAL(planned * 1.2, legs.legs().legs[0].energyJ, 1e-9);
    DOUBLES_EQUAL(1.2, legs.legGrowth(), 0.0);
    CHECK_TRUE(seen.textHas(ev::kBoundRelaxed, "leg 1 energy bound relaxed x1.200 (x1.200 of planned"));
    // Re-sent from (2, 0): the bounds from there, the energy still x1.2.
    const msg::PoseEstimateMsg pose = poseAt(2.0, 0.0);
    CHECK_TRUE(legs.resendFromPose(200, false, 0.0, clear, pose, params()));
    (void)published(&leg);
    LONGS_EQUAL(2, leg.legId);
    msg::PlanLeg fresh = legs.legs().legs[0];
    CHECK(core::isOk(deliberative::legBoundsFrom(2.0, 0.0, 0.0, params(), &fresh)));
    DOUBLES_EQUAL(fresh.energyJ * 1.2, leg.maxEnergyJ, 1e-9);
    DOUBLES_EQUAL(fresh.lengthM, leg.maxPathLengthM, 1e-9);
    // Reached: the next leg starts unrelaxed.
    CHECK_TRUE(legs.achieved());
    DOUBLES_EQUAL(1.0, legs.legGrowth(), 0.0);
}

TEST(LegSequencer, ARelaxedPowerBoundHoldsForEveryLaterLegUntilTheNextPlan) {
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    FailUpAnswer power;
    power.action = FailUpAnswer::Action::kRelaxPower;
    power.needed = 1.1;
    power.grown = 1.1;
    power.limit = 1.5;
    legs.relax(power, msg::LegConstraint::kPower);
    CHECK_TRUE(seen.textHas(ev::kBoundRelaxed, "leg 1 power bound relaxed x1.100"));
    legs.dropLegInForce();
    legs.send(200, false, 0.0, clear);
    (void)published(&leg);
    const double planned = legs.legs().legs[0].powerW;
    DOUBLES_EQUAL(planned * 1.1, leg.maxPowerW, 1e-9);
    CHECK_TRUE(legs.achieved());
    legs.send(300, false, 0.0, clear);
    (void)published(&leg);
    DOUBLES_EQUAL(planned * 1.1, leg.maxPowerW, 1e-9);
    DOUBLES_EQUAL(1.1, legs.powerGrowth(), 0.0);
    legs.begin();
    DOUBLES_EQUAL(1.0, legs.powerGrowth(), 0.0);
    // A replan answer changes nothing.
    FailUpAnswer replan;
    legs.relax(replan, msg::LegConstraint::kNoPath);
    DOUBLES_EQUAL(1.0, legs.powerGrowth(), 0.0);
}

TEST(LegSequencer, ABackUpLegIsNotFinalHasBoundsFromThePoseAndThePlansPowerBound) {
    msg::LegCommandMsg leg{};
    legs.send(100, false, 0.0, clear);
    msg::PlanLeg target{};
    target.xM = -2.0;
    const msg::PoseEstimateMsg pose = poseAt(0.0, 0.0);
    legs.sendBackUp(200, false, &target, pose, params());
    LONGS_EQUAL(2, published(&leg));
    LONGS_EQUAL(2, leg.legId);
    LONGS_EQUAL(0, leg.finalLeg);
    DOUBLES_EQUAL(-2.0, leg.goalXM, 0.0);
    CHECK(target.lengthM > 2.0);
    DOUBLES_EQUAL(target.lengthM, leg.maxPathLengthM, 0.0);
    DOUBLES_EQUAL(legs.legs().legs[0].powerW, leg.maxPowerW, 0.0);
    CHECK_TRUE(seen.textHas(ev::kLegSent, "leg 2 (back-up) to (-2.00, 0.00)"));
    legs.sendBackUp(300, true, &target, pose, params());
    LONGS_EQUAL(0, published(&leg));
    LONGS_EQUAL(0, legs.legInForce().legId);
}

TEST(LegSequencer, AFirstLegFromTheReentryPointIsWidenedToTheBoundsFromTheRover) {
    const double planned = legs.legs().legs[0].lengthM;
    legs.widenFirstLeg(poseAt(-3.0, 0.0), params());
    CHECK(legs.legs().legs[0].lengthM > planned);
    const double widened = legs.legs().legs[0].lengthM;
    legs.widenFirstLeg(poseAt(5.0, 0.0), params());  // nearer: kept
    DOUBLES_EQUAL(widened, legs.legs().legs[0].lengthM, 0.0);
}

TEST(LegSequencer, TheGoalIsClaimedOnlyFromACertainPose) {
    const msg::PoseEstimateMsg unsure = poseAt(18.0, 0.0, 3.0);
    CHECK(GoalClaim::kUnconfirmed == legs.claimGoal(arrival(unsure, true)));
    CHECK(GoalClaim::kUnconfirmed == legs.claimGoal(arrival(unsure, true)));
    CHECK_TRUE(legs.goalUnconfirmed());
    CHECK_FALSE(legs.legToDrive());
    LONGS_EQUAL(1, legs.counters().goalsUnconfirmed);
    LONGS_EQUAL(1, seen.count(ev::kGoalUnconfirmed));
    CHECK_TRUE(seen.textHas(ev::kGoalUnconfirmed, "goal 2 (18.00, 0.00): last leg reached but the pose is uncertain"));
    CHECK(GoalClaim::kWaiting == legs.reclaimGoal(arrival(unsure, true)));
    const msg::PoseEstimateMsg sure = poseAt(18.2, 0.0);
    CHECK(GoalClaim::kReached == legs.reclaimGoal(arrival(sure, false)));
    CHECK_FALSE(legs.goalUnconfirmed());
    LONGS_EQUAL(1, legs.counters().goalsReached);
    STRCMP_EQUAL("deliberative: goal 2 (18.00, 0.00) reached", seen.text(ev::kGoalReached));
}

TEST(LegSequencer, ACertainPoseOffTheGoalReSendsTheLastLeg) {
    const msg::PoseEstimateMsg unsure = poseAt(16.0, 0.0, 3.0);
    CHECK(GoalClaim::kUnconfirmed == legs.claimGoal(arrival(unsure, true)));
    const msg::PoseEstimateMsg off = poseAt(16.0, 0.0);
    CHECK(GoalClaim::kResend == legs.reclaimGoal(arrival(off, false)));
    LONGS_EQUAL(2, legs.index());
    LONGS_EQUAL(1, legs.counters().goalLegsResent);
    CHECK_TRUE(seen.textHas(ev::kGoalLegResent, "goal 2: pose certain again 2.00 m from the goal"));
    CHECK_TRUE(legs.legToDrive());
}

TEST(LegSequencer, AGoalRegionIsReachedAnywhereInItAndSaysHowFarOff) {
    goal.radiusM = 3.0F;
    const msg::PoseEstimateMsg inside = poseAt(16.0, 0.0);
    CHECK(GoalClaim::kReached == legs.claimGoal(arrival(inside, false, 3.0)));
    STRCMP_EQUAL("deliberative: goal 2 (18.00, 0.00) reached within 3.00 m (2.00 m off)", seen.text(ev::kGoalReached));
}

TEST(LegSequencer, NewGoalsDropTheLegsAndAnyGoalWaitingForAPose) {
    const msg::PoseEstimateMsg unsure = poseAt(18.0, 0.0, 3.0);
    (void)legs.claimGoal(arrival(unsure, true));
    legs.newGoals();
    CHECK_FALSE(legs.goalUnconfirmed());
    LONGS_EQUAL(0, legs.legs().count);
    LONGS_EQUAL(0, legs.index());
    CHECK_FALSE(legs.legToDrive());
    const msg::PoseEstimateMsg pose = poseAt(0.0, 0.0);
    CHECK_FALSE(legs.resendFromPose(100, false, 0.0, clear, pose, params()));
}
