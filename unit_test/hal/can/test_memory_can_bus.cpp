#include "hal/can/memory_can_bus.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
using core::Status;

namespace {

CanFrame frame(std::uint32_t id, std::uint8_t dlc, std::uint8_t fill = 0) {
    CanFrame f;
    f.id = id;
    f.dlc = dlc;
    for (std::uint8_t i = 0; i < dlc; ++i) {
        f.data[i] = static_cast<std::uint8_t>(fill + i);
    }
    return f;
}

}  // namespace

TEST_GROUP(MemoryCanBus) {
    core::VirtualClock clock;
    MemoryCanBus wire{clock};
    MemoryCanEndpoint* a = nullptr;
    MemoryCanEndpoint* b = nullptr;
    MemoryCanEndpoint* c = nullptr;
    void setup() override {
        a = wire.attach("a");
        b = wire.attach("b");
        c = wire.attach("c");
    }
};

TEST(MemoryCanBus, EveryOtherEndpointReceivesInOrderButNotTheSender) {
    clock.sleepUntil(1234);
    CHECK(Status::kOk == a->send(frame(0x181, 6, 10)));
    CHECK(Status::kOk == a->send(frame(0x281, 2, 20)));
    for (MemoryCanEndpoint* e : {b, c}) {
        CanFrame f;
        CHECK(Status::kOk == e->receive(&f));
        LONGS_EQUAL(0x181, f.id);
        LONGS_EQUAL(6, f.dlc);
        LONGS_EQUAL(15, f.data[5]);
        CHECK_EQUAL(1234, f.timestamp);
        CHECK(Status::kOk == e->receive(&f));
        LONGS_EQUAL(0x281, f.id);
        CHECK(Status::kEmpty == e->receive(&f));
        LONGS_EQUAL(2, e->stats().rxFrames);
    }
    CanFrame f;
    CHECK(Status::kEmpty == a->receive(&f));
    LONGS_EQUAL(2, a->stats().txFrames);
}

TEST(MemoryCanBus, MalformedFramesAreRefusedAndCounted) {
    CHECK(Status::kInvalidArgument == a->send(frame(0x800, 1)));  // 12-bit id in standard format
    CanFrame longFrame = frame(0x100, 8);
    longFrame.dlc = 9;
    CHECK(Status::kInvalidArgument == a->send(longFrame));
    CanFrame ext = frame(0x1FFFFFFF, 8);
    ext.flags = CanFrame::kExtended;
    CHECK(Status::kOk == a->send(ext));
    LONGS_EQUAL(2, a->stats().txInvalid);
    LONGS_EQUAL(1, wire.stats().framesCarried);
}

TEST(MemoryCanBus, FiltersPassOnlyMatchingFramesAndCountTheRest) {
    const CanFilter onlyNode5[] = {{0x185, 0x7FF, false}, {0x705, 0x7FF, false}};
    CHECK(Status::kOk == b->setFilters(onlyNode5, 2));
    CHECK(Status::kOk == a->send(frame(0x185, 1)));
    CHECK(Status::kOk == a->send(frame(0x186, 1)));
    CHECK(Status::kOk == a->send(frame(0x705, 1)));
    CanFrame f;
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x185, f.id);
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x705, f.id);
    CHECK(Status::kEmpty == b->receive(&f));
    LONGS_EQUAL(1, b->stats().rxFiltered);
    CanFilter tooMany[kCanMaxFilters + 1] = {};
    CHECK(Status::kNoCapacity == b->setFilters(tooMany, kCanMaxFilters + 1));
}

TEST(MemoryCanBus, BabblingNodeOverflowsReceiversCountedAndBusRecovers) {
    for (std::size_t i = 0; i < kMemoryBusRxDepth + 100; ++i) {
        CHECK(Status::kOk == c->send(frame(0x001, 8, 0xAA)));  // top-priority babble
    }
    LONGS_EQUAL(100, b->stats().rxOverruns);
    CanFrame f;
    std::size_t drained = 0;
    while (core::isOk(b->receive(&f)) && drained < 10 * kMemoryBusRxDepth) {
        ++drained;
    }
    LONGS_EQUAL(kMemoryBusRxDepth, drained);
    // Once the babbler is quiet, the bus carries normal traffic again.
    CHECK(Status::kOk == a->send(frame(0x701, 1, 5)));
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x701, f.id);
}

TEST(MemoryCanBus, DropRuleLosesTheNextMatchingFramesOnly) {
    CanFaultRule drop;
    drop.kind = CanFaultKind::kDrop;
    drop.id = 0x700;
    drop.mask = 0x780;  // every heartbeat 0x700-0x77F
    drop.count = 2;
    CHECK(Status::kOk == wire.addFault(drop));
    CHECK(Status::kOk == a->send(frame(0x705, 1)));
    CHECK(Status::kOk == a->send(frame(0x185, 1)));  // does not match: delivered
    CHECK(Status::kOk == a->send(frame(0x706, 1)));
    CHECK(Status::kOk == a->send(frame(0x707, 1)));  // rule spent: delivered
    CanFrame f;
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x185, f.id);
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x707, f.id);
    CHECK(Status::kEmpty == b->receive(&f));
    LONGS_EQUAL(2, wire.stats().faultDropped);
}

TEST(MemoryCanBus, CorruptRuleFlipsTheChosenByte) {
    CanFaultRule corrupt;
    corrupt.kind = CanFaultKind::kCorrupt;
    corrupt.id = 0x181;
    corrupt.mask = 0x7FF;
    corrupt.corruptByte = 2;
    corrupt.corruptXor = 0x0F;
    CHECK(Status::kOk == wire.addFault(corrupt));
    CHECK(Status::kOk == a->send(frame(0x181, 4, 0x10)));
    CanFrame f;
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x10, f.data[0]);
    LONGS_EQUAL(0x12 ^ 0x0F, f.data[2]);
    LONGS_EQUAL(1, wire.stats().faultCorrupted);
}

TEST(MemoryCanBus, DelayRuleHoldsFramesUntilTheirTimeAndKeepsThemOrdered) {
    CanFaultRule delay;
    delay.kind = CanFaultKind::kDelay;
    delay.id = 0x281;
    delay.mask = 0x7FF;
    delay.count = 0;  // until cleared
    delay.delay = 5 * core::kNsPerMs;
    CHECK(Status::kOk == wire.addFault(delay));
    CHECK(Status::kOk == a->send(frame(0x281, 1, 1)));
    CHECK(Status::kOk == a->send(frame(0x181, 1, 2)));
    CanFrame f;
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x181, f.id);  // overtook the held frame
    CHECK(Status::kEmpty == b->receive(&f));
    clock.advance(5 * core::kNsPerMs);
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(0x281, f.id);
    CHECK_EQUAL(5 * core::kNsPerMs, f.timestamp);
    wire.clearFaults();
    CHECK(Status::kOk == a->send(frame(0x281, 1, 3)));
    CHECK(Status::kOk == b->receive(&f));
    LONGS_EQUAL(3, f.data[0]);
}

TEST(MemoryCanBus, BusOffEndpointNeitherSendsNorReceivesUntilRestored) {
    wire.setBusOff(b, true);
    CHECK(CanBusState::kBusOff == b->state());
    CHECK(Status::kUnavailable == b->send(frame(0x100, 0)));
    CHECK(Status::kOk == a->send(frame(0x101, 0)));
    CanFrame f;
    CHECK(Status::kEmpty == b->receive(&f));
    CHECK(Status::kOk == c->receive(&f));  // the rest of the bus is unaffected
    wire.setBusOff(b, false);
    CHECK(CanBusState::kErrorActive == b->state());
    CHECK(Status::kOk == b->send(frame(0x100, 0)));
    LONGS_EQUAL(1, b->stats().busOffCount);
    LONGS_EQUAL(1, b->stats().txUnavailable);
}

TEST(MemoryCanBus, EndpointCountIsBounded) {
    for (std::size_t i = 3; i < kMemoryBusMaxEndpoints; ++i) {
        CHECK(wire.attach("more") != nullptr);
    }
    POINTERS_EQUAL(nullptr, wire.attach("one-too-many"));
}
