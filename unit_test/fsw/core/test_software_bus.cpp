#include <cstring>

#include "fsw/core/core_events.hpp"
#include "fsw/core/software_bus.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::core;

namespace {

struct PingMsg {
    static constexpr MsgId kMsgId = 0x0101;
    std::uint32_t value;
};

struct PongMsg {
    static constexpr MsgId kMsgId = 0x0102;
    std::uint32_t value;
};

}  // namespace

TEST_GROUP(SoftwareBus) {
    VirtualClock clock{1000};
    EventLog events{clock};
    // CppUTest creates each test object on the heap, so the bus's fixed storage
    // (a few hundred KiB) does not land on the stack.
    SoftwareBus busStorage{clock, events};
    SoftwareBus* bus = &busStorage;
};

TEST(SoftwareBus, DeliversEachMessageToEverySubscriber) {
    PipeId a, b, c, other;
    CHECK(Status::kOk == bus->createPipe("a", 4, &a));
    CHECK(Status::kOk == bus->createPipe("b", 4, &b));
    CHECK(Status::kOk == bus->createPipe("c", 4, &c));
    CHECK(Status::kOk == bus->createPipe("other", 4, &other));
    CHECK(Status::kOk == bus->subscribe(a, PingMsg::kMsgId));
    CHECK(Status::kOk == bus->subscribe(b, PingMsg::kMsgId));
    CHECK(Status::kOk == bus->subscribe(c, PingMsg::kMsgId));
    CHECK(Status::kOk == bus->subscribe(other, PongMsg::kMsgId));

    CHECK(Status::kOk == bus->publish(PingMsg{41}));
    CHECK(Status::kOk == bus->publish(PingMsg{42}));

    for (PipeId p : {a, b, c}) {
        Message m;
        PingMsg ping{};
        CHECK(Status::kOk == bus->receive(p, &m));
        CHECK(Status::kOk == m.decode(&ping));
        LONGS_EQUAL(41, ping.value);
        LONGS_EQUAL(0, m.header.sequence);
        CHECK_EQUAL(1000, m.header.time);
        CHECK(Status::kOk == bus->receive(p, &m));
        CHECK(Status::kOk == m.decode(&ping));
        LONGS_EQUAL(42, ping.value);
        LONGS_EQUAL(1, m.header.sequence);
        CHECK(Status::kEmpty == bus->receive(p, &m));
    }
    Message m;
    CHECK(Status::kEmpty == bus->receive(other, &m));
    LONGS_EQUAL(2, bus->stats().published);
    LONGS_EQUAL(6, bus->stats().delivered);
    LONGS_EQUAL(0, bus->stats().dropped);
}

TEST(SoftwareBus, FullQueueDropsForThatSubscriberOnlyCountedAndEvented) {
    PipeId slow, fast;
    CHECK(Status::kOk == bus->createPipe("slow", 2, &slow));
    CHECK(Status::kOk == bus->createPipe("fast", 8, &fast));
    CHECK(Status::kOk == bus->subscribe(slow, PingMsg::kMsgId));
    CHECK(Status::kOk == bus->subscribe(fast, PingMsg::kMsgId));
    for (std::uint32_t i = 0; i < 5; ++i) {
        CHECK(Status::kOk == bus->publish(PingMsg{i}));
    }
    LONGS_EQUAL(3, bus->pipeStats(slow)->dropped);
    LONGS_EQUAL(2, bus->pipeStats(slow)->delivered);
    LONGS_EQUAL(2, bus->pipeStats(slow)->highWater);
    LONGS_EQUAL(0, bus->pipeStats(fast)->dropped);
    LONGS_EQUAL(5, bus->pipeStats(fast)->delivered);
    LONGS_EQUAL(3, bus->stats().dropped);
    // Evented on the 1st and 2nd drop (powers of two), not the 3rd.
    LONGS_EQUAL(2, rse::test::drainEventsWithId(events, events::kBusQueueOverflow));

    // The slow pipe kept the oldest two; the fast one got all five in order.
    Message m;
    PingMsg ping{};
    CHECK(Status::kOk == bus->receive(slow, &m));
    CHECK(Status::kOk == m.decode(&ping));
    LONGS_EQUAL(0, ping.value);
    for (std::uint32_t i = 0; i < 5; ++i) {
        CHECK(Status::kOk == bus->receive(fast, &m));
        CHECK(Status::kOk == m.decode(&ping));
        LONGS_EQUAL(i, ping.value);
    }
}

TEST(SoftwareBus, OversizedMessageRejectedCountedEventedNotDelivered) {
    PipeId p;
    CHECK(Status::kOk == bus->createPipe("p", 4, &p));
    CHECK(Status::kOk == bus->subscribe(p, 0x0200));
    static std::uint8_t big[kBusMaxPayload + 1];
    CHECK(Status::kTooLarge == bus->publish(0x0200, big, sizeof big));
    CHECK(Status::kOk == bus->publish(0x0200, big, kBusMaxPayload));  // the limit itself is fine
    LONGS_EQUAL(1, bus->stats().rejectedTooLarge);
    LONGS_EQUAL(1, bus->stats().published);
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, events::kBusMessageTooLarge));
    Message m;
    CHECK(Status::kOk == bus->receive(p, &m));
    LONGS_EQUAL(kBusMaxPayload, m.header.length);
    CHECK(Status::kEmpty == bus->receive(p, &m));
}

TEST(SoftwareBus, MessageWithoutSubscribersIsCounted) {
    CHECK(Status::kOk == bus->publish(PongMsg{1}));
    LONGS_EQUAL(1, bus->stats().noSubscribers);
    LONGS_EQUAL(0, bus->stats().delivered);
}

TEST(SoftwareBus, DecodeChecksTypeAndSize) {
    PipeId p;
    CHECK(Status::kOk == bus->createPipe("p", 4, &p));
    CHECK(Status::kOk == bus->subscribe(p, PingMsg::kMsgId));
    const std::uint16_t shortPayload = 7;
    CHECK(Status::kOk == bus->publish(PingMsg::kMsgId, &shortPayload, sizeof shortPayload));
    Message m;
    CHECK(Status::kOk == bus->receive(p, &m));
    PingMsg ping{};
    CHECK(Status::kWrongType == m.decode(&ping));  // right id, wrong size
    PongMsg pong{};
    CHECK(Status::kWrongType == m.decode(&pong));  // wrong id
}

TEST(SoftwareBus, ConfigurationBeyondCapacityIsRejected) {
    PipeId p;
    CHECK(Status::kInvalidArgument == bus->createPipe("zero", 0, &p));
    CHECK(Status::kNoCapacity == bus->createPipe("huge", kBusTotalQueueSlots + 1, &p));
    CHECK(Status::kOk == bus->createPipe("p", 1, &p));
    CHECK(Status::kOk == bus->subscribe(p, 0x0300));
    CHECK(Status::kAlreadyExists == bus->subscribe(p, 0x0300));
    CHECK(Status::kNotFound == bus->subscribe(static_cast<PipeId>(p + 1), 0x0300));
    for (MsgId id = 0; id < kBusMaxRoutes - 1; ++id) {
        CHECK(Status::kOk == bus->subscribe(p, static_cast<MsgId>(0x0400 + id)));
    }
    CHECK(Status::kNoCapacity == bus->subscribe(p, 0x0fff));
    LONGS_EQUAL(5, bus->stats().configRejected);
    LONGS_EQUAL(5, rse::test::drainEventsWithId(events, events::kBusConfigRejected));
    Message m;
    CHECK(Status::kNotFound == bus->receive(static_cast<PipeId>(p + 1), &m));
}

TEST(SoftwareBus, PipeCountIsBounded) {
    PipeId p;
    for (std::size_t i = 0; i < kBusMaxPipes; ++i) {
        CHECK(Status::kOk == bus->createPipe("p", 1, &p));
    }
    CHECK(Status::kNoCapacity == bus->createPipe("one-too-many", 1, &p));
}

TEST(SoftwareBus, NullPayloadAndNullOutputAreRejectedNotCrashed) {
    PipeId p;
    CHECK(Status::kOk == bus->createPipe("p", 2, &p));
    CHECK(Status::kOk == bus->subscribe(p, 0x0500));
    CHECK(Status::kInvalidArgument == bus->publish(0x0500, nullptr, 4));
    CHECK(Status::kOk == bus->publish(0x0500, nullptr, 0));  // an empty message is legal
    LONGS_EQUAL(1, bus->stats().rejectedInvalid);
    LONGS_EQUAL(1, bus->stats().published);
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, events::kBusPublishInvalid));
    CHECK(Status::kInvalidArgument == bus->receive(p, nullptr));
    Message m;
    CHECK(Status::kOk == bus->receive(p, &m));
    LONGS_EQUAL(0, m.header.length);
}
