#include "fsw/core/event_log.hpp"
#include "hal/can/can_events.hpp"
#include "hal/can/can_link_monitor.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;

TEST_GROUP(CanLinkMonitor) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    MemoryCanBus wire{clock};
    MemoryCanEndpoint* flight = wire.attach("flight");
    MemoryCanEndpoint* other = wire.attach("other");
    CanLinkMonitor monitor{*flight, events, "can0"};
};

TEST(CanLinkMonitor, ReportsStateOnceThenOnlyChanges) {
    monitor.check();
    monitor.check();
    LONGS_EQUAL(1, test::drainEventsWithId(events, events::kCanStateChanged));
    wire.setBusOff(flight, true);
    monitor.check();
    wire.setBusOff(flight, false);
    monitor.check();
    LONGS_EQUAL(2, test::drainEventsWithId(events, events::kCanStateChanged));
}

TEST(CanLinkMonitor, ReceiveOverrunsAndRefusedSendsAreEvented) {
    monitor.check();
    (void)test::drainEventsWithId(events, 0);
    CanFrame f;
    f.id = 0x100;
    for (std::size_t i = 0; i < kMemoryBusRxDepth + 3; ++i) {
        (void)other->send(f);
    }
    wire.setBusOff(flight, true);
    (void)flight->send(f);
    f.id = 0xFFF;
    (void)flight->send(f);
    monitor.check();
    core::Event e;
    unsigned overrun = 0, refused = 0, invalid = 0;
    while (core::isOk(events.pop(&e))) {
        overrun += e.id == events::kCanRxOverrun ? 1U : 0U;
        refused += e.id == events::kCanTxRefused ? 1U : 0U;
        invalid += e.id == events::kCanTxInvalid ? 1U : 0U;
    }
    LONGS_EQUAL(1, overrun);
    LONGS_EQUAL(1, refused);
    LONGS_EQUAL(1, invalid);
    LONGS_EQUAL(3, flight->stats().rxOverruns);
}
