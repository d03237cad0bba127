// Goal lists as plans (goal_plan.hpp): the text of a goal list (one drive a
// goal in order, a region kept as `within R`), which parses to its drives;
// the longest list at the largest coordinates fits kGoalPlanTextBytes, a
// smaller buffer says it does not fit; on the executive's parts: a new
// revision becomes a plan (978) when begun, the same revision again is
// ignored, the risk bound goes to the next drive; an empty list stops a goal
// plan (980) but not a mission plan; a goal plan's failed drive stops it (979).
#include <cstdint>
#include <cstring>

#include "fsw/plan_executive/plan_executive_events.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "unit_test/fsw/plan_executive/executive_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::plan_executive;
namespace ev = plan_executive::events;

namespace {

Tpn goalPlan;  // static: a plan is 47 KB
char goalText[kGoalPlanTextBytes];
test::ExecutiveParts* parts = nullptr;

msg::GoalListMsg goals(std::uint32_t revision, std::size_t count, double risk = 1e-3) {
    msg::GoalListMsg g{};
    g.revision = revision;
    g.riskBound = risk;
    g.count = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count; ++i) {
        g.goals[i].xM = 10.0 * static_cast<double>(i + 1);
        g.goals[i].yM = -2.5;
    }
    return g;
}

}  // namespace

TEST_GROUP(GoalPlanText){};

TEST(GoalPlanText, AGoalListIsAPlanOfDrivesInItsOrder) {
    msg::GoalListMsg g = goals(3, 2);
    g.goals[1].radiusM = 2.5F;
    const std::size_t n = writeGoalPlanText(g, goalText, sizeof goalText);
    CHECK(n < sizeof goalText);
    STRCMP_EQUAL("plan goal_list\n"
                 "event goal1\n"
                 "event goal2\n"
                 "activity drive1 drive start goal1 [0, inf] at 10.000 -2.500\n"
                 "activity drive2 drive goal1 goal2 [0, inf] at 20.000 -2.500 within 2.500\n"
                 "end\n",
                 goalText);
    LONGS_EQUAL(std::strlen(goalText), n);
    const ParseResult r = parsePlan(goalText, n, &goalPlan);
    CHECK(r.error == PlanError::kOk);
    LONGS_EQUAL(2, goalPlan.activityCount);
    LONGS_EQUAL(2500, goalPlan.activities[1].radiusMm);
    LONGS_EQUAL(0, goalPlan.activities[0].radiusMm);
}

TEST(GoalPlanText, TheLongestListFitsItsBufferAndASmallerBufferSaysItDoesNot) {
    msg::GoalListMsg g = goals(1, msg::kMaxGoals);
    for (std::size_t i = 0; i < msg::kMaxGoals; ++i) {
        g.goals[i].xM = -99999.999;
        g.goals[i].yM = -99999.999;
        g.goals[i].radiusM = 50.0F;
    }
    const std::size_t n = writeGoalPlanText(g, goalText, sizeof goalText);
    CHECK(n < sizeof goalText);
    CHECK(parsePlan(goalText, n, &goalPlan).error == PlanError::kOk);
    CHECK(writeGoalPlanText(g, goalText, 200) >= 200);
}

TEST_GROUP(GoalPlans) {
    void setup() override {
        parts = new test::ExecutiveParts();
        CHECK_TRUE(parts->init());
    }
    void teardown() override {
        delete parts;
        parts = nullptr;
    }
    // The pending revision begun and its plan run to dispatching.
    void begun() {
        CHECK_TRUE(parts->goals.pending());
        parts->goals.begin();
        for (int i = 0; i < 50 && parts->ctx.job != SelectionJob::kNone; ++i) {
            parts->adoption.stepSelection();
        }
        for (int i = 0; i < 50 && parts->ctx.checking; ++i) {
            parts->adoption.stepCheck();
        }
        parts->advance();
    }
};

TEST(GoalPlans, ANewRevisionBecomesAPlanOfDrivesAtItsRiskBound) {
    parts->goals.take(goals(5, 2, 2e-3));
    begun();
    LONGS_EQUAL(1, parts->count(ev::kGoalPlan));
    LONGS_EQUAL(1, parts->goals.plansMade());
    CHECK_TRUE(parts->ctx.goalPlan);
    STRCMP_EQUAL("goal_list", parts->ctx.plan().name);
    LONGS_EQUAL(1, parts->goalsSent);
    DOUBLES_EQUAL(10.0, parts->lastGoal.goals.goals[0].xM, 1e-9);
    DOUBLES_EQUAL(2e-3, parts->lastGoal.goals.riskBound, 0.0);
    LONGS_EQUAL(0, parts->lastGoal.listIndex);
    // The same revision again is not news (its risk bound still is).
    parts->goals.take(goals(5, 2, 3e-3));
    CHECK_FALSE(parts->goals.pending());
}

TEST(GoalPlans, AnEmptyListStopsAGoalPlan) {
    parts->goals.take(goals(5, 1));
    begun();
    parts->goals.take(goals(6, 0));
    parts->goals.begin();
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kGoalListEmpty));
    CHECK(parts->ctx.state == msg::PlanExecutiveState::kIdle);
    LONGS_EQUAL(0, parts->lastGoal.goals.count);  // the drive's goal cleared
}

TEST(GoalPlans, AnEmptyListLeavesAMissionPlanRunning) {
    CHECK_TRUE(parts->adopt("plan mission;event e;activity w wait start e [100, 200];end"));
    parts->goals.take(goals(6, 0));
    parts->goals.begin();
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kGoalListEmpty));
    CHECK(parts->ctx.state == msg::PlanExecutiveState::kDispatching);
}

TEST(GoalPlans, AGoalPlansFailedDriveStopsItWithoutASecondCall) {
    parts->goals.take(goals(5, 1));
    begun();
    parts->goals.stop();
    parts->drain();
    LONGS_EQUAL(1, parts->count(ev::kGoalPlanStopped));
    CHECK(parts->ctx.state == msg::PlanExecutiveState::kFailed);
    LONGS_EQUAL(0, parts->safeRequests);
}
