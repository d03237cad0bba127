// The deliberative task's part in recoveries (issue 13), on the bus
// (deliberative_rig.hpp): hazards the habitual layer has seen are obstacles of
// every replan and no leg ends inside one; fault protection's mission hold;
// no "goal reached" while the pose is uncertain; what a replan request carries.
#include <cmath>
#include <cstring>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/plan_legs.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "unit_test/fsw/deliberative/deliberative_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using msg::DeliberativeState;
using msg::HabitualState;
using msg::LegConstraint;
using test::DeliberativeRig;
namespace ev = rse::deliberative::events;

namespace {

constexpr double kGoalX = 20.0;
constexpr double kGoalY = 0.0;
constexpr double kRisk = 1e-3;
constexpr int kPlanRuns = 200;

bool contains(const char* text, const char* what) { return std::strstr(text, what) != nullptr; }

}  // namespace

TEST_GROUP(DeliberativeRecovery) {
    DeliberativeRig* rig = nullptr;
    double footprint = 0.0;
    void setup() override {
        rig = new DeliberativeRig();
        CHECK_TRUE(rig->init());
        rig->sendDriveModes();
        footprint = static_cast<double>(rig->tables.roverGeometry().footprint_radius_m);
    }
    void teardown() override { delete rig; }

    void autonomousToFirstLeg(float radiusM = 0.0F) {
        rig->setMode(DeliberativeRig::kAutonomous);
        rig->sendGoal(kGoalX, kGoalY, kRisk, radiusM);
        CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
        CHECK(rig->legs >= 1);
    }
    // The octagon the problem holds for a hazard at (cx, cy): faces at
    // distance `reach` from the centre; nullptr if none.
    const deliberative::PlanObstacle* hazardObstacle(double cx, double cy, double reach) {
        const deliberative::CcProblem& p = rig->task.problem();
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            const deliberative::PlanObstacle& o = p.obstacles[i];
            bool match = o.faceCount == deliberative::kHazardFaces;
            for (std::size_t k = 0; match && k < o.faceCount; ++k) {
                match = std::fabs(o.offset[k] - (o.normalX[k] * cx + o.normalY[k] * cy) - reach) < 1e-4;
            }
            if (match) {
                return &o;
            }
        }
        return nullptr;
    }
    // Drives every leg but the goal's last one.
    void achieveAllButLastLeg() {
        for (int i = 0; i < 60 && static_cast<std::size_t>(rig->task.status().legIndex) + 1 < rig->task.legs().count; ++i) {
            rig->achieveLeg();
            rig->run();
        }
        LONGS_EQUAL(rig->task.legs().count - 1, rig->task.status().legIndex);
        LONGS_EQUAL(1, rig->lastLeg.finalLeg);
    }
};

// ---- seen hazards ---------------------------------------------------------------

TEST(DeliberativeRecovery, ANoPathReplanPlansRoundTheSeenHazardsAndSendsNoLegEndInsideOne) {
    autonomousToFirstLeg();
    const std::uint8_t coarseObstacles = rig->task.problem().obstacleCount;
    CHECK(hazardObstacle(8.0, 0.0, 0.8 + footprint) == nullptr);
    // The habitual layer saw a rock on the route beyond the first leg end, and
    // failed up the second leg.
    const double hazard[1][3] = {{8.0, 0.0, 0.8}};
    rig->sendHazards(hazard, 1);
    rig->run();
    LONGS_EQUAL(1, rig->task.hazards().count);
    rig->x = 5.0;
    rig->y = 0.3;
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().replans);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));

    const deliberative::CcProblem& p = rig->task.problem();
    LONGS_EQUAL(coarseObstacles + 1, p.obstacleCount);
    CHECK(hazardObstacle(8.0, 0.0, 0.8 + footprint) != nullptr);
    // Every mean of the plan keeps the footprint off the disc.
    const deliberative::CcPlan& plan = rig->task.plan();
    for (std::size_t t = 0; t <= plan.steps; ++t) {
        CHECK(std::hypot(plan.meanX[t] - 8.0, plan.meanY[t]) >= 0.8 + footprint - 1e-6);
    }
    // The leg sent ends clear of the disc by the footprint and the leg-end margin.
    CHECK(std::hypot(rig->lastLeg.goalXM - 8.0, rig->lastLeg.goalYM) >=
          0.8 + footprint + deliberative::kLegEndMarginM);
    CHECK_TRUE(contains(rig->seenText(ev::kPlanStarted), "obstacles, 1 seen"));
    CHECK_TRUE(contains(rig->seenText(ev::kReplan), "from (5.00, 0.30): goals 0..0 left, 1 hazards"));
}

TEST(DeliberativeRecovery, ALegInForceEndingInsideANewlySeenHazardMovesOnToTheNextLegEnd) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    const deliberative::LegPlan legs = rig->task.legs();
    CHECK(legs.count >= 2);
    const unsigned sent = rig->legs;
    const double hazard[1][3] = {{first.goalXM, first.goalYM, 0.3}};
    rig->sendHazards(hazard, 1);
    rig->run();
    LONGS_EQUAL(sent + 1, rig->legs);
    CHECK(rig->lastLeg.legId != first.legId);
    // The first later leg end clear of the disc by the footprint and the leg-end
    // margin (the plan may put a corner within that of the first leg end).
    const double reach = 0.3 + footprint + deliberative::kLegEndMarginM;
    std::size_t next = 1;
    while (next + 1 < legs.count && std::hypot(legs.legs[next].xM - first.goalXM, legs.legs[next].yM - first.goalYM) < reach) {
        ++next;
    }
    DOUBLES_EQUAL(legs.legs[next].xM, rig->lastLeg.goalXM, 1e-12);
    DOUBLES_EQUAL(legs.legs[next].yM, rig->lastLeg.goalYM, 1e-12);
    // The skipped legs' allowances go with them.
    double length = 0.0;
    double energy = 0.0;
    for (std::size_t k = 0; k <= next; ++k) {
        length += legs.legs[k].lengthM;
        energy += legs.legs[k].energyJ;
    }
    DOUBLES_EQUAL(length, rig->lastLeg.maxPathLengthM, 1e-9);
    DOUBLES_EQUAL(energy, rig->lastLeg.maxEnergyJ, 1e-6);
    LONGS_EQUAL(next, rig->task.counters().legEndsSkipped);
    LONGS_EQUAL(next, rig->seenCount(ev::kLegEndSkipped));  // one event a leg end
    LONGS_EQUAL(0, rig->task.counters().failUps);
    // A hazard nowhere near the leg in force changes nothing.
    const double far[1][3] = {{-3.0, 8.0, 0.5}};
    rig->sendHazards(far, 1);
    rig->run();
    LONGS_EQUAL(sent + 1, rig->legs);
}

TEST(DeliberativeRecovery, MalformedHazardListsAreRefusedAndThePreviousOneKept) {
    autonomousToFirstLeg();
    const double good[1][3] = {{30.0, 9.0, 0.5}};
    rig->sendHazards(good, 1);
    rig->run();
    const std::uint32_t malformed = rig->task.counters().malformedInputs;
    const double bad[3][3] = {{8.0, 0.0, NAN}, {8.0, 0.0, -1.0}, {8.0, 0.0, 50.0}};
    for (const auto& h : bad) {
        rig->sendHazards(&h, 1);
        rig->run();
    }
    msg::KnownHazardsMsg tooMany{};
    tooMany.count = msg::kMaxKnownHazards + 1;
    (void)rig->bus.publish(tooMany);
    rig->run();
    msg::KnownHazardsMsg nowhere{};
    nowhere.count = 1;
    nowhere.hazards[0] = msg::KnownHazard{NAN, 0.0F, 0.5F, 4, {}};
    (void)rig->bus.publish(nowhere);
    rig->run();
    LONGS_EQUAL(malformed + 5, rig->task.counters().malformedInputs);
    LONGS_EQUAL(1, rig->task.hazards().count);
    DOUBLES_EQUAL(30.0, static_cast<double>(rig->task.hazards().hazards[0].xM), 0.0);
}

// ---- mission hold -----------------------------------------------------------------

TEST(DeliberativeRecovery, AHoldSendsNoLegIgnoresFailUpsAndDriveLossAndItsReleaseResendsTheLegFromThePose) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    const unsigned sent = rig->legs;
    rig->sendHold(1U << msg::hold::kDriveRecovery, 0);
    rig->run();
    CHECK_TRUE(rig->task.held());
    LONGS_EQUAL(1, rig->seenCount(ev::kMissionHeld));
    // What the hold causes counts against nothing: a fail-up and a drive under
    // recovery (declared failed for a while) neither replan nor call home.
    rig->report(HabitualState::kFailedUp, LegConstraint::kCannotFollow);
    rig->sendDriveModes(msg::DriveMode::kFailed, 2, 4.5);
    for (int i = 0; i < 30; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kExecuting == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().replans);
    LONGS_EQUAL(0, rig->task.counters().callHomes);
    LONGS_EQUAL(1, rig->task.counters().failUpsWhileHeld);
    LONGS_EQUAL(sent, rig->legs);
    rig->sendDriveModes();  // the drive recovered

    // Released where the rover now stands: the same leg end, a new id, bounds from here.
    rig->x = 2.0;
    rig->y = 0.3;
    rig->sendHold(0, 1);
    rig->run();
    CHECK_FALSE(rig->task.held());
    LONGS_EQUAL(sent + 1, rig->legs);
    CHECK(rig->lastLeg.legId != first.legId);
    DOUBLES_EQUAL(first.goalXM, rig->lastLeg.goalXM, 1e-12);
    DOUBLES_EQUAL(first.goalYM, rig->lastLeg.goalYM, 1e-12);
    const tables::PlannerTable& planner = rig->tables.planner();
    const tables::HabitualTable& habitual = rig->tables.habitual();
    const double l = std::hypot(first.goalXM - 2.0, first.goalYM - 0.3);
    DOUBLES_EQUAL((l + deliberative::kLengthAllowanceM) * (1.0 + static_cast<double>(planner.leg_slack_frac)) /
                      (1.0 - static_cast<double>(habitual.distance_margin_frac)),
                  rig->lastLeg.maxPathLengthM, 1e-9);
    CHECK(rig->lastLeg.maxPathLengthM < first.maxPathLengthM);  // nearer than the plan's start
    CHECK(rig->lastLeg.maxEnergyJ < first.maxEnergyJ);
    LONGS_EQUAL(1, rig->seenCount(ev::kMissionResumed));
    // Driving resumes: the re-sent leg's reports count again.
    rig->achieveLeg();
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().legsAchieved);
}

TEST(DeliberativeRecovery, ALegReSentAfterAHoldKeepsTheEnergyRelaxationItEarned) {
    autonomousToFirstLeg();
    const msg::LegCommandMsg first = rig->lastLeg;
    // An energy fail-up 20 % over: the bound grows x1.2 x 1.05 and the leg is re-sent.
    rig->report(HabitualState::kFailedUp, LegConstraint::kEnergy, 1.2 * 1000.0, 1000.0);
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().boundRelaxations);
    const msg::LegCommandMsg relaxed = rig->lastLeg;
    DOUBLES_EQUAL(first.maxEnergyJ * 1.2 * deliberative::kBoundRelaxHeadroom, relaxed.maxEnergyJ, 1e-6);
    // A hold and its release where the rover stands (it has not moved): the
    // bounds from here are the planned ones, and the relaxation still applies.
    rig->sendHold(1U << msg::hold::kDriveRecovery, 0);
    rig->run();
    rig->sendHold(0, 1);
    rig->run();
    CHECK(rig->lastLeg.legId != relaxed.legId);
    DOUBLES_EQUAL(relaxed.maxEnergyJ, rig->lastLeg.maxEnergyJ, 1e-6 * relaxed.maxEnergyJ);
    DOUBLES_EQUAL(first.maxPathLengthM, rig->lastLeg.maxPathLengthM, 1e-6 * first.maxPathLengthM);  // length was not relaxed
}

TEST(DeliberativeRecovery, AHeldMissionStartsNoPlanAndALegPlannedDuringTheHoldWaitsForTheRelease) {
    rig->sendHold(1U << msg::hold::kBatteryLow, 0);
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoal(kGoalX, kGoalY, kRisk);
    for (int i = 0; i < 30; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kWaiting == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().plansStarted);
    LONGS_EQUAL(0, rig->legs);
    rig->sendHold(0, 1);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    LONGS_EQUAL(1, rig->legs);

    // A plan that finishes while held keeps its first leg back until the release.
    rig->sendHold(0, 1);
    rig->x = 1.0;
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();  // replanning, sliced
    rig->sendHold(1U << msg::hold::kPoseUncertain, 1);
    for (int i = 0; i < kPlanRuns && rig->task.counters().plansFound < 2; ++i) {
        rig->run();
    }
    LONGS_EQUAL(2, rig->task.counters().plansFound);
    LONGS_EQUAL(1, rig->legs);
    rig->sendHold(0, 2);
    rig->run();
    LONGS_EQUAL(2, rig->legs);
}

TEST(DeliberativeRecovery, AHoldWithUnknownReasonBitsIsMalformedAndDoesNotHold) {
    autonomousToFirstLeg();
    const std::uint32_t malformed = rig->task.counters().malformedInputs;
    rig->sendHold(1U << msg::hold::kCount, 0);
    rig->run();
    CHECK_FALSE(rig->task.held());
    LONGS_EQUAL(malformed + 1, rig->task.counters().malformedInputs);
}

// ---- goal reached only with a certain pose ------------------------------------------

TEST(DeliberativeRecovery, TheGoalIsNotClaimedWhileThePoseUncertaintyFaultIsActive) {
    autonomousToFirstLeg();
    achieveAllButLastLeg();
    rig->sendFaults(1ULL << msg::fault::kPoseUncertain);
    rig->achieveLeg();
    for (int i = 0; i < 20; ++i) {
        rig->run();
    }
    CHECK(DeliberativeState::kExecuting == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().goalsReached);
    LONGS_EQUAL(1, rig->seenCount(ev::kGoalUnconfirmed));
    LONGS_EQUAL(0, rig->seenCount(ev::kGoalReached));
    rig->sendFaults(0);  // cleared, the rover at the goal
    rig->run();
    CHECK(DeliberativeState::kComplete == rig->task.state());
    LONGS_EQUAL(1, rig->task.counters().goalsReached);
}

TEST(DeliberativeRecovery, AGoalReachedWithASigmaAboveTheFaultLimitIsDrivenAgainFromTheCertainPose) {
    autonomousToFirstLeg();
    achieveAllButLastLeg();
    const double limit = static_cast<double>(rig->tables.estimatorNoise().pose_fault_sigma_m);
    rig->positionSigma = 1.5 * limit;
    rig->achieveLeg();
    rig->run();
    CHECK(DeliberativeState::kExecuting == rig->task.state());
    LONGS_EQUAL(1, rig->seenCount(ev::kGoalUnconfirmed));
    const unsigned sent = rig->legs;
    // Certain again, and it shows the rover 2 m short of the goal.
    rig->positionSigma = 0.5 * limit;
    rig->x = kGoalX - 2.0;
    rig->run();
    LONGS_EQUAL(sent + 1, rig->legs);
    DOUBLES_EQUAL(kGoalX, rig->lastLeg.goalXM, 1e-9);
    DOUBLES_EQUAL(kGoalY, rig->lastLeg.goalYM, 1e-9);
    LONGS_EQUAL(1, rig->lastLeg.finalLeg);
    LONGS_EQUAL(1, rig->seenCount(ev::kGoalLegResent));
    LONGS_EQUAL(0, rig->task.counters().goalsReached);
    rig->achieveLeg();
    rig->run();
    CHECK(DeliberativeState::kComplete == rig->task.state());
}

// A goal's region (a plan's `within R`): the rover 2 m short of the goal is
// inside a 3 m region, so the goal is claimed once the pose is certain, where
// the point (the test above) had its last leg driven again. A region below
// HABITUAL.goal_tolerance_m is the point.
TEST(DeliberativeRecovery, AGoalRegionIsClaimedFromACertainPoseInsideItWhereThePointWouldBeDrivenAgain) {
    const double tolerance = static_cast<double>(rig->tables.habitual().goal_tolerance_m);
    CHECK(2.0 > tolerance);  // 2 m short is not the point
    autonomousToFirstLeg(3.0F);
    achieveAllButLastLeg();
    DOUBLES_EQUAL(3.0, rig->lastLeg.arriveWithinM, 1e-6);  // the last leg carries the region
    const double limit = static_cast<double>(rig->tables.estimatorNoise().pose_fault_sigma_m);
    rig->positionSigma = 1.5 * limit;
    rig->achieveLeg();
    rig->run();
    LONGS_EQUAL(1, rig->seenCount(ev::kGoalUnconfirmed));
    const unsigned sent = rig->legs;
    rig->positionSigma = 0.5 * limit;
    rig->x = kGoalX - 2.0;
    rig->run();
    CHECK(DeliberativeState::kComplete == rig->task.state());
    LONGS_EQUAL(sent, rig->legs);  // nothing driven again
    LONGS_EQUAL(0, rig->seenCount(ev::kGoalLegResent));
    LONGS_EQUAL(1, rig->task.counters().goalsReached);
    CHECK(contains(rig->seenText(ev::kGoalReached), "reached within 3.00 m (2.00 m off)"));
}

TEST(DeliberativeRecovery, OutsideItsRegionAGoalIsNotClaimedAndItsLastLegIsDrivenAgain) {
    autonomousToFirstLeg(3.0F);
    achieveAllButLastLeg();
    const double limit = static_cast<double>(rig->tables.estimatorNoise().pose_fault_sigma_m);
    rig->positionSigma = 1.5 * limit;
    rig->achieveLeg();
    rig->run();
    const unsigned sent = rig->legs;
    rig->positionSigma = 0.5 * limit;
    rig->x = kGoalX - 3.2;
    rig->run();
    CHECK(DeliberativeState::kExecuting == rig->task.state());
    LONGS_EQUAL(sent + 1, rig->legs);
    LONGS_EQUAL(1, rig->lastLeg.finalLeg);
    DOUBLES_EQUAL(3.0, rig->lastLeg.arriveWithinM, 1e-6);  // re-sent with its region
    LONGS_EQUAL(1, rig->seenCount(ev::kGoalLegResent));
    LONGS_EQUAL(0, rig->task.counters().goalsReached);
}

// ---- the replan request ---------------------------------------------------------------

TEST(DeliberativeRecovery, AReplanRequestCarriesTheUnfinishedGoalsTheTimeAndThePositionAndThePlanStartsThere) {
    const double goals[2][2] = {{kGoalX, kGoalY}, {kGoalX, 5.0}};
    rig->setMode(DeliberativeRig::kAutonomous);
    rig->sendGoals(goals, 2, kRisk);
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    rig->x = 3.0;
    rig->y = 0.4;
    rig->run();
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    const deliberative::ReplanRequest& r = rig->task.lastReplanRequest();
    LONGS_EQUAL(rig->clock.now(), r.timeNs);
    DOUBLES_EQUAL(3.0, r.xM, 0.0);
    DOUBLES_EQUAL(0.4, r.yM, 0.0);
    LONGS_EQUAL(0, r.firstGoal);
    LONGS_EQUAL(2, r.unfinished);
    CHECK(LegConstraint::kNoPath == r.why);
    CHECK_TRUE(contains(rig->seenText(ev::kReplan), "from (3.00, 0.40): goals 0..1 left"));
    char at[32];
    std::snprintf(at, sizeof at, "t=%.2f s", static_cast<double>(r.timeNs) / 1e9);
    CHECK_TRUE(contains(rig->seenText(ev::kReplan), at));
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(3.0, rig->task.problem().startX, 0.0);
    DOUBLES_EQUAL(0.4, rig->task.problem().startY, 0.0);
}

TEST(DeliberativeRecovery, AReplanRequestWhosePositionIsStaleStartsFromTheNextFreshPose) {
    autonomousToFirstLeg();
    rig->x = 3.0;
    rig->run();
    rig->publishPose = false;  // the estimate goes quiet: what it last said gets old
    for (int i = 0; i < 12; ++i) {
        rig->run();
    }
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    DOUBLES_EQUAL(3.0, rig->task.lastReplanRequest().xM, 0.0);
    CHECK(DeliberativeState::kWaiting == rig->task.state());
    rig->x = 4.0;
    rig->publishPose = true;
    CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    DOUBLES_EQUAL(4.0, rig->task.problem().startX, 0.0);
    DOUBLES_EQUAL(4.0, rig->task.lastReplanRequest().xM, 0.0);
}

// ---- backing up after "no path" ---------------------------------------------------------

TEST(DeliberativeRecovery, NoPathTheReplansCannotFixBacksUpAlongTheTrackRetriesUpToTheLimitThenCallsHome) {
    autonomousToFirstLeg();
    for (int i = 0; i <= 20; ++i) {  // driven east along y = 0.5 to x = 6
        rig->x = 0.3 * i;
        rig->y = 0.5;
        rig->run();
    }
    const tables::PlannerTable& planner = rig->tables.planner();
    const double backUp = static_cast<double>(planner.no_path_backup_m);
    CHECK(backUp > 0.0 && backUp < 3.0);
    CHECK(planner.no_path_backup_limit >= 2);
    for (unsigned k = 0; k < planner.replan_limit; ++k) {
        rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
        rig->run();
        CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
    }
    double atX = 6.0;
    for (unsigned b = 1; b <= planner.no_path_backup_limit; ++b) {
        rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
        rig->run();
        CHECK_TRUE(rig->task.backingUp());
        LONGS_EQUAL(b, rig->task.counters().backUps);
        CHECK(DeliberativeState::kExecuting == rig->task.state());
        // Back along the track it came by, not over the last back-up.
        DOUBLES_EQUAL(atX - backUp, rig->lastLeg.goalXM, 1e-9);
        DOUBLES_EQUAL(0.5, rig->lastLeg.goalYM, 1e-9);
        LONGS_EQUAL(0, rig->lastLeg.finalLeg);
        LONGS_EQUAL(planner.replan_limit, rig->task.counters().replans);  // a back-up is not a replan
        rig->achieveLeg();
        rig->run();
        CHECK_FALSE(rig->task.backingUp());
        CHECK_TRUE(rig->runUntilState(DeliberativeState::kExecuting, kPlanRuns));
        atX -= backUp;
        DOUBLES_EQUAL(atX, rig->task.problem().startX, 1e-9);  // the retry plans from there
    }
    LONGS_EQUAL(planner.no_path_backup_limit, rig->seenCount(ev::kBackingUp));
    LONGS_EQUAL(planner.no_path_backup_limit, rig->seenCount(ev::kBackedUp));
    LONGS_EQUAL(0, rig->safeRequests);
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK(DeliberativeState::kCalledHome == rig->task.state());
    CHECK(msg::CallHomeReason::kReplansExhausted == rig->lastSafe.reason);
}

TEST(DeliberativeRecovery, TheBackUpDistanceComesFromThePlannerTableAndSkipsPointsInsideSeenHazards) {
    tables::PlannerTable t = rig->tables.planner();
    t.no_path_backup_m = 1.0F;
    t.replan_limit = 0;
    CHECK_TRUE(rig->loadTable(tables::TableId::kPlanner, t, 50));
    autonomousToFirstLeg();
    for (int i = 0; i <= 20; ++i) {
        rig->x = 0.3 * i;
        rig->run();
    }
    // A rock seen beside the track 1 m back: the first clear point is farther back.
    const double hazard[1][3] = {{4.8, 0.6, 0.1}};
    rig->sendHazards(hazard, 1);
    rig->run();
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK_TRUE(rig->task.backingUp());
    const double clear = 0.1 + footprint + deliberative::kLegEndMarginM;
    const double bx = rig->lastLeg.goalXM;
    DOUBLES_EQUAL(0.0, rig->lastLeg.goalYM, 1e-9);
    CHECK(bx < 5.0);
    CHECK(std::hypot(bx - 4.8, 0.6) >= clear);
    CHECK(std::hypot(bx + deliberative::kTrackStepM - 4.8, 0.6) < clear);  // one step nearer is not clear
    // Without the hazard, exactly the table's distance.
    delete rig;
    setup();
    CHECK_TRUE(rig->loadTable(tables::TableId::kPlanner, t, 50));
    autonomousToFirstLeg();
    for (int i = 0; i <= 20; ++i) {
        rig->x = 0.3 * i;
        rig->run();
    }
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK_TRUE(rig->task.backingUp());
    DOUBLES_EQUAL(5.0, rig->lastLeg.goalXM, 1e-9);
}

TEST(DeliberativeRecovery, NoBackUpWithoutATrackOrWithTheLimitZero) {
    tables::PlannerTable t = rig->tables.planner();
    t.replan_limit = 0;
    t.no_path_backup_limit = 0;
    CHECK_TRUE(rig->loadTable(tables::TableId::kPlanner, t, 51));
    autonomousToFirstLeg();
    for (int i = 0; i <= 20; ++i) {
        rig->x = 0.3 * i;
        rig->run();
    }
    rig->report(HabitualState::kFailedUp, LegConstraint::kNoPath);
    rig->run();
    CHECK(DeliberativeState::kCalledHome == rig->task.state());
    LONGS_EQUAL(0, rig->task.counters().backUps);
}

// ---- off the map (fault 46): fault protection's ReplanRequestMsg ------------

namespace {
void sendReplanRequest(DeliberativeRig& rig, std::uint8_t faultId, std::uint8_t attempt) {
    msg::ReplanRequestMsg r{};
    r.timeNs = rig.clock.now();
    r.faultId = faultId;
    r.attempt = attempt;
    (void)rig.bus.publish(r);
}
}  // namespace

TEST(DeliberativeRecovery, OffTheMapCancelsTheWaypointAndReplansFromTheRoverPlanningFromTheNearestPointOnTheSite) {
    autonomousToFirstLeg();
    const unsigned cancels = rig->cancels;
    const unsigned legs = rig->legs;
    const std::uint32_t plans = rig->task.counters().plansStarted;
    // Carried 1.5 m south of the site's south edge.
    const tables::CoarseMapTable& site = rig->tables.coarseMap();
    rig->x = 3.0;
    rig->y = static_cast<double>(site.y_min_m) - 1.5;
    rig->run();
    sendReplanRequest(*rig, msg::fault::kOffMap, 1);
    rig->run();
    LONGS_EQUAL(cancels + 1, rig->cancels);  // the waypoint is dropped at once
    LONGS_EQUAL(1, rig->task.counters().offMapReplans);
    LONGS_EQUAL(1, rig->seenCount(ev::kOffMapReplan));
    CHECK(contains(rig->seenText(ev::kOffMapReplan), "waypoint cancelled"));
    const deliberative::ReplanRequest& rr = rig->task.lastReplanRequest();
    DOUBLES_EQUAL(3.0, rr.xM, 1e-9);
    DOUBLES_EQUAL(rig->y, rr.yM, 1e-9);
    LONGS_EQUAL(0, rr.firstGoal);
    LONGS_EQUAL(1, rr.unfinished);

    CHECK_TRUE(rig->runUntil([&] { return rig->legs > legs; }, kPlanRuns));
    CHECK(rig->task.counters().plansStarted > plans);
    LONGS_EQUAL(1, rig->task.counters().reentryPlans);
    LONGS_EQUAL(1, rig->seenCount(ev::kPlannedFromReentry));
    // Planned from the nearest point of the site shrunk by the footprint and the inset.
    const double onSite = static_cast<double>(site.y_min_m) +
                          rse::geometry::clearanceRadiusM(rig->tables.roverGeometry()) + deliberative::kReentryInsetM;
    DOUBLES_EQUAL(3.0, rig->task.problem().startX, 1e-9);
    DOUBLES_EQUAL(onSite, rig->task.problem().startY, 1e-9);
    // The first leg's bounds are those from the rover, which stands farther off.
    const double fromRover = std::hypot(rig->lastLeg.goalXM - rig->x, rig->lastLeg.goalYM - rig->y);
    CHECK(rig->lastLeg.maxPathLengthM >= fromRover);
    LONGS_EQUAL(0, rig->task.counters().callHomes);
    LONGS_EQUAL(0, rig->task.counters().problemsRefused);
}

TEST(DeliberativeRecovery, AStartOnTheSiteIsPlannedFromTheRoverItself) {
    autonomousToFirstLeg();
    LONGS_EQUAL(0, rig->task.counters().reentryPlans);
    DOUBLES_EQUAL(rig->x, rig->task.problem().startX, 1e-9);
    DOUBLES_EQUAL(rig->y, rig->task.problem().startY, 1e-9);
}

TEST(DeliberativeRecovery, AReplanRequestWithNoMissionIsCountedAndAMalformedOneRefused) {
    rig->run();
    sendReplanRequest(*rig, msg::fault::kOffMap, 1);  // idle: no goals
    rig->run();
    LONGS_EQUAL(1, rig->task.counters().offMapIgnored);
    CHECK(contains(rig->seenText(ev::kOffMapReplan), "no mission to replan"));
    LONGS_EQUAL(0, rig->task.counters().offMapReplans);

    sendReplanRequest(*rig, msg::fault::kPoseUncertain, 1);  // only the off-map fault asks for a replan
    sendReplanRequest(*rig, msg::fault::kOffMap, 0);         // tries count from 1
    rig->run();
    LONGS_EQUAL(2, rig->task.counters().malformedInputs);
    LONGS_EQUAL(1, rig->task.counters().offMapIgnored);
}

TEST(DeliberativeRecovery, AnOffMapReplanDuringAHoldWaitsForTheRelease) {
    autonomousToFirstLeg();
    rig->sendHold(1U << msg::hold::kPoseUncertain, 0);
    rig->run();
    const unsigned legs = rig->legs;
    rig->y = static_cast<double>(rig->tables.coarseMap().y_min_m) - 1.0;
    sendReplanRequest(*rig, msg::fault::kOffMap, 1);
    for (int i = 0; i < 20; ++i) {
        rig->run();
    }
    LONGS_EQUAL(legs, rig->legs);  // nothing sent while held
    CHECK_TEXT(contains(rig->seenText(ev::kOffMapReplan), "after hold"), rig->seenText(ev::kOffMapReplan));
    rig->sendHold(0, 1);
    CHECK_TRUE(rig->runUntil([&] { return rig->legs > legs; }, kPlanRuns));
    LONGS_EQUAL(1, rig->task.counters().reentryPlans);
}
