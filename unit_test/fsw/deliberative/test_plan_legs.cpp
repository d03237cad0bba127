// Cutting a plan into legs (plan_legs.hpp): corners, spacing, merged points,
// risk bookkeeping, the bounds' formula and refusals.
#include <cmath>

#include "fsw/deliberative/plan_legs.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::deliberative;

namespace {

// A plan through the given means with risk r[t] on segment t (its certified
// share, and split over its two ends' deltas).
CcPlan planThrough(const double (*xy)[2], std::size_t points, const double* r) {
    CcPlan p{};
    p.status = CcStatus::kOptimal;
    p.steps = static_cast<std::uint8_t>(points - 1);
    for (std::size_t t = 0; t < points; ++t) {
        p.meanX[t] = xy[t][0];
        p.meanY[t] = xy[t][1];
    }
    for (std::size_t t = 0; t + 1 < points; ++t) {
        p.delta[t][0][0] = 0.5 * r[t];
        p.delta[t][0][1] = 0.5 * r[t];
        p.segmentRisk[t] = r[t];
        p.riskUsed += r[t];
    }
    return p;
}

LegParams params(double spacing) {
    LegParams lp;
    lp.spacingM = spacing;
    lp.slackFrac = 0.3;
    lp.distanceMarginFrac = 0.1;
    lp.powerMarginFrac = 0.2;
    lp.power = rover_model::PowerModel{940.0, 1370.0, 4.5};
    lp.meanPowerFactor = 1.2;
    lp.headingRad = 0.0;
    return lp;
}

}  // namespace

TEST_GROUP(PlanLegs){};

// (0,0) (3,0) (6,0) (6,4) (6,4) (6,4): one straight run of 6 m (the middle
// point is not a corner), a corner, a run of 4 m, steps parked at the goal.
TEST(PlanLegs, CornersAndSpacingMakeTheLegsAndEverySegmentsRiskLandsInOne) {
    const double xy[6][2] = {{0, 0}, {3, 0}, {6, 0}, {6, 4}, {6, 4}, {6, 4}};
    const double r[5] = {1e-4, 2e-4, 3e-4, 4e-4, 5e-4};
    const CcPlan plan = planThrough(xy, 6, r);
    LegPlan legs;
    CHECK(core::isOk(splitPlanIntoLegs(plan, params(2.5), &legs)));
    LONGS_EQUAL(5, legs.count);  // 6 m in 3 pieces of 2 m, 4 m in 2 of 2 m
    const double ends[5][2] = {{2, 0}, {4, 0}, {6, 0}, {6, 2}, {6, 4}};
    double total = 0.0;
    for (std::size_t k = 0; k < legs.count; ++k) {
        DOUBLES_EQUAL(ends[k][0], legs.legs[k].xM, 1e-12);
        DOUBLES_EQUAL(ends[k][1], legs.legs[k].yM, 1e-12);
        DOUBLES_EQUAL(2.0, legs.plannedLengthM[k], 1e-12);
        total += legs.legs[k].risk;
    }
    DOUBLES_EQUAL(plan.riskUsed, total, 1e-15);
    DOUBLES_EQUAL((r[0] + r[1]) / 3.0, legs.legs[0].risk, 1e-15);
    DOUBLES_EQUAL((r[2] + r[3] + r[4]) / 2.0, legs.legs[4].risk, 1e-15);
}

TEST(PlanLegs, BoundsArePlannedFiguresWithAllowancesAndSlackAfterTheHabitualMargins) {
    const double xy[3][2] = {{0, 0}, {6, 0}, {6, 4}};
    const double r[2] = {1e-4, 1e-4};
    const LegParams lp = params(10.0);
    LegPlan legs;
    CHECK(core::isOk(splitPlanIntoLegs(planThrough(xy, 3, r), lp, &legs)));
    LONGS_EQUAL(2, legs.count);
    const double slack = 1.3;
    DOUBLES_EQUAL((6.0 + kLengthAllowanceM) * slack / 0.9, legs.legs[0].lengthM, 1e-9);
    DOUBLES_EQUAL(rover_model::motionEnergyJ(lp.power, 6.0 + kLengthAllowanceM, kTurnAllowanceRad, 1.2) * slack / 0.8,
                  legs.legs[0].energyJ, 1e-9);
    // The second leg starts with a quarter turn left.
    DOUBLES_EQUAL(rover_model::motionEnergyJ(lp.power, 4.0 + kLengthAllowanceM, M_PI / 2 + kTurnAllowanceRad, 1.2) *
                      slack / 0.8,
                  legs.legs[1].energyJ, 1e-9);
    // A rover facing the wrong way pays the turn on the first leg.
    LegParams back = lp;
    back.headingRad = M_PI;
    LegPlan turned;
    CHECK(core::isOk(splitPlanIntoLegs(planThrough(xy, 3, r), back, &turned)));
    CHECK(turned.legs[0].energyJ > legs.legs[0].energyJ);
    DOUBLES_EQUAL(legs.legs[0].lengthM, turned.legs[0].lengthM, 0.0);
    // The power bound: the drives' power at the cruise speed with the mean
    // factor, plus the power slack, over the habitual margin; every leg alike,
    // and kept when a leg's other bounds are recomputed from a pose.
    const double power = 1.2 * 940.0 * lp.cruiseSpeedMS * (1.0 + lp.powerSlackFrac) / 0.8;
    DOUBLES_EQUAL(power, legs.legs[0].powerW, 1e-9);
    DOUBLES_EQUAL(power, legs.legs[1].powerW, 1e-9);
    DOUBLES_EQUAL(power, turned.legs[0].powerW, 1e-9);
    msg::PlanLeg fromPose = legs.legs[1];
    CHECK(core::isOk(legBoundsFrom(3.0, -1.0, 0.0, lp, &fromPose)));
    CHECK(fromPose.lengthM != legs.legs[1].lengthM);
    DOUBLES_EQUAL(power, fromPose.powerW, 0.0);
}

TEST(PlanLegs, PointsCloserThanTheShortestLegAreMergedIntoTheNext) {
    // (5, 0.1) is 0.1 m from (5, 0): not a leg of its own.
    const double xy[4][2] = {{0, 0}, {5, 0}, {5, 0.1}, {5, 5}};
    const double r[3] = {1e-4, 1e-4, 1e-4};
    LegPlan legs;
    CHECK(core::isOk(splitPlanIntoLegs(planThrough(xy, 4, r), params(20.0), &legs)));
    LONGS_EQUAL(2, legs.count);
    DOUBLES_EQUAL(5.0, legs.legs[0].xM, 0.0);
    DOUBLES_EQUAL(0.0, legs.legs[0].yM, 0.0);
    DOUBLES_EQUAL(5.0, legs.legs[1].yM, 0.0);
    DOUBLES_EQUAL(3e-4, legs.legs[0].risk + legs.legs[1].risk, 1e-15);
}

TEST(PlanLegs, AGoalAtTheStartIsOneLegAndTheLegCountIsCapped) {
    const double still[2][2] = {{1, 1}, {1, 1}};
    const double r[1] = {0.0};
    LegPlan legs;
    CHECK(core::isOk(splitPlanIntoLegs(planThrough(still, 2, r), params(5.0), &legs)));
    LONGS_EQUAL(1, legs.count);
    DOUBLES_EQUAL(1.0, legs.legs[0].xM, 0.0);

    const double far[3][2] = {{0, 0}, {20, 0}, {20, 20}};
    const double r2[2] = {1e-4, 1e-4};
    CHECK(core::isOk(splitPlanIntoLegs(planThrough(far, 3, r2), params(0.1), &legs)));
    LONGS_EQUAL(kMaxPlanLegs, legs.count);
    DOUBLES_EQUAL(20.0, legs.legs[legs.count - 1].yM, 0.0);
    // The corner (20, 0) is still a leg end.
    bool corner = false;
    for (std::size_t k = 0; k < legs.count; ++k) {
        corner = corner || (legs.legs[k].xM == 20.0 && legs.legs[k].yM == 0.0);
    }
    CHECK_TRUE(corner);
}

TEST(PlanLegs, PlansWithoutAPathAndBadParametersAreRefused) {
    const double xy[2][2] = {{0, 0}, {5, 0}};
    const double r[1] = {1e-4};
    CcPlan plan = planThrough(xy, 2, r);
    LegPlan legs;
    plan.status = CcStatus::kNoPlan;
    CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, params(5.0), &legs));
    LONGS_EQUAL(0, legs.count);
    plan.status = CcStatus::kFeasible;
    CHECK(core::isOk(splitPlanIntoLegs(plan, params(5.0), &legs)));
    LegParams bad = params(0.0);
    CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, bad, &legs));
    LegParams stopped = params(5.0);
    stopped.cruiseSpeedMS = 0.0;
    LegParams noSpeed = params(5.0);
    noSpeed.cruiseSpeedMS = NAN;
    LegParams negativeSlack = params(5.0);
    negativeSlack.powerSlackFrac = -0.1;
    for (const LegParams& p : {stopped, noSpeed, negativeSlack}) {
        CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, p, &legs));
    }
    bad = params(5.0);
    bad.meanPowerFactor = 0.5;
    CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, bad, &legs));
    bad = params(5.0);
    bad.powerMarginFrac = 1.0;
    CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, bad, &legs));
    plan.meanY[1] = NAN;
    CHECK(core::Status::kInvalidArgument == splitPlanIntoLegs(plan, params(5.0), &legs));
}
