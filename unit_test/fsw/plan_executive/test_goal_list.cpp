// The goal list the goal commands keep: every change is a new revision (the
// plan executive task replans on a new revision); a full list refuses a target
// and stays as it was.
#include "fsw/plan_executive/goal_list.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(GoalList) {
    plan_executive::GoalList list{1e-3};
};

TEST(GoalList, StartsEmptyAtItsDefaultRiskBound) {
    LONGS_EQUAL(0, list.count());
    DOUBLES_EQUAL(1e-3, list.riskBound(), 0.0);
    LONGS_EQUAL(0, list.revision());
}

TEST(GoalList, EveryChangeIsANewRevision) {
    CHECK(core::isOk(list.addTarget(1.0, 2.0, 3)));
    LONGS_EQUAL(1, list.revision());
    list.replaceWithGoal(5.0, 6.0, 0.02);
    LONGS_EQUAL(2, list.revision());
    LONGS_EQUAL(1, list.count());
    DOUBLES_EQUAL(5.0, list.message().goals[0].xM, 0.0);
    DOUBLES_EQUAL(6.0, list.message().goals[0].yM, 0.0);
    LONGS_EQUAL(0, list.message().goals[0].priority);
    DOUBLES_EQUAL(0.02, list.riskBound(), 0.0);
    list.setRiskBound(1e-4);
    LONGS_EQUAL(3, list.revision());
    list.clear();
    LONGS_EQUAL(4, list.revision());
    LONGS_EQUAL(0, list.count());
    DOUBLES_EQUAL(1e-4, list.riskBound(), 0.0);  // clearing the goals keeps the bound
}

TEST(GoalList, ATargetBeyondAFullListIsRefusedAndChangesNothing) {
    for (std::size_t i = 0; i < msg::kMaxGoals; ++i) {
        CHECK(core::isOk(list.addTarget(static_cast<double>(i), 0.0, static_cast<std::uint8_t>(i))));
    }
    const std::uint32_t revision = list.revision();
    LONGS_EQUAL(static_cast<int>(core::Status::kFull), static_cast<int>(list.addTarget(99.0, 0.0, 1)));
    LONGS_EQUAL(msg::kMaxGoals, list.count());
    LONGS_EQUAL(revision, list.revision());
}
