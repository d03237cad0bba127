// The plan commands (APID 0x185): each goes to the plan executive task as a
// PlanCommandMsg, as it is; carried out when the bus took it.
#include <cstring>

#include "fsw/plan_executive/plan_commands.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;

TEST_GROUP(PlanCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::BusProbe<msg::PlanCommandMsg> sent{bus, "plan_commands"};
    plan_executive::PlanCommands commands{clock, bus};
    msg::PlanCommandMsg m{};
};

TEST(PlanCommands, OwnsThePlanExecutivesApid) { LONGS_EQUAL(0x185, commands.apid()); }

TEST(PlanCommands, AChunkAStartAndAnAbortGoAsTheyAre) {
    cmdtlm::PLAN_LOAD_Args load{};
    load.offset = 200;
    load.data_length = 5;
    std::memcpy(load.data, "plan ", 5);
    const test::AcceptedCommand chunk(CommandCode::PLAN_LOAD, load);
    CHECK_TRUE(commands.execute(chunk.verdict()).ok);
    LONGS_EQUAL(1, sent.drain(&m));
    CHECK(msg::PlanCommandKind::kChunk == m.kind);
    LONGS_EQUAL(200, m.offset);
    LONGS_EQUAL(5, m.length);
    CHECK(std::memcmp(m.data, "plan ", 5) == 0);
    const test::AcceptedCommand start(CommandCode::PLAN_START, cmdtlm::PLAN_START_Args{205, 0xDEADBEEF});
    CHECK_TRUE(commands.execute(start.verdict()).ok);
    LONGS_EQUAL(1, sent.drain(&m));
    CHECK(msg::PlanCommandKind::kStart == m.kind);
    LONGS_EQUAL(205, m.textLength);
    LONGS_EQUAL(0xDEADBEEF, m.crc32);
    const test::AcceptedCommand abort(CommandCode::PLAN_ABORT);
    CHECK_TRUE(commands.execute(abort.verdict()).ok);
    LONGS_EQUAL(1, sent.drain(&m));
    CHECK(msg::PlanCommandKind::kAbort == m.kind);
    LONGS_EQUAL(0, m.length);  // nothing left from the chunk before
}

TEST(PlanCommands, AShortPlanAndAnExtensionCarryTheirText) {
    cmdtlm::PLAN_SHORT_Args text{};
    text.text_length = 3;
    std::memcpy(text.text, "a;b", 3);
    const test::AcceptedCommand shortPlan(CommandCode::PLAN_SHORT, text);
    CHECK_TRUE(commands.execute(shortPlan.verdict()).ok);
    LONGS_EQUAL(1, sent.drain(&m));
    CHECK(msg::PlanCommandKind::kShort == m.kind);
    LONGS_EQUAL(3, m.length);
    cmdtlm::PLAN_EXTEND_Args extend{};
    extend.extra = 2.55F;
    extend.activity_length = 6;
    std::memcpy(extend.activity, "sample", 6);
    const test::AcceptedCommand more(CommandCode::PLAN_EXTEND, extend);
    CHECK_TRUE(commands.execute(more.verdict()).ok);
    LONGS_EQUAL(1, sent.drain(&m));
    CHECK(msg::PlanCommandKind::kExtend == m.kind);
    LONGS_EQUAL(2550, m.extendMs);  // to the millisecond
    CHECK(std::memcmp(m.data, "sample", 6) == 0);
}
