// The command and telemetry service's own commands (APID 0x180): NOOP,
// RESET_COUNTERS (everywhere, every application included), REQUEST_HK,
// SET_MODE through the mode owner, AUTH_RESYNC's report.
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/service_commands.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;

namespace {

class CountedApp final : public cmdtlm::AppCommands {
public:
    std::uint16_t apid() const override { return 0x183; }
    cmdtlm::CommandOutcome execute(const cmdtlm::CommandVerdict&) override { return {}; }
    void resetCounters() override { ++resets; }
    unsigned resets = 0;
};

}  // namespace

TEST_GROUP(ServiceCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    core::Executive executive{clock, events};
    cmdtlm::GroundLinks links;
    cmdtlm::TelemetryOutput output{clock, events, links};
    cmdtlm::RoverMode mode{clock, bus, events};
    cmdtlm::CommandRouter router{bus, events, mode};
    cmdtlm::CommandTask commandTask{clock, events, links, output, router};
    cmdtlm::HousekeepingTask collection{executive, bus, events};
    cmdtlm::HousekeepingTelemetry housekeeping{collection};
    cmdtlm::ServiceCommands commands{
        cmdtlm::ServiceCommands::Parts{events, bus, executive, output, commandTask, router, mode, housekeeping}};
    CountedApp tables;
    test::RecordingSink sink;

    cmdtlm::CommandOutcome execute(CommandCode code) {
        const test::AcceptedCommand c(code);
        return commands.execute(c.verdict());
    }
};

TEST(ServiceCommands, OwnsTheServicesApid) { LONGS_EQUAL(0x180, commands.apid()); }

TEST(ServiceCommands, NoopIsEventedWithItsKeyAndSequence) {
    CHECK_TRUE(execute(CommandCode::NOOP).ok);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(cmdtlm::events::kNoop, e.id);
    STRCMP_EQUAL("cmd: NOOP (key 1, seq 7)", e.text);
}

TEST(ServiceCommands, SetModeGoesThroughTheModeOwner) {
    const test::AcceptedCommand c(CommandCode::SET_MODE, cmdtlm::SET_MODE_Args{3});
    CHECK_TRUE(commands.execute(c.verdict()).ok);
    CHECK(cmdtlm::Mode::kManual == mode.mode());
}

TEST(ServiceCommands, RequestHkSendsHousekeepingInTheNextRun) {
    housekeeping.pack(test::frameAt(5), sink);
    LONGS_EQUAL(0, sink.count<cmdtlm::HK_Tlm>());
    CHECK_TRUE(execute(CommandCode::REQUEST_HK).ok);
    housekeeping.pack(test::frameAt(6), sink);
    housekeeping.pack(test::frameAt(7), sink);
    LONGS_EQUAL(1, sink.count<cmdtlm::HK_Tlm>());
}

TEST(ServiceCommands, AuthResyncIsReportedForAKeyAndRefusedWithoutOne) {
    test::AcceptedCommand keyed(CommandCode::AUTH_RESYNC, cmdtlm::AUTH_RESYNC_Args{0, 0});
    CHECK_TRUE(commands.execute(keyed.verdict()).ok);
    LONGS_EQUAL(1, test::drainEventsWithId(events, cmdtlm::events::kAuthResynced));
    cmdtlm::CommandVerdict unkeyed = keyed.verdict();
    unkeyed.keyId = cmdtlm::kNoKey;
    const cmdtlm::CommandOutcome o = commands.execute(unkeyed);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(1, o.detail);
}

TEST(ServiceCommands, ResetCountersZeroesTheCountersEverywhereAndSaysSo) {
    CHECK(core::isOk(router.add(&tables)));
    (void)bus.publish(msg::ModeMsg{});  // nobody subscribed: counted
    events.report(999, core::Severity::kWarning, "before");
    CHECK(bus.stats().published > 0);
    CHECK_TRUE(execute(CommandCode::RESET_COUNTERS).ok);
    LONGS_EQUAL(0, bus.stats().published);
    LONGS_EQUAL(0, bus.stats().noSubscribers);
    LONGS_EQUAL(1, events.total());  // the reset's own event only
    LONGS_EQUAL(0, events.count(core::Severity::kWarning));
    LONGS_EQUAL(1, tables.resets);   // every application's, through the router
    LONGS_EQUAL(0, commandTask.counters().accepted);
    core::Event e;
    while (core::isOk(events.pop(&e)) && e.id != cmdtlm::events::kCountersReset) {
    }
    LONGS_EQUAL(cmdtlm::events::kCountersReset, e.id);
    STRCMP_EQUAL("cmd: counters reset", e.text);
}
