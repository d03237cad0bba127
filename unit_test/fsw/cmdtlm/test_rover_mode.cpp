// The mode owner: the rover mode and the software e-stop, evented and
// announced on every change (ModeMsg) and at start-up; a call home puts the
// rover in SAFE; HK shows both.
#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/cmdtlm/rover_mode.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(RoverMode) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::BusProbe<msg::ModeMsg> modes{bus, "modes"};
    cmdtlm::RoverMode mode{clock, bus, events};
    core::InputPipe requests{bus, events, core::InputPipeConfig{"mode_requests", 8, 211, "app"}};
};

TEST(RoverMode, BootsInSafeAndAnnouncesIt) {
    CHECK(cmdtlm::Mode::kSafe == cmdtlm::kBootMode);
    CHECK(cmdtlm::Mode::kSafe == mode.mode());
    CHECK_FALSE(mode.estop());
    clock.advance(5 * core::kNsPerMs);
    mode.announce();
    msg::ModeMsg m{};
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(msg::mode::kSafe, m.mode);
    LONGS_EQUAL(0, m.estop);
    CHECK_EQUAL(5 * core::kNsPerMs, m.timeNs);
}

TEST(RoverMode, AModeChangeIsEventedAndAnnounced) {
    mode.setMode(cmdtlm::Mode::kAutonomous);
    CHECK(cmdtlm::Mode::kAutonomous == mode.mode());
    msg::ModeMsg m{};
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(msg::mode::kAutonomous, m.mode);
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(cmdtlm::events::kModeChanged, e.id);
    STRCMP_EQUAL("app: mode SAFE -> AUTONOMOUS", e.text);
}

TEST(RoverMode, TheEstopIsSetAndClearedWithTheModeKept) {
    mode.setMode(cmdtlm::Mode::kManual);
    (void)modes.drain();
    mode.setEstop(true);
    msg::ModeMsg m{};
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(1, m.estop);
    LONGS_EQUAL(msg::mode::kManual, m.mode);
    CHECK_TRUE(mode.estop());
    mode.setEstop(false);
    LONGS_EQUAL(1, modes.drain(&m));
    LONGS_EQUAL(0, m.estop);
    LONGS_EQUAL(1, test::drainEventsWithId(events, cmdtlm::events::kEstopSet));
}

TEST(RoverMode, ACallHomePutsTheRoverInSafeOnceAndIsCounted) {
    CHECK(core::isOk(requests.create()));
    CHECK(core::isOk(mode.routeRequests(requests)));
    mode.setMode(cmdtlm::Mode::kAutonomous);
    (void)modes.drain();
    msg::SafeRequestMsg call{};
    call.reason = msg::CallHomeReason::kMobilityLost;
    CHECK(core::isOk(bus.publish(call)));
    CHECK(core::isOk(bus.publish(call)));
    (void)requests.drain();
    CHECK(cmdtlm::Mode::kSafe == mode.mode());
    LONGS_EQUAL(2, mode.safeRequests());
    LONGS_EQUAL(1, modes.drain());  // the second found it SAFE: no change announced
    LONGS_EQUAL(2, test::drainEventsWithId(events, cmdtlm::events::kSafedOnRequest));
}

// The safing's numbers (what the ground reads; dictionary.def names the event).
static_assert(cmdtlm::event_data::SAFED_ON_REQUEST::kFirstId == cmdtlm::events::kSafedOnRequest &&
                  cmdtlm::event_data::SAFED_ON_REQUEST::kLastId == cmdtlm::events::kSafedOnRequest,
              "215");

TEST(RoverMode, ASafingOnRequestCarriesTheReasonAndTheModeItLeft) {
    CHECK(core::isOk(requests.create()));
    CHECK(core::isOk(mode.routeRequests(requests)));
    mode.setMode(cmdtlm::Mode::kAutonomous);
    msg::SafeRequestMsg call{};
    call.reason = msg::CallHomeReason::kNoPlanWithinRisk;
    CHECK(core::isOk(bus.publish(call)));
    (void)requests.drain();
    cmdtlm::event_data::SAFED_ON_REQUEST safed;
    CHECK_TRUE(test::lastEventData(events, cmdtlm::events::kSafedOnRequest, &safed));
    DOUBLES_EQUAL(1.0, safed.reason, 0.0);
    DOUBLES_EQUAL(static_cast<double>(cmdtlm::Mode::kAutonomous), safed.mode_before, 0.0);
}

TEST(RoverMode, HousekeepingShowsTheModeAndTheEstop) {
    mode.setMode(cmdtlm::Mode::kStandby);
    mode.setEstop(true);
    cmdtlm::HK_Tlm hk{};
    mode.fillHousekeeping(hk);
    LONGS_EQUAL(1, hk.mode);
    LONGS_EQUAL(1, hk.estop);
    LONGS_EQUAL(0, hk.cmd_accepted);  // not its field
}
