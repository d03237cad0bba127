// The executive's commands: EXEC_SET_TASK disables or enables a rate-group
// row, except the protected rows (refused with the reason); fault protection's
// task restarts run a row again.
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/executive_commands.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;
using cmdtlm::TaskCommandRefusal;

namespace {

struct CountingTask final : core::Task {
    unsigned runs = 0;
    void run(const core::FrameContext&) override { ++runs; }
};

}  // namespace

TEST_GROUP(ExecutiveCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    core::Executive executive{clock, events};
    cmdtlm::ExecutiveCommands commands{executive, events};
    CountingTask a, b;
    void setup() override {
        const core::RateGroupEntry table[] = {{"a", &a, 1, 0, 1000}, {"b", &b, 1, 0, 1000}};
        CHECK(core::isOk(executive.init(core::ExecutiveConfig{10 * core::kNsPerMs, 100}, table, 2)));
        CHECK(core::isOk(commands.protectRow(1, TaskCommandRefusal::kCanIo)));
        (void)test::drainEventsWithId(events, 0);
    }
    cmdtlm::CommandOutcome setTask(std::uint8_t row, std::uint8_t enabled) {
        const test::AcceptedCommand c(CommandCode::EXEC_SET_TASK, cmdtlm::EXEC_SET_TASK_Args{row, enabled});
        return commands.execute(c.verdict());
    }
};

TEST(ExecutiveCommands, OwnsTheExecutivesApid) { LONGS_EQUAL(0x184, commands.apid()); }

TEST(ExecutiveCommands, GroundDisablesAndEnablesARow) {
    CHECK_TRUE(setTask(0, 0).ok);
    (void)executive.run(nullptr, 3);
    LONGS_EQUAL(0, a.runs);
    LONGS_EQUAL(1, test::drainEventsWithId(events, cmdtlm::events::kTaskSetByGround));
    CHECK_TRUE(setTask(0, 1).ok);
    (void)executive.run(nullptr, 1);
    LONGS_EQUAL(1, a.runs);
    LONGS_EQUAL(2, commands.taskCommands());
}

TEST(ExecutiveCommands, AProtectedRowAndARowBeyondTheTableAreRefusedWithTheReason) {
    cmdtlm::CommandOutcome o = setTask(1, 0);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(static_cast<int>(TaskCommandRefusal::kCanIo), o.detail);
    CHECK(TaskCommandRefusal::kCanIo == commands.lastTaskRefusal());
    CHECK_TRUE(setTask(1, 1).ok);  // enabling is always safe
    o = setTask(9, 0);
    LONGS_EQUAL(static_cast<int>(TaskCommandRefusal::kNoSuchRow), o.detail);
    LONGS_EQUAL(2, commands.taskCommandsRefused());
    LONGS_EQUAL(2, test::drainEventsWithId(events, cmdtlm::events::kTaskSetRefused));
}

TEST(ExecutiveCommands, OnlyARowsReasonMayProtectIt) {
    CHECK(core::Status::kInvalidArgument == commands.protectRow(core::kMaxTasks, TaskCommandRefusal::kCanIo));
    CHECK(core::Status::kInvalidArgument == commands.protectRow(0, TaskCommandRefusal::kNone));
    CHECK(core::Status::kInvalidArgument == commands.protectRow(0, TaskCommandRefusal::kNoSuchRow));
}

TEST(ExecutiveCommands, FaultProtectionsTaskRestartRunsTheRowAgain) {
    core::InputPipe requests{bus, events, core::InputPipeConfig{"mode_requests", 8, 211, "app"}};
    CHECK(core::isOk(requests.create()));
    CHECK(core::isOk(commands.routeRequests(requests)));
    CHECK(core::isOk(executive.setTaskEnabled(0, false)));
    CHECK(core::isOk(bus.publish(msg::TaskRestartMsg{0, 0, {}})));
    CHECK(core::isOk(bus.publish(msg::TaskRestartMsg{0, 7, {}})));  // no such row
    (void)requests.drain();
    (void)executive.run(nullptr, 1);
    LONGS_EQUAL(1, a.runs);
    LONGS_EQUAL(1, commands.taskRestarts());
    LONGS_EQUAL(1, commands.taskRestartsRefused());
    core::Event e;
    (void)events.pop(&e);  // the executive's own enable event
    unsigned restarted = 0, refused = 0;
    while (core::isOk(events.pop(&e))) {
        restarted += e.id == cmdtlm::events::kTaskRestarted ? 1U : 0U;
        refused += e.id == cmdtlm::events::kTaskRestartRefused ? 1U : 0U;
    }
    LONGS_EQUAL(1, restarted);
    LONGS_EQUAL(1, refused);
}
