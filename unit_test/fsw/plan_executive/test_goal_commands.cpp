// The mission-goal commands (APID 0x181), owned by the plan executive: each
// changes the goal list, which is announced (GoalListMsg) and evented (208,
// with its numbers: GOALS_COMMANDED); ADD_TARGET on a full list fails.
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/plan_executive/goal_commands.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "fsw/tables/default_tables.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;
namespace evd = rse::cmdtlm::event_data;

// The dictionary's event data for 208 names the plan executive's constant.
static_assert(evd::GOALS_COMMANDED::kFirstId == plan_executive::events::kGoalsCommanded &&
                  evd::GOALS_COMMANDED::kLastId == plan_executive::events::kGoalsCommanded,
              "208");

TEST_GROUP(GoalCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    test::BusProbe<msg::GoalListMsg> announced{bus, "goals"};
    plan_executive::GoalCommands commands{clock, bus, events, tables};
    void setup() override {
        CHECK(core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
        (void)test::drainEventsWithId(events, 0);
    }
    cmdtlm::CommandOutcome addTarget(double x, double y, std::uint8_t priority) {
        const test::AcceptedCommand c(CommandCode::ADD_TARGET, cmdtlm::ADD_TARGET_Args{x, y, priority});
        return commands.execute(c.verdict());
    }
};

TEST(GoalCommands, OwnsTheGoalsApid) { LONGS_EQUAL(0x181, commands.apid()); }

TEST(GoalCommands, StartUpAnnouncesTheEmptyListAtThePlannerTablesRiskBound) {
    commands.init();
    msg::GoalListMsg m{};
    LONGS_EQUAL(1, announced.drain(&m));
    LONGS_EQUAL(0, m.count);
    DOUBLES_EQUAL(tables.planner().default_risk_bound, m.riskBound, 0.0);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(plan_executive::events::kGoalsCommanded, e.id);
    LONGS_EQUAL(208, e.id);
    STRCMP_EQUAL("app: 0 goal(s), risk bound 0.001", e.text);
}

TEST(GoalCommands, GotoReplacesTheGoalsAndEachChangeIsAnnounced) {
    CHECK_TRUE(addTarget(1.0, 2.0, 5).ok);
    const test::AcceptedCommand go(CommandCode::GOTO, cmdtlm::GOTO_Args{20.0, -3.0, 0.01});
    CHECK_TRUE(commands.execute(go.verdict()).ok);
    msg::GoalListMsg m{};
    LONGS_EQUAL(2, announced.drain(&m));
    LONGS_EQUAL(1, m.count);
    DOUBLES_EQUAL(20.0, m.goals[0].xM, 0.0);
    DOUBLES_EQUAL(-3.0, m.goals[0].yM, 0.0);
    DOUBLES_EQUAL(0.01, m.riskBound, 0.0);
    const test::AcceptedCommand risk(CommandCode::SET_RISK_BOUND, cmdtlm::SET_RISK_BOUND_Args{1e-6});
    CHECK_TRUE(commands.execute(risk.verdict()).ok);
    const test::AcceptedCommand clear(CommandCode::CLEAR_GOALS);
    CHECK_TRUE(commands.execute(clear.verdict()).ok);
    LONGS_EQUAL(2, announced.drain(&m));
    LONGS_EQUAL(0, m.count);
    DOUBLES_EQUAL(1e-6, m.riskBound, 0.0);
    LONGS_EQUAL(4, test::drainEventsWithId(events, plan_executive::events::kGoalsCommanded));
    LONGS_EQUAL(0, commands.goals().count());
}

TEST(GoalCommands, TheGoalListTakenCarriesItsCountAndRiskBound) {
    const test::AcceptedCommand go(CommandCode::GOTO, cmdtlm::GOTO_Args{20.0, -3.0, 0.01});
    CHECK_TRUE(commands.execute(go.verdict()).ok);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(plan_executive::events::kGoalsCommanded, e.id);
    STRCMP_EQUAL("app: 1 goal(s), risk bound 0.01", e.text);
    evd::GOALS_COMMANDED goals;
    CHECK_TRUE(goals.unpack(e.id, e.data));
    DOUBLES_EQUAL(1.0, goals.goal_count, 0.0);
    DOUBLES_EQUAL(0.01, goals.risk_bound, 0.0);
}

TEST(GoalCommands, ATargetBeyondAFullListFailsWithTheListsSizeAndChangesNothing) {
    for (std::size_t i = 0; i < msg::kMaxGoals; ++i) {
        CHECK_TRUE(addTarget(static_cast<double>(i), 0.0, 1).ok);
    }
    (void)announced.drain();
    const cmdtlm::CommandOutcome o = addTarget(99.0, 0.0, 1);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(msg::kMaxGoals, o.detail);
    LONGS_EQUAL(0, announced.drain());
    LONGS_EQUAL(msg::kMaxGoals, commands.goals().count());
}

TEST(GoalCommands, ACommandOfAnotherApidIsNotItsToCarryOut) {
    const test::AcceptedCommand noop(CommandCode::NOOP);
    const cmdtlm::CommandOutcome o = commands.execute(noop.verdict());
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(-1, o.detail);
    LONGS_EQUAL(0, announced.drain());
}
