#include <cstdio>
#include <cstring>

#include "fsw/app/fsw_app.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/housekeeping_msg.hpp"
#include "fsw/msg/mode_msgs.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(FswApp) {
    core::VirtualClock clock;
    hal::MemoryCanBus can{clock};  // nothing else attached
    app::FswApp fsw{clock, *can.attach("fsw")};  // the group object is heap-allocated by CppUTest
};

TEST(FswApp, PublishesHousekeepingOncePerSecondWithTaskTiming) {
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(nullptr));
    core::PipeId probe;
    CHECK(core::Status::kOk == fsw.bus().createPipe("probe", 8, &probe));
    CHECK(core::Status::kOk == fsw.bus().subscribe(probe, msg::ids::kHousekeeping));

    fsw.run(nullptr, 350);  // 3.5 s: HK at 0, 1, 2 and 3 s

    core::Message m;
    msg::HousekeepingMsg hk{};
    unsigned seen = 0;
    while (core::isOk(fsw.bus().receive(probe, &m))) {
        CHECK(core::Status::kOk == m.decode(&hk));
        CHECK_EQUAL(static_cast<core::TimeNs>(seen) * core::kNsPerSec, hk.timeNs);
        LONGS_EQUAL(seen * 100, hk.framesRun);  // counters as of the frame it ran in
        ++seen;
    }
    LONGS_EQUAL(4, seen);
    LONGS_EQUAL(16, hk.taskCount);
    const char* const names[] = {"tables",   "can_io",       "estimator",    "drive_modes", "health",
                                 "fault_prot", "follower",   "commands",     "manual_drive", "housekeeping",
                                 "telemetry", "console",     "habitual",     "plan_exec",    "deliberative",
                                 "watchdog"};
    for (std::size_t i = 0; i < 16; ++i) {
        STRCMP_EQUAL(names[i], hk.tasks[i].name);
    }
    LONGS_EQUAL(301, hk.tasks[1].runs);    // every frame, this one included
    LONGS_EQUAL(301, hk.tasks[4].runs);    // health: every frame, before housekeeping in the table
    LONGS_EQUAL(301, hk.tasks[5].runs);    // fault protection: every frame, right after health
    LONGS_EQUAL(3, hk.tasks[9].runs);      // runs before the 4th collection
    LONGS_EQUAL(300, hk.tasks[10].runs);   // every frame, but after housekeeping in the table
    LONGS_EQUAL(30, hk.tasks[11].runs);    // 10 Hz console, offset 1
    LONGS_EQUAL(30, hk.tasks[12].runs);    // 10 Hz habitual layer, offset 5
    LONGS_EQUAL(0, hk.frameOverruns);
    CHECK(hk.eventsTotal >= 2);            // app and executive start-up events
}

TEST(FswApp, QuietConsoleStillDrainsEventsSoNoneAreLost) {
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(nullptr));
    for (int i = 0; i < 3 * static_cast<int>(core::kEventRingDepth); ++i) {
        fsw.events().report(999, core::Severity::kDebug, "burst %d", i);
        fsw.run(nullptr, 10);  // the console runs once per 10 frames
    }
    LONGS_EQUAL(0, fsw.events().lost());
    CHECK(fsw.console().eventsWritten() >= 3 * core::kEventRingDepth);
}

TEST(FswApp, ConsoleWritesHousekeepingAndEventLines) {
    char text[4096] = {};
    std::FILE* stream = fmemopen(text, sizeof text - 1, "w");
    CHECK(stream != nullptr);
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(stream));
    fsw.run(nullptr, 101);
    fsw.shutdown("test over");
    std::fclose(stream);
    CHECK(std::strstr(text, "HK  #1 frames=0") != nullptr);
    CHECK(std::strstr(text, "HK  #2 frames=100") != nullptr);
    CHECK(std::strstr(text, "EVT 202 INFO  app: rse-fsw initialised, 16 tasks, ") != nullptr);
    CHECK(std::strstr(text, "EVT 203 INFO  app: test over, shutting down cleanly") != nullptr);
}

TEST(FswApp, MalformedHousekeepingIsCountedNotPrinted) {
    char text[4096] = {};
    std::FILE* stream = fmemopen(text, sizeof text - 1, "w");
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(stream));
    const std::uint8_t truncated[8] = {};
    CHECK(core::Status::kOk == fsw.bus().publish(msg::ids::kHousekeeping, truncated, sizeof truncated));
    fsw.run(nullptr, 20);
    std::fclose(stream);
    LONGS_EQUAL(1, fsw.console().malformed());
    LONGS_EQUAL(1, fsw.console().housekeepingSeen());  // the real one from frame 0
    POINTERS_EQUAL(nullptr, std::strstr(text, "HK  #0"));
}

// A call home (the deliberative layer's SafeRequestMsg) is taken by the mode owner
// (cmdtlm::RoverMode, through the command router) on its next run and counted; from SAFE (the boot
// mode) no mode change is announced. AUTONOMOUS -> SAFE on a call home:
// unit_test/system/lockstep/test_lockstep_deliberative.cpp.
TEST(FswApp, ASafeRequestIsTakenByTheModeOwnerAndCounted) {
    CHECK(core::Status::kOk == fsw.useLabKey());  // a lab bench: asked for explicitly
    CHECK(core::Status::kOk == fsw.init(nullptr));
    core::PipeId probe;
    CHECK(core::Status::kOk == fsw.bus().createPipe("probe", 8, &probe));
    CHECK(core::Status::kOk == fsw.bus().subscribe(probe, msg::ids::kMode));
    msg::SafeRequestMsg request{};
    request.reason = msg::CallHomeReason::kMobilityLost;
    CHECK(core::isOk(fsw.bus().publish(request)));
    fsw.run(nullptr, 2);
    LONGS_EQUAL(1, fsw.roverMode().safeRequests());
    CHECK(cmdtlm::Mode::kSafe == fsw.roverMode().mode());
    // Already SAFE (the boot mode): counted and evented, no mode change announced.
    core::Message m;
    unsigned modes = 0;
    while (core::isOk(fsw.bus().receive(probe, &m))) {
        ++modes;
    }
    LONGS_EQUAL(0, modes);
    // A request of the wrong size is counted and evented, not acted on.
    const std::uint8_t shortRequest[3] = {};
    CHECK(core::isOk(fsw.bus().publish(msg::ids::kSafeRequest, shortRequest, sizeof shortRequest)));
    fsw.run(nullptr, 2);
    LONGS_EQUAL(1, fsw.roverMode().safeRequests());
    LONGS_EQUAL(1, fsw.commandRouter().malformedRequests());
}

// Issue 14 item 4: the public lab key is never a silent default. With no key
// loaded (no rse-fsw --key-file, no --lab-key) the application does not start,
// and says why in a critical event.
TEST(FswApp, RefusesToStartWithoutACommandKey) {
    LONGS_EQUAL(0, fsw.keys().size());
    CHECK(core::Status::kNotInitialized == fsw.init(nullptr));
    LONGS_EQUAL(0, fsw.keys().size());  // nothing loaded behind our back
    bool said = false;
    core::Event event;
    while (core::isOk(fsw.events().pop(&event))) {
        said = said || (event.id == 201 && event.severity == core::Severity::kCritical &&
                        std::strstr(event.text, "command keys") != nullptr &&
                        std::strstr(event.text, "--lab-key") != nullptr);
    }
    CHECK_TRUE(said);
}

TEST(FswApp, UseLabKeyLoadsTheLabKeyUnderIdOneAndInitWarns) {
    CHECK(core::Status::kOk == fsw.useLabKey());
    CHECK(core::Status::kOk == fsw.init(nullptr));
    CHECK_TRUE(fsw.keys().labKeyInUse());
    LONGS_EQUAL(cmdtlm::kLabKeyId, fsw.keys().labKeyId());
    bool warned = false;
    core::Event event;
    while (core::isOk(fsw.events().pop(&event))) {
        warned = warned || (event.id == 504 && event.severity == core::Severity::kWarning);
    }
    CHECK_TRUE(warned);
}
