// Publishing the layer's messages (publisher.hpp): a refusal is counted and
// evented on its 1st, 2nd, 4th ... occurrence, naming what was not published.
#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/publisher.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
namespace ev = rse::deliberative::events;

TEST_GROUP(Publisher) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::EventRecord seen{events};
    deliberative::Publisher out{bus, events};
};

TEST(Publisher, APublishedMessageReachesTheBusAndCountsNothing) {
    core::PipeId probe = 0;
    CHECK(core::isOk(bus.createPipe("probe", 4, &probe)));
    CHECK(core::isOk(bus.subscribe(probe, msg::ids::kLegCommand)));
    msg::LegCommandMsg leg{};
    leg.legId = 3;
    out.publish(leg, "leg");
    core::Message m;
    CHECK(core::isOk(bus.receive(probe, &m)));
    LONGS_EQUAL(0, out.failures());
    LONGS_EQUAL(0, seen.count(ev::kPublishFailed));
}

TEST(Publisher, RefusalsAreCountedAndEventedThrottled) {
    for (int i = 0; i < 5; ++i) {
        out.published(core::Status::kTooLarge, "plan path");
    }
    LONGS_EQUAL(5, out.failures());
    LONGS_EQUAL(3, seen.count(ev::kPublishFailed));  // 1st, 2nd, 4th
    STRCMP_EQUAL("deliberative: plan path not published (too-large), 4 so far", seen.text(ev::kPublishFailed));
}
