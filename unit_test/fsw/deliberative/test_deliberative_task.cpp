// The deliberative task on the bus (deliberative_rig.hpp): goals to plans to
// legs, fail-up handling (bound relaxation, replans), the call home in each of
// its cases, mode changes, hostile inputs, sliced planning and no heap.
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "unit_test/fsw/deliberative/deliberative_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::CcStatus;
using msg::CallHomeReason;
using msg::DeliberativeState;
using msg::HabitualState;
using msg::LegConstraint;
using test::DeliberativeRig;

namespace {

// The demo mission's goal (sim_stub/scenarios/demo_mission.toml): 20 m east.
constexpr double kGoalX = 20.0;
constexpr double kGoalY = 0.0;
constexpr double kRisk = 1e-3;
constexpr int kPlanRuns = 200;  // 20 s: far more than the 20 ms budget needs

double legsRisk(const deliberative::LegPlan& legs) {
    double r = 0.0;
    for (std::size_t k = 0; k < legs.count; ++k) {
        r += legs.legs[k].risk;
    }
    return r;
}

}  // namespace

TEST_GROUP(DeliberativeTask) {
    DeliberativeRig* rig = nullptr;
    void setup() override {
        rig = new DeliberativeRig();
        CHECK_TRUE(rig->init());
        rig->sendDriveModes();
    }
    void teardown() override { delete rig; }

    // Runs until a drive declared failed now has been so for PLANNER.failed_drive_confirm_s.
    void runPastFailedDriveConfirm() {
        const double confirmS = static_cast<double>(rig->tables.planner().failed_drive_confirm_s);
        const auto runs = static_cast<int>(std::ceil(confirmS * 1e9 / static_cast<double>(DeliberativeRig::kRun)));
        for (int i = 0; i <= runs; ++i) {
            rig->run();
        }
    }
    void autonomousToFirstLeg(double gx = kGoalX, double gy = kGoalY, double risk = kRisk, float radiusM = 0.0F) {
        rig->setMode(DeliberativeRig::kAutonomous);
        rig->sendGoal(gx, gy, risk, radiusM);
        CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
        CHECK(rig->legs >= 1);
    }
    // Fails up the leg in force until the layer calls home; the fail-ups it took.
    unsigned failUpUntilCallHome(LegConstraint why, double predicted, double allowed) {
        const std::uint32_t limit = rig->tables.planner().replan_limit;
        unsigned n = 0;
        while (n <= limit + 1 && rig->task.state() == DeliberativeState::kExecuting) {
            rig->report(HabitualState::kFailedUp, why, predicted, allowed);
            rig->run();
            ++n;
            if (rig->task.state() != DeliberativeState::kCalledHome) {
                CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
            }
        }
        return n;
    }
};

TEST(DeliberativeTask, GoalsWaitForAutonomousAndThenPlanFromTheEstimate) {
    rig->setMode(DeliberativeRig::kStandby);
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    for (int i = 0; i < 20; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kWaiting == rig->task.state());
    LONGS_EQUAL(0, rig->legs);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kGoalsChanged));
    CHECK(DeliberativeState::kWaiting == rig->lastStatus.state);
    LONGS_EQUAL(1, rig->lastStatus.goalCount);

    rig->x = 1.0;
    rig->y = -0.5;
    rig->setMode(DeliberativeRig::kAutonomous);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    const deliberative::CcProblem& p = rig->task.problem();
    DOUBLES_EQUAL(1.0, p.startX, 0.0);
    DOUBLES_EQUAL(-0.5, p.startY, 0.0);
    DOUBLES_EQUAL(rig->positionVariance, p.startCov[0], 0.0);
    DOUBLES_EQUAL(kRisk, p.riskBound, 0.0);
    const deliberative::CcPlan& plan = rig->task.plan();
    CHECK(plan.status == CcStatus::kOptimal || plan.status == CcStatus::kFeasible);
    CHECK(plan.riskUsed <= kRisk);
    CHECK(core::isOk(deliberative::checkPlan(p, plan)));
}

TEST(DeliberativeTask, APlanBecomesLegsOfAtMostTheSpacingEndingAtTheGoalWithTheirRiskAndBounds) {
    autonomousToFirstLeg();
    const deliberative::LegPlan& legs = rig->task.legs();
    const double spacing = static_cast<double>(rig->tables.planner().waypoint_spacing_m);
    CHECK(legs.count >= static_cast<std::size_t>(std::ceil(kGoalX / spacing)));
    DOUBLES_EQUAL(kGoalX, legs.legs[legs.count - 1].xM, 1e-9);
    DOUBLES_EQUAL(kGoalY, legs.legs[legs.count - 1].yM, 1e-9);
    for (std::size_t k = 0; k < legs.count; ++k) {
        CHECK(legs.plannedLengthM[k] <= spacing + 1e-9);
        CHECK(legs.legs[k].lengthM > legs.plannedLengthM[k]);
        CHECK(legs.legs[k].energyJ > 0.0);
    }
    // Every segment's risk is in exactly one leg.
    DOUBLES_EQUAL(rig->task.plan().riskUsed, legsRisk(legs), 1e-12);
    // The first leg went out as a LegCommandMsg with those bounds, and PLAN shows it.
    DOUBLES_EQUAL(legs.legs[0].xM, rig->lastLeg.goalXM, 0.0);
    DOUBLES_EQUAL(legs.legs[0].lengthM, rig->lastLeg.maxPathLengthM, 0.0);
    DOUBLES_EQUAL(legs.legs[0].energyJ, rig->lastLeg.maxEnergyJ, 0.0);
    LONGS_EQUAL(legs.count == 1 ? 1 : 0, rig->lastLeg.finalLeg);
    DOUBLES_EQUAL(0.0, rig->lastLeg.arriveWithinM, 0.0);  // a point goal: the table's tolerance
    rig->run();
    CHECK(DeliberativeState::kExecuting == rig->lastStatus.state);
    LONGS_EQUAL(rig->lastLeg.legId, rig->lastStatus.currentLegId);
    LONGS_EQUAL(legs.count, rig->lastStatus.legCount);
    DOUBLES_EQUAL(legs.legs[0].xM, rig->lastStatus.legs[0].xM, 0.0);
    DOUBLES_EQUAL(rig->task.plan().riskUsed, rig->lastStatus.riskUsed, 0.0);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kPlanFound));
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kLegSent));
}

// PLAN_PATH's source: every plan made is published once as PlanPathMsg with
// the plan's means, the problem's start covariance, motion noise and the
// bound planned to, numbered as PlanStatusMsg::plansMade counts it.
TEST(DeliberativeTask, EveryPlanMadeIsPublishedOnceWithItsMeansCovarianceAndNumber) {
    rig->x = 1.0;
    rig->y = -0.5;
    rig->positionVariance = 0.04;
    autonomousToFirstLeg();
    LONGS_EQUAL(1, rig->planPaths);
    const deliberative::CcProblem& p = rig->task.problem();
    const deliberative::CcPlan& plan = rig->task.plan();
    const msg::PlanPathMsg& m = rig->lastPath;
    LONGS_EQUAL(1, m.planNumber);
    LONGS_EQUAL(rig->task.counters().plansFound, m.planNumber);
    LONGS_EQUAL(static_cast<long>(plan.status), m.status);
    LONGS_EQUAL(plan.steps, m.steps);
    CHECK(m.steps >= 1);
    DOUBLES_EQUAL(kRisk, m.riskBound, 0.0);
    DOUBLES_EQUAL(p.riskBound, m.riskBound, 0.0);
    DOUBLES_EQUAL(plan.riskUsed, m.riskUsed, 0.0);
    CHECK(m.riskUsed > 0.0 && m.riskUsed <= kRisk);
    DOUBLES_EQUAL(plan.euclideanLengthM, m.lengthM, 0.0);
    CHECK(m.lengthM >= std::hypot(kGoalX - 1.0, kGoalY + 0.5) - 1e-9);
    DOUBLES_EQUAL(p.processSigmaM, m.processSigmaM, 0.0);
    CHECK(m.processSigmaM > 0.0);
    for (std::size_t i = 0; i < 4; ++i) {
        DOUBLES_EQUAL(p.startCov[i], m.startCov[i], 0.0);
    }
    DOUBLES_EQUAL(0.04, m.startCov[0], 0.0);  // the estimate's (x, y) block
    DOUBLES_EQUAL(0.0, m.startCov[1], 0.0);
    DOUBLES_EQUAL(0.04, m.startCov[3], 0.0);
    DOUBLES_EQUAL(kGoalX, m.goalX, 0.0);
    DOUBLES_EQUAL(kGoalY, m.goalY, 0.0);
    for (std::size_t t = 0; t <= m.steps; ++t) {
        DOUBLES_EQUAL(plan.meanX[t], m.meanX[t], 0.0);
        DOUBLES_EQUAL(plan.meanY[t], m.meanY[t], 0.0);
    }
    DOUBLES_EQUAL(1.0, m.meanX[0], 0.0);  // mu_0: the pose planned from
    DOUBLES_EQUAL(-0.5, m.meanY[0], 0.0);
    DOUBLES_EQUAL(kGoalX, m.meanX[m.steps], 1e-9);
    DOUBLES_EQUAL(kGoalY, m.meanY[m.steps], 1e-9);
    for (std::size_t t = m.steps + 1U; t < msg::kPlanPathMeans; ++t) {
        DOUBLES_EQUAL(0.0, m.meanX[t], 0.0);
        DOUBLES_EQUAL(0.0, m.meanY[t], 0.0);
    }
    CHECK(m.timeNs > 0 && m.timeNs <= rig->clock.now());
    rig->run();
    LONGS_EQUAL(1, rig->planPaths);  // once, not with every status
    LONGS_EQUAL(m.planNumber, rig->lastStatus.plansMade);

    // A replan is a plan made: the second, from where the rover stands now.
    rig->x = 3.0;
    rig->y = 0.25;
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    LONGS_EQUAL(2, rig->planPaths);
    LONGS_EQUAL(2, rig->lastPath.planNumber);
    LONGS_EQUAL(rig->task.counters().plansFound, rig->lastPath.planNumber);
    DOUBLES_EQUAL(rig->task.problem().startX, rig->lastPath.meanX[0], 0.0);
    DOUBLES_EQUAL(rig->task.problem().startY, rig->lastPath.meanY[0], 0.0);
    DOUBLES_EQUAL(rig->task.plan().riskUsed, rig->lastPath.riskUsed, 0.0);
    rig->run();
    LONGS_EQUAL(2, rig->lastStatus.plansMade);
}

TEST(DeliberativeTask, AchievedLegsAdvanceThroughEveryGoalToComplete) {
    const double goals[2][2] = {{kGoalX, kGoalY}, {24.0, 6.0}};
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoals(goals, 2, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    unsigned achieved = 0;
    for (int guard = 0; guard < 100 && rig->task.state() != DeliberativeState::kComplete; ++guard) {
        if (rig->task.state() == DeliberativeState::kExecuting) {
            const std::uint32_t before = rig->lastLeg.legId;
            rig->achieveLeg();
            ++achieved;
            rig->run();
            CHECK(rig->lastLeg.legId != before || rig->task.state() != DeliberativeState::kExecuting);
        } else {
            rig->run();
        }
    }
    CHECK(DeliberativeState::kComplete == rig->task.state());
    LONGS_EQUAL(achieved, rig->task.counters().legsAchieved);
    LONGS_EQUAL(achieved, rig->legs);
    LONGS_EQUAL(2, rig->task.counters().goalsReached);
    LONGS_EQUAL(2, rig->task.counters().plansFound);  // the second goal planned from where the first ended
    DOUBLES_EQUAL(kGoalX, rig->task.problem().startX, 1e-9);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kMissionComplete));
    LONGS_EQUAL(0, rig->safeRequests);
    // Late or repeated reports about an old leg change nothing.
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK(DeliberativeState::kComplete == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().failUps);
}

// A goal's region (PlanGoalMsg radius, a plan's `within R`) goes to the
// habitual layer on the goal's last leg only: the waypoints before it are
// reached as points, the last one anywhere within the region.
TEST(DeliberativeTask, OnlyTheGoalsLastLegCarriesItsRegion) {
    autonomousToFirstLeg(kGoalX, kGoalY, kRisk, 3.0F);
    const std::size_t count = rig->task.legs().count;
    CHECK(count >= 2);
    for (std::size_t k = 0; k + 1 < count; ++k) {
        LONGS_EQUAL(0, rig->lastLeg.finalLeg);
        DOUBLES_EQUAL(0.0, rig->lastLeg.arriveWithinM, 0.0);
        rig->achieveLeg();
        rig->run();
    }
    LONGS_EQUAL(1, rig->lastLeg.finalLeg);
    DOUBLES_EQUAL(kGoalX, rig->lastLeg.goalXM, 1e-9);  // the leg still ends at the point
    DOUBLES_EQUAL(3.0, rig->lastLeg.arriveWithinM, 1e-6);
    rig->x = kGoalX - 2.5;  // the habitual layer stopped inside the region
    rig->report(HabitualState::kAchieved);
    rig->run();
    CHECK(DeliberativeState::kComplete == rig->task.state());
}

TEST(DeliberativeTask, AnEnergyFailUpWithinTheRelaxLimitResendsTheLegWithTheBoundGrownByWhatIsNeeded) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    // The habitual layer predicts 20 % more than it is allowed.
    rig->report(HabitualState::kFailedUp, LegConstraint::kEnergy, 1200.0, 1000.0);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().boundRelaxations);
    LONGS_EQUAL(2, rig->legs);
    CHECK(rig->lastLeg.legId != first.legId);
    DOUBLES_EQUAL(first.goalXM, rig->lastLeg.goalXM, 0.0);
    DOUBLES_EQUAL(first.maxEnergyJ * 1.2 * deliberative::kBoundRelaxHeadroom, rig->lastLeg.maxEnergyJ, 1e-6);
    DOUBLES_EQUAL(first.maxPathLengthM, rig->lastLeg.maxPathLengthM, 0.0);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kBoundRelaxed));
    LONGS_EQUAL(0, rig->task.counters().replans);
    // A second fail-up that would take the bound past bound_relax_limit replans instead.
    const double limit = static_cast<double>(rig->tables.planner().bound_relax_limit);
    rig->report(HabitualState::kFailedUp, LegConstraint::kEnergy, 1000.0 * limit, 1000.0);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().boundRelaxations);
    LONGS_EQUAL(1, rig->task.counters().replans);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kReplan));
}

TEST(DeliberativeTask, ALengthFailUpRelaxesTheLengthBound) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    rig->report(HabitualState::kFailedUp, LegConstraint::kPathLength, 7.0, 6.5);
    rig->run();
    DOUBLES_EQUAL(first.maxPathLengthM * 7.0 / 6.5 * deliberative::kBoundRelaxHeadroom, rig->lastLeg.maxPathLengthM,
                  1e-9);
    DOUBLES_EQUAL(first.maxEnergyJ, rig->lastLeg.maxEnergyJ, 0.0);
}

TEST(DeliberativeTask, NoPathFailUpsReplanFromTheCurrentEstimateUntilTheLimitThenCallHome) {
    autonomousToFirstLeg();
    rig->x = 3.0;  // the rover got this far
    rig->y = 0.4;
    const std::uint32_t limit = rig->tables.planner().replan_limit;
    CHECK(limit >= 1);
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath, 0.0, 0.0);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().replans);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(3.0, rig->task.problem().startX, 0.0);  // from the estimate, same goal
    DOUBLES_EQUAL(0.4, rig->task.problem().startY, 0.0);
    DOUBLES_EQUAL(kGoalX, rig->task.problem().goalX, 0.0);
    // Each further fail-up replans until limit replans are spent; the next calls home.
    LONGS_EQUAL(limit, failUpUntilCallHome(LegConstraint::kCannotFollow, 0.0, 0.0));
    CHECK(DeliberativeState::kCalledHome == rig->task.state());
    LONGS_EQUAL(limit, rig->task.counters().replans);
    LONGS_EQUAL(1, rig->safeRequests);
    CHECK(CallHomeReason::kReplansExhausted == rig->lastSafe.reason);
    CHECK(rig->cancels >= 1);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kCallHome));
    cmdtlm::event_data::CALL_HOME callHome;  // the reason by number, as PLAN.call_home
    CHECK_TRUE(rig->seenData(deliberative::events::kCallHome, &callHome));
    DOUBLES_EQUAL(static_cast<double>(CallHomeReason::kReplansExhausted), callHome.reason, 0.0);
    DOUBLES_EQUAL(kRisk, callHome.risk_bound, 0.0);
    rig->run();
    CHECK(CallHomeReason::kReplansExhausted == rig->lastStatus.callHome);
    CHECK(DeliberativeState::kCalledHome == rig->lastStatus.state);
    // It stays called home (no legs) until the operator sends goals again.
    const unsigned legsBefore = rig->legs;
    for (int i = 0; i < 20; ++i) {
        rig->run();
    }
    LONGS_EQUAL(legsBefore, rig->legs);
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    CHECK(CallHomeReason::kNone == rig->task.status().callHome);
}

TEST(DeliberativeTask, EnergyFailUpsBeyondEveryRelaxationCallHomeForInsufficientPower) {
    autonomousToFirstLeg();
    const double limit = static_cast<double>(rig->tables.planner().bound_relax_limit);
    LONGS_EQUAL(rig->tables.planner().replan_limit + 1,
                failUpUntilCallHome(LegConstraint::kEnergy, 1000.0 * (limit + 1.0), 1000.0));
    CHECK(DeliberativeState::kCalledHome == rig->task.state());
    CHECK(CallHomeReason::kInsufficientPower == rig->lastSafe.reason);
    LONGS_EQUAL(0, rig->task.counters().boundRelaxations);
}

TEST(DeliberativeTask, AGoalInsideAnObstacleCallsHomeAtOnce) {
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(5.75, 2.5, kRisk);  // inside coarse-map rock 0
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kCalledHome, 10));
    CHECK(CallHomeReason::kGoalUnreachable == rig->lastSafe.reason);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kProblemRefused));
    CHECK(std::strstr(rig->seenText(deliberative::events::kProblemRefused), "goal inside an obstacle") != nullptr);
    LONGS_EQUAL(0, rig->legs);
}

TEST(DeliberativeTask, NoPlanWithinTheRiskRelaxesItToTheTableLimitThenCallsHome) {
    // A goal 5 cm south of rock 0 grown by the footprint: the final mean's
    // margin (its quantile times the final sigma, >= 0.2 m) cannot be met at any
    // risk the limit allows, so no plan exists (proven by the planner).
    const double radius = static_cast<double>(rig->tables.roverGeometry().footprint_radius_m);
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(5.75, 1.8 - radius - 0.05, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kCalledHome, kPlanRuns));
    const double relaxLimit = static_cast<double>(rig->tables.planner().risk_relax_limit);
    const unsigned relaxations =
        static_cast<unsigned>(std::ceil(std::log(relaxLimit) / std::log(deliberative::kRiskRelaxStep) - 1e-9));
    LONGS_EQUAL(relaxations, rig->task.counters().riskRelaxations);
    LONGS_EQUAL(relaxations + 1, rig->task.counters().noPlans);
    // Before each "no plan", the wide search (issue 15 item 3) was tried once
    // at the same bound, and found nothing either.
    LONGS_EQUAL(relaxations + 1, rig->task.counters().wideSearches);
    LONGS_EQUAL(0, rig->task.counters().wideSearchPlans);
    LONGS_EQUAL(relaxations + 1, rig->seenCount(deliberative::events::kWideSearch));
    CHECK(std::strstr(rig->seenText(deliberative::events::kWideSearch), "(proven): search x8, certify at") != nullptr);
    DOUBLES_EQUAL(kRisk * relaxLimit, rig->task.problem().riskBound, 1e-15);
    CHECK(CallHomeReason::kNoPlanWithinRisk == rig->lastSafe.reason);
    LONGS_EQUAL(0, rig->legs);
    // No plan made, none counted in plansMade: no plan path published.
    LONGS_EQUAL(0, rig->task.counters().plansFound);
    LONGS_EQUAL(0, rig->planPaths);
    rig->run();
    DOUBLES_EQUAL(kRisk * relaxLimit, rig->lastStatus.riskInForce, 1e-15);
    DOUBLES_EQUAL(kRisk, rig->lastStatus.riskBound, 0.0);
}

// Operator's Delta 0.1, no plan within it: relaxed x10 would be 1, but the
// planner needs Delta < 0.5, so 0.49 is planned to; event 904 says 0.49 (it
// said "relaxed to 1"), and the factor it gives is the one in force.
TEST(DeliberativeTask, ARelaxationPastTheCapNamesTheRiskActuallyPlannedTo) {
    const double radius = static_cast<double>(rig->tables.roverGeometry().footprint_radius_m);
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(5.75, 1.8 - radius - 0.05, 0.1);
    CHECK_TRUE(rig->runUntil([this] { return rig->seenCount(deliberative::events::kPlanStarted) >= 2; }, kPlanRuns));
    LONGS_EQUAL(1, rig->task.counters().riskRelaxations);
    DOUBLES_EQUAL(deliberative::kMaxRiskInForce, rig->task.problem().riskBound, 0.0);
    STRCMP_EQUAL("deliberative: risk bound relaxed to 0.49 (the operator's 0.1 x4.9, capped below 0.5, limit x10)",
                 rig->seenText(deliberative::events::kRiskRelaxed));
    CHECK(std::strstr(rig->seenText(deliberative::events::kPlanStarted), "risk 0.49,") != nullptr);
}

TEST(DeliberativeTask, ADriveDeclaredFailedWithTheWheelsFreeIsPlannedWithItsPowerFactorNotACallHome) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    rig->sendDriveModes(msg::DriveMode::kFailed, 2, 4.5);
    for (int i = 0; i < 5; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kExecuting == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().callHomes);
    // Driving goes on: the next leg is handed down (its energy bound from the
    // power model with the failed drive's factor, test_plan_legs).
    rig->achieveLeg();
    rig->run();
    CHECK(rig->lastLeg.legId != first.legId);
    CHECK(rig->lastLeg.legId != 0);
}

TEST(DeliberativeTask, TheInterlockHoldingEveryDriveCallsHomeForLostMobility) {
    autonomousToFirstLeg();
    msg::DriveStatusMsg status{};
    for (msg::WheelStatus& w : status.wheels) {
        w.health = msg::DriveHealth::kOperational;
    }
    status.wheels[2].health = msg::DriveHealth::kFailed;
    status.interlockTripped = 1;
    (void)rig->bus.publish(status);
    rig->run();
    CHECK(DeliberativeState::kCalledHome == rig->task.state());
    CHECK(CallHomeReason::kMobilityLost == rig->lastSafe.reason);
    CHECK(rig->cancels >= 1);
}

// The power bound (issue 17, points 6 and 7): every leg carries the drives'
// power at the cruise speed planned with, plus PLANNER.leg_power_slack_frac,
// over the habitual layer's margin; a power fail-up relaxes it for the rest of
// the plan (the drives' power is the same on every leg), within
// bound_relax_limit; past it, a replan.
TEST(DeliberativeTask, APowerFailUpRelaxesThePowerBoundForTheRestOfThePlanAndPastTheLimitReplans) {
    autonomousToFirstLeg();
    const tables::HabitualTable& hab = rig->tables.habitual();
    const tables::PlannerTable& planner = rig->tables.planner();
    const double planned = static_cast<double>(hab.drive_energy_j_per_m) * static_cast<double>(hab.cruise_speed_m_s) *
                           (1.0 + static_cast<double>(planner.leg_power_slack_frac)) /
                           (1.0 - static_cast<double>(hab.power_margin_frac));
    const msg::LegCommandMsg first = rig->lastLeg;
    DOUBLES_EQUAL(planned, first.maxPowerW, 1e-9);
    // A worn motor: 10 % over what is allowed.
    rig->report(HabitualState::kFailedUp, LegConstraint::kPower, 330.0, 300.0);
    rig->run();
    const double grown = 1.1 * deliberative::kBoundRelaxHeadroom;
    LONGS_EQUAL(1, rig->task.counters().powerRelaxations);
    LONGS_EQUAL(1, rig->task.counters().boundRelaxations);
    LONGS_EQUAL(0, rig->task.counters().replans);
    CHECK(rig->lastLeg.legId != first.legId);
    DOUBLES_EQUAL(first.goalXM, rig->lastLeg.goalXM, 0.0);
    DOUBLES_EQUAL(planned * grown, rig->lastLeg.maxPowerW, 1e-9);
    DOUBLES_EQUAL(first.maxEnergyJ, rig->lastLeg.maxEnergyJ, 0.0);  // the other bounds as planned
    CHECK(std::strstr(rig->seenText(deliberative::events::kBoundRelaxed), "power bound relaxed x1.155") != nullptr);
    // The next leg keeps the relaxed power bound.
    rig->achieveLeg();
    rig->run();
    DOUBLES_EQUAL(planned * grown, rig->lastLeg.maxPowerW, 1e-9);
    // A failed drive's draw: past bound_relax_limit in all: a replan, whose legs
    // are bounded at the power factors of the moment again.
    rig->report(HabitualState::kFailedUp, LegConstraint::kPower, 480.0, 300.0);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().powerRelaxations);
    LONGS_EQUAL(1, rig->task.counters().replans);
    CHECK(std::strstr(rig->seenText(deliberative::events::kReplan), "(power)") != nullptr);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(planned, rig->lastLeg.maxPowerW, 1e-9);
}

// The motor loss in the state estimate (point 9): plans made while the drive
// mode estimator declares a drive failed take it at failed_drive_power_factor
// and a motion noise failed_drive_noise_factor times the table's. To the demo
// goal, 2.4 m from a grown rock, no plan then fits even the relaxed risk bound
// (the goal's own end needs it: point 10); with every drive nominal it does.
TEST(DeliberativeTask, AFailedDriveInTheEstimateCanLeaveNoPlanWithinTheRiskBound) {
    const tables::PlannerTable& planner = rig->tables.planner();
    rig->sendDriveModes(msg::DriveMode::kFailed, 1, 4.5);
    rig->setMode(DeliberativeRig::kAutonomous);
    runPastFailedDriveConfirm();
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kCalledHome, kPlanRuns));
    DOUBLES_EQUAL(static_cast<double>(planner.process_noise_sigma_m) *
                      static_cast<double>(planner.failed_drive_noise_factor),
                  rig->task.problem().processSigmaM, 1e-12);
    CHECK(CallHomeReason::kNoPlanWithinRisk == rig->lastSafe.reason);
    LONGS_EQUAL(1, rig->task.counters().riskRelaxations);
    LONGS_EQUAL(0, rig->legs);
    // Said once, when the set of failed drives changed, not per plan.
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kFailedDriveModel));
    LONGS_EQUAL(1, rig->task.counters().failedDriveModels);
    CHECK(std::strstr(rig->seenText(deliberative::events::kFailedDriveModel), "ML failed") != nullptr);
    CHECK(std::strstr(rig->seenText(deliberative::events::kFailedDriveModel), "noise 0.250 m/step") != nullptr);
    cmdtlm::event_data::FAILED_DRIVE_MODEL model;  // the numbers the ground decides on
    CHECK_TRUE(rig->seenData(deliberative::events::kFailedDriveModel, &model));
    DOUBLES_EQUAL(1U << 1, model.failed_drives, 0.0);
    DOUBLES_EQUAL(rig->task.problem().processSigmaM, model.noise, 0.0);

    // The drive back to nominal: the same goal plans with the table's noise.
    rig->sendDriveModes(msg::DriveMode::kNominal);
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(static_cast<double>(planner.process_noise_sigma_m), rig->task.problem().processSigmaM, 1e-12);
    LONGS_EQUAL(2, rig->seenCount(deliberative::events::kFailedDriveModel));
    CHECK(std::strstr(rig->seenText(deliberative::events::kFailedDriveModel), "every drive back") != nullptr);
    CHECK_TRUE(rig->seenData(deliberative::events::kFailedDriveModel, &model));
    DOUBLES_EQUAL(0.0, model.failed_drives, 0.0);
}

// A drive declared failed for less than PLANNER.failed_drive_confirm_s (a
// resettable fault reads so for an update or two after its reset): planned at
// its failed power factor but with the table's motion noise; once the
// declaration has lasted, with the failed drive's noise.
TEST(DeliberativeTask, AFailedDriveDeclarationMustLastBeforeItsNoiseIsPlannedWith) {
    const tables::PlannerTable& planner = rig->tables.planner();
    CHECK(planner.failed_drive_confirm_s > 0.5F);
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendDriveModes(msg::DriveMode::kFailed, 1, 4.5);
    rig->run();
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(static_cast<double>(planner.process_noise_sigma_m), rig->task.problem().processSigmaM, 1e-12);
    LONGS_EQUAL(0, rig->seenCount(deliberative::events::kFailedDriveModel));
    // Still declared failed past the confirmation time: the next plan takes its noise.
    runPastFailedDriveConfirm();
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntil([this] { return rig->task.counters().plansStarted >= 2; }, kPlanRuns));
    DOUBLES_EQUAL(static_cast<double>(planner.process_noise_sigma_m) *
                      static_cast<double>(planner.failed_drive_noise_factor),
                  rig->task.problem().processSigmaM, 1e-12);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kFailedDriveModel));
}

// Fault protection gives a failed drive up and leaves the interlock latched:
// when the estimator declares that drive failed, the deliberative layer decides
// by planning with it failed (a fail-up replans as any other) - no plan within
// the risk bound calls home with that reason; a plan that fits calls home
// "mobility lost" (no drive is isolated to drive on the others yet).
TEST(DeliberativeTask, AnInterlockLatchedOnADriveDeclaredFailedIsDecidedByPlanning) {
    autonomousToFirstLeg();
    rig->sendDriveModes(msg::DriveMode::kFailed, 1, 4.5);
    rig->sendDriveStatus(true, 1);
    runPastFailedDriveConfirm();
    CHECK(DeliberativeState::kExecuting == rig->task.state());  // not called home on the interlock alone
    rig->report(HabitualState::kFailedUp, LegConstraint::kPower, 480.0, 300.0);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kCalledHome, kPlanRuns));
    CHECK(CallHomeReason::kNoPlanWithinRisk == rig->lastSafe.reason);

    // A goal far from every rock: a plan fits, but the wheels are held.
    rig->sendGoal(-2.0, -5.0, kRisk);
    CHECK_TRUE(rig->runUntil([this] { return rig->safeRequests >= 2; }, kPlanRuns));
    CHECK(CallHomeReason::kMobilityLost == rig->lastSafe.reason);
    CHECK(std::strstr(rig->seenText(deliberative::events::kCallHome), "a plan fits, but the interlock") != nullptr);
    // That plan counts in plansMade, so it is downlinked too (the one before
    // it, with no plan within the risk, is not).
    LONGS_EQUAL(rig->task.counters().plansFound, rig->planPaths);
    LONGS_EQUAL(rig->task.counters().plansFound, rig->lastPath.planNumber);
    DOUBLES_EQUAL(-2.0, rig->lastPath.goalX, 0.0);
    DOUBLES_EQUAL(-5.0, rig->lastPath.goalY, 0.0);
}

// Degraded, or unknown (nothing says its wheel has stopped): mobility lost.
TEST(DeliberativeTask, TheInterlockLatchedOnADriveNotDeclaredFailedStillCallsHomeAtOnce) {
    for (const msg::DriveMode mode : {msg::DriveMode::kDegraded, msg::DriveMode::kUnknown}) {
        autonomousToFirstLeg();
        rig->sendDriveModes(mode, 1, 1.4);
        rig->sendDriveStatus(true, 1);
        rig->run();
        CHECK(DeliberativeState::kCalledHome == rig->task.state());
        CHECK(CallHomeReason::kMobilityLost == rig->lastSafe.reason);
        rig->sendDriveStatus(false);
        rig->sendDriveModes(msg::DriveMode::kNominal);
        rig->run();
    }
    LONGS_EQUAL(2, rig->safeRequests);
}

TEST(DeliberativeTask, LeavingAutonomousCancelsTheLegAndReturningReplansFromThePose) {
    autonomousToFirstLeg();
    const unsigned cancels = rig->cancels;
    rig->setMode(DeliberativeRig::kStandby);
    rig->run();
    CHECK(DeliberativeState::kWaiting == rig->task.state());
    LONGS_EQUAL(cancels + 1, rig->cancels);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kLeftAutonomous));
    rig->x = 2.0;
    rig->setMode(DeliberativeRig::kAutonomous);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(2.0, rig->task.problem().startX, 0.0);
    LONGS_EQUAL(2, rig->task.counters().plansFound);
}

TEST(DeliberativeTask, ANewGoalListCancelsTheLegInForceAndPlansForTheNewGoal) {
    autonomousToFirstLeg();
    const unsigned cancels = rig->cancels;
    rig->sendGoal(10.0, -6.0, 1e-6);
    rig->run();
    LONGS_EQUAL(cancels + 1, rig->cancels);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(-6.0, rig->task.problem().goalY, 0.0);
    DOUBLES_EQUAL(1e-6, rig->task.problem().riskBound, 0.0);
    CHECK(rig->task.plan().riskUsed <= 1e-6);
    // An empty list: idle, leg cancelled.
    rig->sendGoals(nullptr, 0, 1e-3);
    rig->run();
    CHECK(DeliberativeState::kIdle == rig->task.state());
    LONGS_EQUAL(cancels + 2, rig->cancels);
}

TEST(DeliberativeTask, MalformedInputsAreCountedEventedAndIgnored) {
    rig->setMode(DeliberativeRig::kAutonomous);
    msg::PlanGoalMsg bad{};
    bad.goals.riskBound = 0.7;  // outside (0, 0.5)
    bad.goals.count = 1;
    bad.goals.revision = 77;
    CHECK(core::isOk(rig->bus.publish(bad)));
    bad.goals.riskBound = 1e-3;
    bad.goals.goals[0].xM = NAN;
    CHECK(core::isOk(rig->bus.publish(bad)));
    bad.goals.goals[0].xM = 1.0;
    bad.goals.count = msg::kMaxGoals + 1;
    CHECK(core::isOk(rig->bus.publish(bad)));
    bad.goals.count = 1;
    bad.listIndex = msg::kMaxGoals;  // past any goal list
    CHECK(core::isOk(rig->bus.publish(bad)));
    bad.listIndex = 0;
    // A region radius that is no number, negative or beyond kMaxGoalRadiusM.
    for (const float radius : {NAN, -0.001F, msg::kMaxGoalRadiusM + 0.01F}) {
        bad.goals.goals[0].radiusM = radius;
        CHECK(core::isOk(rig->bus.publish(bad)));
    }
    msg::LegReportMsg report{};
    report.state = static_cast<HabitualState>(9);
    CHECK(core::isOk(rig->bus.publish(report)));
    msg::PoseEstimateMsg pose{};
    pose.xM = INFINITY;
    pose.initialised = 1;
    CHECK(core::isOk(rig->bus.publish(pose)));
    rig->publishPose = false;
    rig->run();
    LONGS_EQUAL(9, rig->task.counters().malformedInputs);
    CHECK(rig->seenCount(deliberative::events::kMalformedInput) >= 3);  // throttled: 1st, 2nd, 4th
    CHECK(DeliberativeState::kIdle == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().goalListsAdopted);
}

// goalListUsable, every goal reader's check: a region radius in [0,
// kMaxGoalRadiusM] (0: the point), NaN refused like a point that is no number.
TEST(DeliberativeTask, AGoalListIsUsableOnlyWithEveryRegionRadiusInRange) {
    msg::GoalListMsg g{};
    g.riskBound = 1e-3;
    g.count = 2;
    g.goals[0].xM = 1.0;
    g.goals[1].xM = 2.0;
    CHECK_TRUE(msg::goalListUsable(g));
    g.goals[1].radiusM = msg::kMaxGoalRadiusM;
    CHECK_TRUE(msg::goalListUsable(g));
    g.goals[1].radiusM = 0.001F;
    CHECK_TRUE(msg::goalListUsable(g));
    const float bad[] = {NAN, INFINITY, -INFINITY, -0.001F, std::nextafter(msg::kMaxGoalRadiusM, 100.0F)};
    for (const float r : bad) {
        g.goals[1].radiusM = r;
        CHECK_FALSE(msg::goalListUsable(g));
    }
    // Only the goals in use are judged.
    g.count = 1;
    CHECK_TRUE(msg::goalListUsable(g));
}

// The plan executive gives a goal plan's goals one at a time with their index
// in the operator's list: PLAN's goal_index and the events number them so.
TEST(DeliberativeTask, TheGoalIsNumberedAsInTheOperatorsList) {
    rig->setMode(DeliberativeRig::kAutonomous);
    const double xy[1][2] = {{kGoalX, kGoalY}};
    rig->sendGoals(xy, 1, kRisk, 3);
    rig->run();
    LONGS_EQUAL(3, rig->task.status().goalIndex);
    LONGS_EQUAL(1, rig->task.status().goalCount);
}

TEST(DeliberativeTask, WithoutAFreshPoseNothingIsPlanned) {
    rig->publishPose = false;
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    for (int i = 0; i < 30; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kWaiting == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().plansStarted);
}

// Issue 15 item 5. The demo route from a start 0.2 m uncertain: at 1e-6 the
// plan is proven optimal (within the planner's 0.2 %); the operator then
// tightens the bound to 1e-7 for the same goal: the new plan is seeded with the
// 1e-6 plan's faces, and it is a budget plan (the search ran out of work
// before proving it), which PLAN (plan_status 1, plan_gap) and event 902
// ("BUDGET plan", the gap) say; before, only "feasible (budget)" was shown,
// with nothing on how far from the best it might be.
TEST(DeliberativeTask, ABudgetPlanSaysSoWithItsGapAndATighterBoundIsSeededWithTheLastPlan) {
    rig->positionVariance = 0.04;
    autonomousToFirstLeg(kGoalX, kGoalY, 1e-6);
    rig->run();
    const deliberative::DeliberativeCounters& c = rig->task.counters();
    LONGS_EQUAL(static_cast<int>(deliberative::CcStatus::kOptimal), rig->lastStatus.planStatus);
    DOUBLES_EQUAL(0.002, rig->lastStatus.planGap, 1e-9);
    CHECK(std::strncmp(rig->seenText(deliberative::events::kPlanFound), "deliberative: optimal plan, gap 0.2%: ", 38) ==
          0);
    LONGS_EQUAL(0, c.budgetPlans);
    LONGS_EQUAL(0, c.seededPlans);

    rig->sendGoal(kGoalX, kGoalY, 1e-7);
    CHECK_TRUE(rig->runUntil([this] { return rig->seenCount(deliberative::events::kPlanFound) >= 2; }, kPlanRuns));
    rig->run();
    LONGS_EQUAL(1, c.seededPlans);
    const deliberative::CcPlanner& planner = rig->task.planner();
    LONGS_EQUAL(static_cast<int>(deliberative::CcStatus::kFeasible), rig->lastStatus.planStatus);
    LONGS_EQUAL(1, c.budgetPlans);
    const double gap = (planner.evenSplitCost() - planner.lowerBound()) / planner.evenSplitCost();
    CHECK(gap > 0.002);
    DOUBLES_EQUAL(gap, rig->lastStatus.planGap, 1e-12);
    char expected[64];
    std::snprintf(expected, sizeof expected, "deliberative: BUDGET plan, seeded, gap %.1f%%: ", 100.0 * gap);
    CHECK(std::strncmp(rig->seenText(deliberative::events::kPlanFound), expected, std::strlen(expected)) == 0);
}

// Sliced and bounded: every run stops stepping the planner once its work passes
// kSliceWork (so a run does at most kSliceWork plus one unit), at most
// kMaxUnitsPerRun units; the whole plan stays within the table's node budget
// and PLANNER.time_budget_ms x kWorkKUnitsPerMs thousand work units (plus one unit).
TEST(DeliberativeTask, PlanningIsSlicedOverRunsWithinTheTableBudget) {
    tables::PlannerTable planner = rig->tables.planner();
    planner.time_budget_ms = 8;
    CHECK_TRUE(rig->loadTable(tables::TableId::kPlanner, planner, 7));
    autonomousToFirstLeg(kGoalX, kGoalY, 1e-6);
    const deliberative::DeliberativeCounters& c = rig->task.counters();
    const deliberative::CcPlanner& p = rig->task.planner();
    CHECK(p.nodes() <= planner.node_budget);
    CHECK(c.maxRunUnits <= deliberative::kMaxUnitsPerRun);
    CHECK(c.maxRunUnits >= 1);
    CHECK(c.maxRunWork <= deliberative::kSliceWork + deliberative::CcPlanner::kMaxUnitWork);
    // Slices: at least the work divided by the most any run did.
    CHECK(rig->task.plannerSlices() >= (p.work() + c.maxRunWork - 1) / c.maxRunWork);
    CHECK(rig->task.plannerSlices() >= 2);
    CHECK(p.work() <= static_cast<std::uint64_t>(planner.time_budget_ms) * deliberative::kWorkKUnitsPerMs * 1000 +
                          c.maxRunWork);
}

// Must-show 4 at the task level: planning, cutting legs, sending them and
// handling reports allocate nothing.
TEST(DeliberativeTask, AWholeGoalFromPlanToArrivalAllocatesNothing) {
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->run();
    test::AllocationWatch watch;
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    for (int guard = 0; guard < 50 && rig->task.state() == DeliberativeState::kExecuting; ++guard) {
        rig->achieveLeg();
        rig->run();
    }
    CHECK(DeliberativeState::kComplete == rig->task.state());
    LONGS_EQUAL(0, watch.count());
}

// Issue 15 item 3: a wall across the site with a gap Boole's even split refuses
// at the operator's bound (no plan at scale 1), but the wide search finds a
// path through it that certifies within the same bound: event 929, then a plan
// at 1e-3, nothing relaxed. The window of half-gaps where this happens on this
// map is a few centimetres wide (the rock grown by the footprint leaves little
// room); the half-gap here was chosen inside it.
TEST(DeliberativeTask, ANarrowGapBooleRefusesIsPlannedByTheWideSearchAtTheSameRisk) {
    tables::CoarseMapTable map = rig->tables.coarseMap();
    map.obstacle_count = 2;
    for (auto& c : map.vertex_count) {
        c = 0;
    }
    for (std::size_t k = 0; k < sizeof map.vertex_x_m / sizeof map.vertex_x_m[0]; ++k) {
        map.vertex_x_m[k] = 0.0f;
        map.vertex_y_m[k] = 0.0f;
    }
    const float half = 1.045f;
    const float xs[4] = {9.0f, 11.0f, 11.0f, 9.0f};
    const float below[4] = {-9.5f, -9.5f, -half, -half};
    const float above[4] = {half, half, 9.5f, 9.5f};
    map.vertex_count[0] = 4;
    map.vertex_count[1] = 4;
    for (std::size_t v = 0; v < 4; ++v) {
        map.vertex_x_m[v] = xs[v];
        map.vertex_y_m[v] = below[v];
        map.vertex_x_m[8 + v] = xs[v];
        map.vertex_y_m[8 + v] = above[v];
    }
    CHECK_TRUE(rig->loadTable(tables::TableId::kCoarseMap, map, 2));
    autonomousToFirstLeg(20.0, 0.0, kRisk);
    LONGS_EQUAL(1, rig->task.counters().wideSearches);
    LONGS_EQUAL(1, rig->task.counters().wideSearchPlans);
    LONGS_EQUAL(0, rig->task.counters().noPlans);
    LONGS_EQUAL(0, rig->task.counters().riskRelaxations);
    LONGS_EQUAL(1, rig->seenCount(deliberative::events::kWideSearch));
    DOUBLES_EQUAL(kRisk, rig->task.problem().riskBound, 0.0);
    CHECK(rig->task.plan().riskUsed <= kRisk);
    CHECK(rig->task.plan().riskUsed > 0.0);
}
