// The console task: events (with its own cursor) and housekeeping lines to a
// stream; a housekeeping message that does not decode counted by its pipe,
// evented, never printed. In the FswApp: unit_test/fsw/app/test_fsw_app.cpp.
#include <cstdio>
#include <cstring>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/console_task.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(ConsoleTask) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    cmdtlm::ConsoleTask console{bus, events};
    char text[2048] = {};
    std::FILE* stream = nullptr;
    void setup() override {
        stream = fmemopen(text, sizeof text - 1, "w");
        CHECK(stream != nullptr);
        CHECK(core::isOk(console.init(stream)));
    }
    void teardown() override { std::fclose(stream); }
};

TEST(ConsoleTask, WritesEventsAndHousekeepingLines) {
    clock.advance(1500 * core::kNsPerMs);
    events.report(321, core::Severity::kWarning, "something to say");
    msg::HousekeepingMsg hk{};
    hk.timeNs = clock.now();
    hk.housekeepingCount = 2;
    hk.framesRun = 150;
    CHECK(core::isOk(bus.publish(hk)));
    console.run(test::frameAt(151));
    std::fflush(stream);
    CHECK(std::strstr(text, "[     1.500] EVT 321 WARN  something to say\n") != nullptr);
    CHECK(std::strstr(text, "[     1.500] HK  #2 frames=150 ") != nullptr);
    LONGS_EQUAL(1, console.eventsWritten());
    LONGS_EQUAL(1, console.housekeepingSeen());
    // The console reads with its own cursor: the event is still there for telemetry.
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(321, e.id);
}

TEST(ConsoleTask, AHousekeepingMessageThatDoesNotDecodeIsCountedAndEventedNotPrinted) {
    const std::uint8_t truncated[8] = {};
    CHECK(core::isOk(bus.publish(msg::ids::kHousekeeping, truncated, sizeof truncated)));
    console.drain();
    LONGS_EQUAL(1, console.malformed());
    LONGS_EQUAL(0, console.housekeepingSeen());
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(cmdtlm::events::kBusMessageMalformed, e.id);
    console.drain();  // the next drain prints that event, and no HK line
    std::fflush(stream);
    POINTERS_EQUAL(nullptr, std::strstr(text, "HK  #"));
    CHECK(std::strstr(text, "EVT 211 ERROR console: bus message") != nullptr);
}

TEST(ConsoleTask, AQuietConsoleCountsWhatItWouldHaveWritten) {
    core::SoftwareBus otherBus{clock, events};
    cmdtlm::ConsoleTask quiet{otherBus, events};
    CHECK(core::isOk(quiet.init(nullptr)));
    events.report(1, core::Severity::kInfo, "x");
    quiet.drain();
    LONGS_EQUAL(1, quiet.eventsWritten());
}
