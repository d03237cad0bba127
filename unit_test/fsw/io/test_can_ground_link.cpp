// The ISO-TP ground link as a PacketLink, against a peer IsoTpChannel on the same
// in-memory CAN bus: commands in through receive(), telemetry out through the
// transmit queues that service() drains by priority and in order, every refusal
// counted, a ground that was not listening served as soon as it is heard, and no
// heap in the frame loop.
#include <cstdint>
#include <cstring>

#include "fsw/io/can_ground_link.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/isotp.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "hal/link/link_events.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;

namespace {

constexpr core::TimeNs kFrame = 10 * core::kNsPerMs;
constexpr int kMaxFrames = 500;  // bounds every "run until" loop (5 s of rover time)

hal::IsoTpConfig groundConfig() {
    hal::IsoTpConfig c;
    c.txId = io::kGroundUplinkCobId;
    c.rxId = io::kGroundDownlinkCobId;
    c.blockSize = 8;
    return c;
}

void fill(std::uint8_t* data, std::size_t length, std::uint8_t tag) {
    for (std::size_t i = 0; i < length; ++i) {
        data[i] = static_cast<std::uint8_t>(tag * 13U + i * 7U);
    }
}

}  // namespace

TEST_GROUP(CanGroundLink) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    core::EventLog groundEvents{clock};
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* roverCan = wire.attach("rover");
    hal::MemoryCanEndpoint* groundCan = wire.attach("ground");
    io::CanGroundLink link{*roverCan, clock, events};
    hal::IsoTpChannel ground{*groundCan, clock, groundEvents, groundConfig()};
    bool groundListens = true;
    std::uint8_t sent[hal::kIsoTpMaxMessage] = {};
    std::uint8_t got[hal::kIsoTpMaxMessage] = {};
    std::uint8_t want[hal::kIsoTpMaxMessage] = {};
    std::size_t length = 0;

    // One minor frame: the rover takes what the ground sent (as the CANopen master
    // routes 0x6C0) and services the link, as the CAN I/O task does; then the
    // ground does the same on its side.
    void frame() {
        hal::CanFrame f;
        while (core::isOk(roverCan->receive(&f))) {  // bounded by the endpoint's queue
            if (f.id == io::kGroundUplinkCobId) {
                link.onFrame(f, clock.now());
            }
        }
        link.service();
        if (groundListens) {
            while (core::isOk(groundCan->receive(&f))) {
                if (f.id == io::kGroundDownlinkCobId) {
                    ground.onFrame(f);
                }
            }
            ground.poll();
        }
        clock.advance(kFrame);
    }
    // The ground's whole message, sent and completed on the wire.
    void uplink(const std::uint8_t* data, std::size_t size) {
        CHECK(Status::kOk == ground.send(data, size));
        for (int i = 0; i < kMaxFrames && ground.txBusy(); ++i) {
            frame();
        }
        CHECK(ground.txResult() == hal::IsoTpTxResult::kDone);
        frame();  // the rover has seen the last frame
    }
    // Frames until the ground holds a complete downlink message; its size, or 0.
    std::size_t downlinked() {
        for (int i = 0; i < kMaxFrames; ++i) {
            if (core::isOk(ground.receive(got, sizeof got, &length))) {
                return length;
            }
            frame();
        }
        return 0;
    }
};

TEST(CanGroundLink, ACommandFromThePeerArrivesThroughReceive) {
    fill(sent, 200, 1);
    CHECK(Status::kEmpty == link.receive(got, sizeof got, &length));
    uplink(sent, 200);
    CHECK(Status::kOk == link.receive(got, 256, &length));
    LONGS_EQUAL(200, length);
    MEMCMP_EQUAL(sent, got, 200);
    CHECK(Status::kEmpty == link.receive(got, 256, &length));
    LONGS_EQUAL(1, link.stats().rxPackets);
    LONGS_EQUAL(0, link.stats().rxDropped);
    STRCMP_EQUAL("can-isotp", link.name());
}

TEST(CanGroundLink, CommandsArriveInTheOrderSent) {
    const std::size_t sizes[] = {5, 256, 7, 60};
    for (std::size_t i = 0; i < 4; ++i) {
        fill(sent, sizes[i], static_cast<std::uint8_t>(i));
        uplink(sent, sizes[i]);
    }
    for (std::size_t i = 0; i < 4; ++i) {
        CHECK(Status::kOk == link.receive(got, 256, &length));
        LONGS_EQUAL(sizes[i], length);
        fill(want, sizes[i], static_cast<std::uint8_t>(i));
        MEMCMP_EQUAL(want, got, length);
    }
    LONGS_EQUAL(4, link.stats().rxPackets);
}

TEST(CanGroundLink, AnUploadLongerThanACommandIsRefusedOnTheWireAndCounted) {
    fill(sent, 300, 2);
    CHECK(Status::kOk == ground.send(sent, 300));
    for (int i = 0; i < kMaxFrames && ground.txBusy(); ++i) {
        frame();
    }
    CHECK(ground.txResult() == hal::IsoTpTxResult::kPeerOverflow);  // FC OVERFLOW from the rover
    CHECK(Status::kEmpty == link.receive(got, sizeof got, &length));
    LONGS_EQUAL(1, link.stats().rxDropped);
    LONGS_EQUAL(1, link.channel().stats().rxTooLong);
}

TEST(CanGroundLink, APacketLongerThanTheReadersBufferIsDroppedCountedAndEvented) {
    fill(sent, 100, 3);
    uplink(sent, 100);
    fill(sent, 20, 4);
    uplink(sent, 20);
    CHECK(Status::kTooLarge == link.receive(got, 50, &length));
    LONGS_EQUAL(100, length);
    LONGS_EQUAL(1, link.stats().rxDropped);
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkRxTooLarge));
    // Gone, not kept: the next read is the next packet.
    CHECK(Status::kOk == link.receive(got, 50, &length));
    LONGS_EQUAL(20, length);
    MEMCMP_EQUAL(sent, got, 20);
}

TEST(CanGroundLink, SendOnlyQueuesServiceDrainsTheQueueInOrderAcrossFrames) {
    const std::size_t sizes[] = {512, 5, 300};
    for (std::size_t i = 0; i < 3; ++i) {
        fill(sent, sizes[i], static_cast<std::uint8_t>(10 + i));
        CHECK(Status::kOk == link.send(sent, sizes[i]));
    }
    LONGS_EQUAL(3, link.txQueued());
    LONGS_EQUAL(0, roverCan->stats().txFrames);  // send() never touches the bus
    LONGS_EQUAL(3, link.stats().txPackets);

    frame();
    LONGS_EQUAL(2, link.txQueued());  // the 512-byte packet is under way, the others wait
    CHECK_TRUE(link.channel().txBusy());

    for (std::size_t i = 0; i < 3; ++i) {
        const std::size_t size = downlinked();
        LONGS_EQUAL(sizes[i], size);
        fill(want, sizes[i], static_cast<std::uint8_t>(10 + i));
        MEMCMP_EQUAL(want, got, size);
    }
    frame();  // the rover's next service sees the last transmission done
    LONGS_EQUAL(3, link.txCompleted());
    LONGS_EQUAL(0, link.txAborted());
    LONGS_EQUAL(0, link.txQueued());
    LONGS_EQUAL(0, link.stats().errors);
}

TEST(CanGroundLink, SingleFramePacketsGoSeveralInOneFrame) {
    for (std::uint8_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        fill(sent, 5, i);
        CHECK(Status::kOk == link.send(sent, 5));
    }
    link.service();
    LONGS_EQUAL(0, link.txQueued());
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth, roverCan->stats().txFrames);
    frame();
    for (std::uint8_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        CHECK(Status::kOk == ground.receive(got, sizeof got, &length));
        fill(want, 5, i);
        MEMCMP_EQUAL(want, got, 5);
    }
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth, link.txCompleted());
}

TEST(CanGroundLink, AFullTransmitQueueRefusesCountsAndEvents) {
    fill(sent, 100, 5);
    for (std::size_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        CHECK(Status::kOk == link.send(sent, 100));
    }
    CHECK(Status::kFull == link.send(sent, 100));
    CHECK(Status::kFull == link.send(sent, 100));
    CHECK(Status::kFull == link.send(sent, 100));
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth, link.stats().txPackets);
    LONGS_EQUAL(3, link.stats().txDropped);
    LONGS_EQUAL(2, rse::test::drainEventsWithId(events, hal::events::kLinkTxFull));  // the 1st and 2nd
    // Once a packet is under way there is room again.
    frame();
    CHECK(Status::kOk == link.send(sent, 100));
}

TEST(CanGroundLink, PacketsOverTheTelemetryLimitOrEmptyAreRefused) {
    CHECK(Status::kTooLarge == link.send(sent, cmdtlm::kMaxTelemetryPacket + 1));
    CHECK(Status::kInvalidArgument == link.send(sent, 0));
    CHECK(Status::kInvalidArgument == link.send(nullptr, 4));
    LONGS_EQUAL(3, link.stats().txDropped);
    LONGS_EQUAL(0, link.txQueued());
    LONGS_EQUAL(2, rse::test::drainEventsWithId(events, hal::events::kLinkTxInvalid));
    CHECK(Status::kOk == link.send(sent, cmdtlm::kMaxTelemetryPacket));
}

TEST(CanGroundLink, ATransmissionTheGroundNeverAnswersIsCountedAndTheNextPacketGoes) {
    groundListens = false;  // no flow control: N_Bs expires
    fill(sent, 100, 6);
    CHECK(Status::kOk == link.send(sent, 100));
    CHECK(Status::kOk == link.send(sent, 3));
    for (int i = 0; i < kMaxFrames && link.txAborted() == 0; ++i) {
        frame();
    }
    LONGS_EQUAL(1, link.txAborted());
    LONGS_EQUAL(1, link.stats().errors);
    LONGS_EQUAL(1, link.channel().stats().timeoutBs);
    frame();
    LONGS_EQUAL(1, link.txCompleted());  // the single-frame packet needs no answer
    LONGS_EQUAL(0, link.txQueued());
}

TEST(CanGroundLink, TxRoomIsTheQueuesRoomWhileTheGroundAnswersAndUnlimitedOnceItStops) {
    fill(sent, 100, 7);
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth, link.txRoom(hal::TxPriority::kEvent));
    CHECK(Status::kOk == link.sendWithPriority(sent, 100, hal::TxPriority::kEvent));
    CHECK(Status::kOk == link.sendWithPriority(sent, 100, hal::TxPriority::kEvent));
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth - 2, link.txRoom(hal::TxPriority::kEvent));
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth, link.txRoom(hal::TxPriority::kRoutine));  // per priority
    // The ground goes silent: the packet in flight waits out N_Bs. Holding
    // events back for a ground that does not answer would only delay them on
    // the other links: the room is no longer its limit.
    groundListens = false;
    for (int i = 0; i < kMaxFrames && link.txAborted() == 0; ++i) {
        frame();
    }
    LONGS_EQUAL(1, link.txAborted());
    CHECK(hal::kTxRoomUnlimited == link.txRoom(hal::TxPriority::kEvent));
    // A single-frame packet completes without an answer: it proves nothing.
    CHECK(Status::kOk == link.send(sent, 3));
    frame();
    frame();
    CHECK(hal::kTxRoomUnlimited == link.txRoom(hal::TxPriority::kEvent));
    // Heard again (a command): the queue's room is the limit once more.
    groundListens = true;
    uplink(sent, 5);
    CHECK(Status::kOk == link.receive(got, sizeof got, &length));
    CHECK(link.txRoom(hal::TxPriority::kEvent) <= io::kGroundLinkTxQueueDepth);
}

TEST(CanGroundLink, AnAcknowledgementNeverWaitsBehindRoutineTelemetry) {
    fill(sent, 100, 7);
    for (std::size_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        CHECK(Status::kOk == link.send(sent, 100));
    }
    CHECK(Status::kFull == link.send(sent, 100));  // routine telemetry has filled its queue ...
    fill(sent, 34, 8);
    CHECK(Status::kOk == link.sendWithPriority(sent, 34, hal::TxPriority::kAck));  // ... not the ack's
    fill(sent, 123, 9);
    CHECK(Status::kOk == link.sendWithPriority(sent, 123, hal::TxPriority::kEvent));
    LONGS_EQUAL(1, link.txFull(hal::TxPriority::kRoutine));
    LONGS_EQUAL(0, link.txFull(hal::TxPriority::kEvent));
    LONGS_EQUAL(0, link.txFull(hal::TxPriority::kAck));
    LONGS_EQUAL(1, link.stats().txDropped);
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth + 2, link.txQueued());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkTxFull));
    // The acknowledgement goes first, then the event, then routine telemetry in order.
    LONGS_EQUAL(34, downlinked());
    fill(want, 34, 8);
    MEMCMP_EQUAL(want, got, 34);
    LONGS_EQUAL(123, downlinked());
    fill(want, 123, 9);
    MEMCMP_EQUAL(want, got, 123);
    fill(want, 100, 7);
    for (std::size_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        LONGS_EQUAL(100, downlinked());
        MEMCMP_EQUAL(want, got, 100);
    }
    frame();
    LONGS_EQUAL(io::kGroundLinkTxQueueDepth + 2, link.txCompleted());
    // A full queue of one priority refuses only that priority, and says which.
    for (std::size_t i = 0; i < io::kGroundLinkTxQueueDepth; ++i) {
        CHECK(Status::kOk == link.sendWithPriority(sent, 34, hal::TxPriority::kAck));
    }
    CHECK(Status::kFull == link.sendWithPriority(sent, 34, hal::TxPriority::kAck));
    CHECK(Status::kOk == link.send(sent, 100));
    LONGS_EQUAL(1, link.txFull(hal::TxPriority::kAck));
    core::Event e;
    CHECK(core::isOk(events.pop(&e)));
    LONGS_EQUAL(hal::events::kLinkTxFull, e.id);
    STRCMP_CONTAINS("acknowledgement queue full", e.text);
}

TEST(CanGroundLink, WhileRoutinePacketsWaitEveryFourthPacketIsRoutine) {
    // Events e1..e8 and routine r1..r3 queued before the first service.
    for (std::uint8_t i = 1; i <= 8; ++i) {
        fill(sent, 20, i);
        CHECK(Status::kOk == link.sendWithPriority(sent, 20, hal::TxPriority::kEvent));
    }
    for (std::uint8_t i = 101; i <= 103; ++i) {
        fill(sent, 20, i);
        CHECK(Status::kOk == link.send(sent, 20));
    }
    static_assert(io::kGroundLinkRoutineShare == 4, "the order below assumes 1 routine packet in 4");
    const std::uint8_t order[] = {1, 2, 3, 101, 4, 5, 6, 102, 7, 8, 103};
    for (std::uint8_t tag : order) {
        LONGS_EQUAL(20, downlinked());
        fill(want, 20, tag);
        MEMCMP_EQUAL(want, got, 20);
    }
    // With no routine packet waiting, events go back to back.
    for (std::uint8_t i = 1; i <= 5; ++i) {
        fill(sent, 20, i);
        CHECK(Status::kOk == link.sendWithPriority(sent, 20, hal::TxPriority::kEvent));
    }
    for (std::uint8_t i = 1; i <= 5; ++i) {
        LONGS_EQUAL(20, downlinked());
        fill(want, 20, i);
        MEMCMP_EQUAL(want, got, 20);
    }
}

TEST(CanGroundLink, AGroundThatWasNotListeningGetsTheWaitingPacketAsSoonAsItCommands) {
    // A ground tool that exits after its ack: the rover's next packet finds nobody.
    groundListens = false;
    fill(sent, 100, 10);
    CHECK(Status::kOk == link.send(sent, 100));
    for (int i = 0; i < 30; ++i) {  // 300 ms: the FF is out, nobody answers
        frame();
    }
    CHECK_TRUE(link.channel().txBusy());
    // The next ground tool starts: what was on the wire before is not its to see.
    hal::CanFrame f;
    while (core::isOk(groundCan->receive(&f))) {  // bounded by the endpoint's queue
    }
    groundListens = true;
    fill(sent, 30, 11);
    CHECK(Status::kOk == ground.send(sent, 30));  // its command
    int frames = 0;
    for (; frames < kMaxFrames && !core::isOk(ground.receive(got, sizeof got, &length)); ++frames) {
        frame();
    }
    LONGS_EQUAL(100, length);  // the packet that waited, sent again at once ...
    CHECK(frames <= 5);        // ... not after N_Bs (1 s, 100 frames)
    fill(want, 100, 10);
    MEMCMP_EQUAL(want, got, 100);
    LONGS_EQUAL(1, link.channel().stats().ffResent);
    LONGS_EQUAL(0, link.channel().stats().timeoutBs);
    CHECK(Status::kOk == link.receive(got, 256, &length));  // and the command arrived
    LONGS_EQUAL(30, length);
    // Its acknowledgement follows straight away.
    fill(sent, 34, 12);
    CHECK(Status::kOk == link.sendWithPriority(sent, 34, hal::TxPriority::kAck));
    CHECK(downlinked() == 34);
    fill(want, 34, 12);
    MEMCMP_EQUAL(want, got, 34);
    frame();
    LONGS_EQUAL(2, link.txCompleted());
    LONGS_EQUAL(0, link.txAborted());
}

TEST(CanGroundLink, FramesOfTrafficBothWaysAllocateNothing) {
    std::uint32_t up = 0;
    std::uint32_t down = 0;
    rse::test::AllocationWatch watch;
    for (std::uint8_t round = 0; round < 20; ++round) {
        fill(sent, 120, round);
        (void)ground.send(sent, 120);
        (void)link.send(sent, 200);
        for (int i = 0; i < 10; ++i) {
            frame();
            up += core::isOk(link.receive(got, 256, &length)) ? 1U : 0U;
            down += core::isOk(ground.receive(got, sizeof got, &length)) ? 1U : 0U;
        }
    }
    const auto allocations = watch.count();
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(20, up);
    LONGS_EQUAL(20, down);
}
