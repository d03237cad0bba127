// The in-memory ground link: packets keep their order and bytes both ways, each
// direction holds a fixed number of packets and counts what it refuses, and none
// of it touches the heap.
#include <cstdint>
#include <cstring>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_task.hpp"
#include "hal/link/memory_packet_link.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;

static_assert(hal::kMemoryLinkMaxPacket >= cmdtlm::kMaxTelemetryPacket &&
                  hal::kMemoryLinkMaxPacket >= cmdtlm::kMaxCommandPacket,
              "the memory link must carry the largest CCSDS packet either way");
static_assert(hal::kMemoryLinkUplinkDepth > cmdtlm::kCommandQueueDepth,
              "a test must be able to uplink more commands in one frame than the command queue holds");

namespace {

// A packet whose every byte says which packet it is and where the byte sits.
void fill(std::uint8_t* data, std::size_t length, std::uint8_t tag) {
    for (std::size_t i = 0; i < length; ++i) {
        data[i] = static_cast<std::uint8_t>(tag * 31U + i);
    }
}

}  // namespace

TEST_GROUP(MemoryPacketLink) {
    hal::MemoryPacketLink link;
    std::uint8_t sent[hal::kMemoryLinkMaxPacket + 1] = {};
    std::uint8_t got[hal::kMemoryLinkMaxPacket + 1] = {};
    std::uint8_t want[hal::kMemoryLinkMaxPacket + 1] = {};
    std::size_t length = 0;
};

TEST(MemoryPacketLink, UplinkPacketsReachTheFlightInOrderAndIntact) {
    const std::size_t sizes[] = {1, 7, 256, 100};
    for (std::size_t i = 0; i < 4; ++i) {
        fill(sent, sizes[i], static_cast<std::uint8_t>(i));
        CHECK(Status::kOk == link.groundSend(sent, sizes[i]));
    }
    LONGS_EQUAL(4, link.uplinkQueued());
    for (std::size_t i = 0; i < 4; ++i) {
        CHECK(Status::kOk == link.receive(got, sizeof got, &length));
        LONGS_EQUAL(sizes[i], length);
        fill(want, sizes[i], static_cast<std::uint8_t>(i));
        MEMCMP_EQUAL(want, got, length);
    }
    CHECK(Status::kEmpty == link.receive(got, sizeof got, &length));
    LONGS_EQUAL(0, length);
    LONGS_EQUAL(4, link.stats().rxPackets);
    LONGS_EQUAL(0, link.stats().rxDropped);
}

TEST(MemoryPacketLink, DownlinkPacketsReachTheGroundInOrderAndIntact) {
    const std::size_t sizes[] = {512, 12, 300};
    for (std::size_t i = 0; i < 3; ++i) {
        fill(sent, sizes[i], static_cast<std::uint8_t>(10 + i));
        CHECK(Status::kOk == link.send(sent, sizes[i]));
    }
    for (std::size_t i = 0; i < 3; ++i) {
        CHECK(Status::kOk == link.groundReceive(got, sizeof got, &length));
        LONGS_EQUAL(sizes[i], length);
        fill(want, sizes[i], static_cast<std::uint8_t>(10 + i));
        MEMCMP_EQUAL(want, got, length);
    }
    CHECK(Status::kEmpty == link.groundReceive(got, sizeof got, &length));
    LONGS_EQUAL(3, link.stats().txPackets);
    LONGS_EQUAL(0, link.stats().txDropped);
}

TEST(MemoryPacketLink, FullUplinkRefusesAndCountsAsDroppedForTheFlight) {
    for (std::size_t i = 0; i < hal::kMemoryLinkUplinkDepth; ++i) {
        fill(sent, 20, static_cast<std::uint8_t>(i));
        CHECK(Status::kOk == link.groundSend(sent, 20));
    }
    CHECK(Status::kFull == link.groundSend(sent, 20));
    CHECK(Status::kFull == link.groundSend(sent, 20));
    LONGS_EQUAL(2, link.stats().rxDropped);
    // What was queued is kept, oldest first; then there is room again.
    CHECK(Status::kOk == link.receive(got, sizeof got, &length));
    fill(want, 20, 0);
    MEMCMP_EQUAL(want, got, 20);
    CHECK(Status::kOk == link.groundSend(sent, 20));
    LONGS_EQUAL(hal::kMemoryLinkUplinkDepth, link.uplinkQueued());
}

TEST(MemoryPacketLink, FullDownlinkRefusesAndCounts) {
    fill(sent, 64, 1);
    for (std::size_t i = 0; i < hal::kMemoryLinkDownlinkDepth; ++i) {
        CHECK(Status::kOk == link.send(sent, 64));
    }
    CHECK(Status::kFull == link.send(sent, 64));
    LONGS_EQUAL(hal::kMemoryLinkDownlinkDepth, link.stats().txPackets);
    LONGS_EQUAL(1, link.stats().txDropped);
    CHECK(Status::kOk == link.groundReceive(got, sizeof got, &length));
    CHECK(Status::kOk == link.send(sent, 64));
}

TEST(MemoryPacketLink, PacketsOverTheSlotSizeOrEmptyAreRefusedBothWays) {
    CHECK(Status::kTooLarge == link.send(sent, hal::kMemoryLinkMaxPacket + 1));
    CHECK(Status::kInvalidArgument == link.send(sent, 0));
    CHECK(Status::kInvalidArgument == link.send(nullptr, 5));
    LONGS_EQUAL(3, link.stats().txDropped);
    CHECK(Status::kTooLarge == link.groundSend(sent, hal::kMemoryLinkMaxPacket + 1));
    CHECK(Status::kInvalidArgument == link.groundSend(sent, 0));
    LONGS_EQUAL(2, link.stats().rxDropped);
    LONGS_EQUAL(0, link.uplinkQueued());
    LONGS_EQUAL(0, link.downlinkQueued());
    CHECK(Status::kOk == link.send(sent, hal::kMemoryLinkMaxPacket));  // the limit itself is fine
}

TEST(MemoryPacketLink, FlightDropsAPacketLongerThanItsBufferAndReadsTheNextOne) {
    fill(sent, 300, 1);
    CHECK(Status::kOk == link.groundSend(sent, 300));
    fill(sent, 30, 2);
    CHECK(Status::kOk == link.groundSend(sent, 30));
    CHECK(Status::kTooLarge == link.receive(got, 256, &length));
    LONGS_EQUAL(300, length);
    LONGS_EQUAL(1, link.stats().rxDropped);
    CHECK(Status::kOk == link.receive(got, 256, &length));
    LONGS_EQUAL(30, length);
    fill(want, 30, 2);
    MEMCMP_EQUAL(want, got, 30);
    LONGS_EQUAL(1, link.stats().rxPackets);
}

TEST(MemoryPacketLink, GroundKeepsAPacketLongerThanItsBufferUntilItBringsALargerOne) {
    fill(sent, 400, 3);
    CHECK(Status::kOk == link.send(sent, 400));
    CHECK(Status::kTooLarge == link.groundReceive(got, 100, &length));
    LONGS_EQUAL(400, length);
    CHECK(Status::kOk == link.groundReceive(got, sizeof got, &length));
    LONGS_EQUAL(400, length);
    MEMCMP_EQUAL(sent, got, 400);
}

TEST(MemoryPacketLink, NullLengthOrNullBufferIsRefused) {
    CHECK(Status::kOk == link.groundSend(sent, 4));
    CHECK(Status::kInvalidArgument == link.receive(got, sizeof got, nullptr));
    CHECK(Status::kInvalidArgument == link.receive(nullptr, 10, &length));
    CHECK(Status::kInvalidArgument == link.groundReceive(got, sizeof got, nullptr));
    LONGS_EQUAL(1, link.uplinkQueued());  // nothing consumed
}

TEST(MemoryPacketLink, ReportsItsName) { STRCMP_EQUAL("memory", link.name()); }

TEST(MemoryPacketLink, TrafficBothWaysAllocatesNothing) {
    rse::test::AllocationWatch watch;
    std::uint32_t moved = 0;
    for (std::uint8_t round = 0; round < 200; ++round) {
        fill(sent, 1U + round, round);
        moved += core::isOk(link.groundSend(sent, 1U + round)) ? 1U : 0U;
        moved += core::isOk(link.receive(got, sizeof got, &length)) ? 1U : 0U;
        moved += core::isOk(link.send(sent, 1U + round)) ? 1U : 0U;
        moved += core::isOk(link.groundReceive(got, sizeof got, &length)) ? 1U : 0U;
        link.service();
    }
    LONGS_EQUAL(0, watch.count());
    LONGS_EQUAL(800, moved);
}
