// ISO-TP channel: every error reason. Hostile or silent peers are played by hand
// from a third endpoint; for each reason the test checks its counter, its event,
// that nothing else broke, and that normal transfers work right afterwards.
#include <cstdint>
#include <cstring>
#include <initializer_list>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/can_events.hpp"
#include "hal/can/isotp.hpp"
#include "hal/can/memory_can_bus.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
using core::Status;

namespace {

constexpr std::uint32_t kRoverRx = 0x6C0;
constexpr std::uint32_t kRoverTx = 0x6C1;
constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr std::size_t kMaxSteps = 20000;

// Passes everything through to an endpoint, but can refuse sends (kFull) the way
// a full SocketCAN transmit queue does; MemoryCanEndpoint itself never fills up.
class RefusingBus final : public CanBus {
public:
    explicit RefusingBus(CanBus& inner) : inner_(inner) {}
    Status send(const CanFrame& frame) override {
        if (refuseAll || refuseNext > 0) {
            if (refuseNext > 0) {
                --refuseNext;
            }
            ++refused;
            return Status::kFull;
        }
        return inner_.send(frame);
    }
    Status receive(CanFrame* out) override { return inner_.receive(out); }
    Status setFilters(const CanFilter* filters, std::size_t count) override {
        return inner_.setFilters(filters, count);
    }
    CanBusState state() const override { return inner_.state(); }
    const CanBusStats& stats() const override { return inner_.stats(); }

    bool refuseAll = false;
    std::uint32_t refuseNext = 0;
    std::uint32_t refused = 0;

private:
    CanBus& inner_;
};

IsoTpConfig makeConfig(std::uint32_t tx, std::uint32_t rx) {
    IsoTpConfig c;
    c.txId = tx;
    c.rxId = rx;
    return c;  // defaults: BS 8, STmin 0, no padding, 1000 ms timeouts, 10 WAITs
}

void fillPattern(std::uint8_t* data, std::size_t n, std::uint8_t start) {
    for (std::size_t i = 0; i < n; ++i) {
        data[i] = static_cast<std::uint8_t>(start + i * 7U);
    }
}

}  // namespace

// a: the channel under test (rover ids) on an endpoint that can refuse sends.
// b: a well-behaved peer (ground ids). evil: a third endpoint that injects frames
// on a's rxId and sees what a sends.
TEST_GROUP(IsoTpErrors) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    MemoryCanBus wire{clock};
    MemoryCanEndpoint* epA = wire.attach("rover");
    MemoryCanEndpoint* epB = wire.attach("ground");
    MemoryCanEndpoint* evil = wire.attach("evil");
    RefusingBus busA{*epA};
    IsoTpChannel* a = nullptr;
    IsoTpChannel* b = nullptr;
    std::uint8_t payload[kIsoTpMaxMessage + 1] = {};
    std::uint8_t received[kIsoTpMaxMessage + 1] = {};

    void setup() override {
        const CanFilter onlyA[] = {{kRoverTx, 0x7FF, false}};
        CHECK(Status::kOk == evil->setFilters(onlyA, 1));
        build(makeConfig(kRoverTx, kRoverRx));
    }
    void teardown() override {
        delete a;
        delete b;
    }
    void build(const IsoTpConfig& ca) {
        delete a;
        delete b;
        a = new IsoTpChannel(busA, clock, events, ca);
        b = new IsoTpChannel(*epB, clock, events, makeConfig(kRoverRx, kRoverTx));
    }

    void dispatch(CanBus& ep, IsoTpChannel* ch) {
        CanFrame f;
        for (std::size_t i = 0; i < kMemoryBusRxDepth && core::isOk(ep.receive(&f)); ++i) {
            if (f.id == ch->config().rxId) {
                ch->onFrame(f);
            }
        }
    }
    void drain(CanBus& ep) {
        CanFrame f;
        for (std::size_t i = 0; i < kMemoryBusRxDepth && core::isOk(ep.receive(&f)); ++i) {
        }
    }
    // One cycle of a alone (its peer silent).
    void stepA(core::TimeNs dt = kMs) {
        clock.advance(dt);
        dispatch(busA, a);
        a->poll();
    }
    // One cycle of a and b.
    void step() {
        clock.advance(kMs);
        dispatch(busA, a);
        a->poll();
        dispatch(*epB, b);
        b->poll();
    }
    // evil puts a frame on a's rxId; a reads it on its next cycle.
    void inject(std::initializer_list<std::uint8_t> bytes) {
        CanFrame f;
        f.id = kRoverRx;
        f.dlc = static_cast<std::uint8_t>(bytes.size());
        std::size_t i = 0;
        for (std::uint8_t byte : bytes) {
            f.data[i++] = byte;
        }
        CHECK(Status::kOk == evil->send(f));
        stepA();
    }
    // The next frame a sent, as evil saw it.
    bool fromA(CanFrame* f) { return core::isOk(evil->receive(f)); }
    void expectFlowControl(std::uint8_t flowStatus) {
        CanFrame f;
        CHECK(fromA(&f));
        LONGS_EQUAL(kRoverTx, f.id);
        LONGS_EQUAL(3, f.dlc);
        LONGS_EQUAL(0x30 | flowStatus, f.data[0]);
    }
    unsigned eventsWithId(core::EventId id) { return test::drainEventsWithId(events, id); }

    void roundTrip(IsoTpChannel* from, IsoTpChannel* to, std::size_t n, std::uint8_t seed) {
        fillPattern(payload, n, seed);
        CHECK(Status::kOk == from->send(payload, n));
        for (std::size_t s = 0; s < kMaxSteps && (from->txBusy() || to->pendingMessages() == 0); ++s) {
            step();
        }
        CHECK(IsoTpTxResult::kDone == from->txResult());
        std::size_t got = 0;
        CHECK(Status::kOk == to->receive(received, sizeof received, &got));
        LONGS_EQUAL(n, got);
        MEMCMP_EQUAL(payload, received, n);
    }
    // After an error: both directions of a are idle and carry messages again.
    void checkCleanTransfers() {
        CHECK(!a->txBusy());
        CHECK(!a->rxBusy());
        drain(*epB);  // frames b was not around to see
        drain(*evil);
        std::size_t got = 0;
        for (std::size_t i = 0; i < 8 && core::isOk(a->receive(received, sizeof received, &got)); ++i) {
        }
        const std::size_t sizes[] = {5, 100, kIsoTpMaxMessage};
        std::uint8_t seed = 1;
        for (std::size_t n : sizes) {
            roundTrip(a, b, n, seed++);
            roundTrip(b, a, n, seed++);
        }
    }
};

// --- Receive-side reasons -------------------------------------------------------

TEST(IsoTpErrors, WrongSequenceNumberAbortsTheReception) {
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});  // FF, 20 bytes
    expectFlowControl(0x0);
    CHECK(a->rxBusy());
    inject({0x22, 7, 8, 9, 10, 11, 12, 13});  // SN 2, expected 1
    LONGS_EQUAL(1, a->stats().wrongSequence);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpWrongSequence));
    CHECK(!a->rxBusy());
    LONGS_EQUAL(0, a->pendingMessages());
    inject({0x21, 7, 8, 9, 10, 11, 12, 13});  // the rest of the old message is now unexpected
    LONGS_EQUAL(1, a->stats().unexpectedCf);
    checkCleanTransfers();
}

TEST(IsoTpErrors, ConsecutiveFrameWithoutFirstFrameIsIgnored) {
    inject({0x21, 1, 2, 3, 4, 5, 6, 7});
    LONGS_EQUAL(1, a->stats().unexpectedCf);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpUnexpectedCf));
    LONGS_EQUAL(0, a->pendingMessages());
    CanFrame f;
    CHECK(!fromA(&f));  // no answer
    checkCleanTransfers();
}

TEST(IsoTpErrors, FlowControlWithNoTransmissionWaitingIsIgnored) {
    inject({0x30, 0x00, 0x00});
    LONGS_EQUAL(1, a->stats().unexpectedFc);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpUnexpectedFc));
    CHECK(!a->txBusy());
    // Also while a is sending CFs (not waiting for an FC): ignored, transfer goes on.
    IsoTpConfig slow = makeConfig(kRoverRx, kRoverTx);
    slow.blockSize = 0;
    slow.stMin = 5;
    delete b;
    b = new IsoTpChannel(*epB, clock, events, slow);
    fillPattern(payload, 200, 3);
    CHECK(Status::kOk == a->send(payload, 200));
    step();
    step();
    step();
    CHECK(a->txBusy());
    CanFrame f;
    f.id = kRoverRx;
    f.dlc = 3;
    f.data[0] = 0x30;
    CHECK(Status::kOk == evil->send(f));
    for (std::size_t s = 0; s < kMaxSteps && a->txBusy(); ++s) {
        step();
    }
    LONGS_EQUAL(2, a->stats().unexpectedFc);
    CHECK(IsoTpTxResult::kDone == a->txResult());
    std::size_t got = 0;
    CHECK(Status::kOk == b->receive(received, sizeof received, &got));
    MEMCMP_EQUAL(payload, received, 200);
    checkCleanTransfers();
}

TEST(IsoTpErrors, SingleFrameDuringAReceptionAbortsItAndIsDelivered) {
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});
    inject({0x21, 7, 8, 9, 10, 11, 12, 13});
    inject({0x03, 0xA1, 0xA2, 0xA3});
    LONGS_EQUAL(1, a->stats().rxAbortedByNew);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpRxAbortedByNew));
    CHECK(!a->rxBusy());
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(3, got);
    const std::uint8_t sf[3] = {0xA1, 0xA2, 0xA3};
    MEMCMP_EQUAL(sf, received, 3);
    CHECK(Status::kEmpty == a->receive(received, sizeof received, &got));
    checkCleanTransfers();
}

TEST(IsoTpErrors, FirstFrameDuringAReceptionRestartsIt) {
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});       // 20 bytes
    inject({0x10, 0x0A, 50, 51, 52, 53, 54, 55});  // new message: 10 bytes
    LONGS_EQUAL(1, a->stats().rxAbortedByNew);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpRxAbortedByNew));
    CHECK(a->rxBusy());
    inject({0x21, 56, 57, 58, 59});  // SN restarts at 1
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(10, got);
    const std::uint8_t expected[10] = {50, 51, 52, 53, 54, 55, 56, 57, 58, 59};
    MEMCMP_EQUAL(expected, received, 10);
    checkCleanTransfers();
}

TEST(IsoTpErrors, FirstFrameLongerThanTheBufferIsAnsweredWithOverflow) {
    inject({0x10, 0x00, 0x00, 0x00, 0x13, 0x88, 1, 2});  // escape FF: 5000 bytes
    expectFlowControl(0x2);
    LONGS_EQUAL(1, a->stats().rxTooLong);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpRxTooLong));
    CHECK(!a->rxBusy());
    inject({0x21, 1, 2, 3, 4, 5, 6, 7});  // the sender should have stopped: unexpected
    LONGS_EQUAL(1, a->stats().unexpectedCf);
    checkCleanTransfers();
}

TEST(IsoTpErrors, FirstFrameLongerThanTheConfiguredMaximumIsAnsweredWithOverflow) {
    IsoTpConfig small = makeConfig(kRoverTx, kRoverRx);
    small.maxRxLength = 64;
    small.padFrames = true;
    build(small);
    inject({0x10, 0x41, 1, 2, 3, 4, 5, 6});  // 65 bytes
    CanFrame f;
    CHECK(fromA(&f));
    LONGS_EQUAL(8, f.dlc);  // padded as configured
    const std::uint8_t overflow[8] = {0x32, 0x00, 0x00, 0xCC, 0xCC, 0xCC, 0xCC, 0xCC};
    MEMCMP_EQUAL(overflow, f.data, 8);
    LONGS_EQUAL(1, a->stats().rxTooLong);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpRxTooLong));
    inject({0x10, 0x40, 1, 2, 3, 4, 5, 6});  // 64 bytes: accepted
    CHECK(fromA(&f));
    LONGS_EQUAL(0x30, f.data[0]);
    CHECK(a->rxBusy());
    stepA(1000 * kMs);  // let it time out (N_Cr) before the clean transfers
    CHECK(!a->rxBusy());
    // The peer's 100-byte and 4095-byte messages would now be refused: check 5 and 64.
    drain(*epB);
    drain(*evil);
    (void)eventsWithId(0);
    roundTrip(b, a, 64, 9);
    roundTrip(a, b, kIsoTpMaxMessage, 10);
    roundTrip(b, a, 5, 11);
}

TEST(IsoTpErrors, FirstFrameShorterThanEightIsIgnored) {
    inject({0x10, 0x05, 1, 2, 3, 4, 5, 6});
    LONGS_EQUAL(1, a->stats().ffTooShort);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpFfTooShort));
    CanFrame f;
    CHECK(!fromA(&f));  // no FC
    CHECK(!a->rxBusy());
    // It does not disturb a reception in progress either.
    inject({0x10, 0x0A, 1, 2, 3, 4, 5, 6});
    expectFlowControl(0x0);
    inject({0x10, 0x07, 9, 9, 9, 9, 9, 9});
    LONGS_EQUAL(2, a->stats().ffTooShort);
    inject({0x21, 7, 8, 9, 10});
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(10, got);
    LONGS_EQUAL(0, a->stats().rxAbortedByNew);
    checkCleanTransfers();
}

TEST(IsoTpErrors, MalformedFramesAreIgnoredAndCounted) {
    inject({0x00, 1, 2, 3, 4, 5, 6, 7});        // SF_DL 0
    inject({0x08, 1, 2, 3, 4, 5, 6, 7});        // SF_DL 8 in a classic frame
    inject({0x05, 1, 2});                       // SF_DL 5 but only 2 data bytes
    inject({0x10, 0x14, 1, 2, 3, 4, 5});        // FF with DLC 7
    inject({});                                 // no N_PCI at all
    inject({0x40, 1, 2, 3});                    // unknown N_PCI type
    inject({0x10, 0x00, 0, 0, 0x0F, 0xFF, 1, 2});  // escape FF announcing 4095
    inject({0x21});                             // CF without data
    inject({0x30, 0x00});                       // FC with DLC 2
    LONGS_EQUAL(9, a->stats().malformed);
    LONGS_EQUAL(4, eventsWithId(events::kIsoTpMalformed));  // 1st, 2nd, 4th, 8th
    LONGS_EQUAL(0, a->pendingMessages());
    CanFrame f;
    CHECK(!fromA(&f));
    // A CF too short for the data still due is ignored; the reception goes on.
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});
    expectFlowControl(0x0);
    inject({0x21, 7, 8, 9});  // 14 bytes still due: this cannot be the last CF
    LONGS_EQUAL(10, a->stats().malformed);
    CHECK(a->rxBusy());
    inject({0x21, 7, 8, 9, 10, 11, 12, 13});
    CanFrame tooLong;  // a backend bug handing over DLC 9: refused, nothing read past data[7]
    tooLong.id = kRoverRx;
    tooLong.dlc = 9;
    tooLong.data[0] = 0x22;
    a->onFrame(tooLong);
    CHECK(a->rxBusy());
    LONGS_EQUAL(11, a->stats().malformed);
    inject({0x22, 14, 15, 16, 17, 18, 19, 20});  // the last CF completes the message
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(20, got);
    LONGS_EQUAL(20, received[19]);
    checkCleanTransfers();
}

TEST(IsoTpErrors, NoConsecutiveFrameWithinNCrAbortsTheReception) {
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});
    expectFlowControl(0x0);
    stepA(999 * kMs);
    inject({0x21, 7, 8, 9, 10, 11, 12, 13});  // in time: N_Cr restarts
    stepA(999 * kMs);
    CHECK(a->rxBusy());
    LONGS_EQUAL(0, a->stats().timeoutCr);
    stepA(1 * kMs);
    LONGS_EQUAL(1, a->stats().timeoutCr);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpTimeoutCr));
    CHECK(!a->rxBusy());
    LONGS_EQUAL(0, a->pendingMessages());
    checkCleanTransfers();
}

TEST(IsoTpErrors, BusRefusingOurFlowControlPastNArAbortsTheReception) {
    busA.refuseAll = true;
    inject({0x10, 0x14, 1, 2, 3, 4, 5, 6});
    CHECK(a->rxBusy());
    inject({0x21, 7, 8, 9, 10, 11, 12, 13});  // the sender jumped the gun: we sent no FC yet
    LONGS_EQUAL(1, a->stats().unexpectedCf);
    for (std::size_t s = 0; s < 998; ++s) {  // FF read at 1 ms: N_Ar ends at 1001 ms
        stepA();
    }
    LONGS_EQUAL(0, a->stats().timeoutAr);
    stepA();
    LONGS_EQUAL(1, a->stats().timeoutAr);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpTimeoutAr));
    CHECK(a->stats().txRefused >= 998);
    CHECK(!a->rxBusy());
    busA.refuseAll = false;
    checkCleanTransfers();
}

// --- Transmit-side reasons ------------------------------------------------------

TEST(IsoTpErrors, NoFlowControlWithinNBsAbortsTheTransmission) {
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    stepA(999 * kMs);
    CHECK(a->txBusy());
    stepA(1 * kMs);
    LONGS_EQUAL(1, a->stats().timeoutBs);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpTimeoutBs));
    CHECK(IsoTpTxResult::kTimeoutBs == a->txResult());
    CHECK(!a->txBusy());
    // Also after a block: evil grants BS 2, then goes quiet.
    drain(*evil);
    fillPattern(payload, 30, 2);  // FF + 4 CFs
    CHECK(Status::kOk == a->send(payload, 30));
    inject({0x30, 0x02, 0x00});
    stepA();
    CanFrame f;
    CHECK(fromA(&f));  // FF
    CHECK(fromA(&f));
    LONGS_EQUAL(0x21, f.data[0]);
    CHECK(fromA(&f));
    LONGS_EQUAL(0x22, f.data[0]);
    CHECK(!fromA(&f));  // block done: waiting for FC
    CHECK(a->txBusy());
    stepA(1000 * kMs);
    LONGS_EQUAL(2, a->stats().timeoutBs);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpTimeoutBs));
    checkCleanTransfers();
}

TEST(IsoTpErrors, PeerOverflowAbortsTheTransmission) {
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    inject({0x32, 0x00, 0x00});
    LONGS_EQUAL(1, a->stats().peerOverflow);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpPeerOverflow));
    CHECK(IsoTpTxResult::kPeerOverflow == a->txResult());
    CHECK(!a->txBusy());
    stepA();
    CanFrame f;
    CHECK(fromA(&f));   // the FF
    CHECK(!fromA(&f));  // and no CF after the overflow
    checkCleanTransfers();
}

TEST(IsoTpErrors, TooManyWaitsAbortTheTransmission) {
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    for (int i = 0; i < kIsoTpDefaultMaxWaitFrames; ++i) {
        inject({0x31, 0x00, 0x00});
        stepA(900 * kMs);  // each WAIT restarts N_Bs
    }
    CHECK(a->txBusy());
    LONGS_EQUAL(10, a->stats().waitsReceived);
    LONGS_EQUAL(0, a->stats().timeoutBs);
    inject({0x31, 0x00, 0x00});
    LONGS_EQUAL(1, a->stats().waitLimit);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpWaitLimit));
    CHECK(IsoTpTxResult::kWaitLimit == a->txResult());
    CHECK(!a->txBusy());
    // The limit counts consecutive WAITs: a CTS resets it.
    CHECK(Status::kOk == a->send(payload, 20));
    for (int i = 0; i < kIsoTpDefaultMaxWaitFrames; ++i) {
        inject({0x31, 0x00, 0x00});
    }
    inject({0x30, 0x01, 0x00});  // BS 1
    stepA();
    for (int i = 0; i < kIsoTpDefaultMaxWaitFrames; ++i) {
        inject({0x31, 0x00, 0x00});
    }
    inject({0x30, 0x00, 0x00});
    stepA();
    CHECK(IsoTpTxResult::kDone == a->txResult());
    LONGS_EQUAL(1, a->stats().waitLimit);
    checkCleanTransfers();
}

TEST(IsoTpErrors, InvalidFlowStatusAbortsTheTransmission) {
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    inject({0x35, 0x00, 0x00});
    LONGS_EQUAL(1, a->stats().invalidFlowStatus);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpInvalidFlowStatus));
    CHECK(IsoTpTxResult::kInvalidFlowStatus == a->txResult());
    CHECK(!a->txBusy());
    checkCleanTransfers();
}

TEST(IsoTpErrors, BusRefusingFramesPastNAsAbortsTheTransmission) {
    busA.refuseAll = true;
    fillPattern(payload, 5, 1);
    CHECK(Status::kOk == a->send(payload, 5));  // under way: the SF waits for room
    CHECK(a->txBusy());
    for (std::size_t s = 0; s < 999; ++s) {
        stepA();
    }
    CHECK(a->txBusy());
    stepA();
    LONGS_EQUAL(1, a->stats().timeoutAs);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpTimeoutAs));
    CHECK(IsoTpTxResult::kTimeoutAs == a->txResult());
    CHECK(!a->txBusy());
    // A CF refused mid-message: N_As again; the receiver then gives up on N_Cr.
    busA.refuseAll = false;
    fillPattern(payload, 100, 2);
    CHECK(Status::kOk == a->send(payload, 100));
    step();  // b answers the FF
    busA.refuseAll = true;
    for (std::size_t s = 0; s < 2000 && a->txBusy(); ++s) {
        step();
    }
    LONGS_EQUAL(2, a->stats().timeoutAs);
    LONGS_EQUAL(1, b->stats().timeoutCr);
    busA.refuseAll = false;
    checkCleanTransfers();
}

TEST(IsoTpErrors, RefusedFramesAreRetriedOnTheNextPoll) {
    busA.refuseNext = 3;
    roundTrip(a, b, 100, 4);  // FF refused once at send(), then twice in poll()
    LONGS_EQUAL(3, a->stats().txRefused);
    LONGS_EQUAL(0, a->stats().timeoutAs);
    LONGS_EQUAL(0, events.total());
}

// --- The application's side ---------------------------------------------------

TEST(IsoTpErrors, SendOfZeroOrMoreThan4095BytesIsRejected) {
    CHECK(Status::kInvalidArgument == a->send(payload, 0));
    CHECK(Status::kInvalidArgument == a->send(payload, kIsoTpMaxMessage + 1));
    CHECK(Status::kInvalidArgument == a->send(nullptr, 5));
    LONGS_EQUAL(3, a->stats().sendInvalid);
    LONGS_EQUAL(2, eventsWithId(events::kIsoTpSendInvalid));  // 1st, 2nd (3rd is not a power of 2)
    CHECK(!a->txBusy());
    CanFrame f;
    CHECK(!fromA(&f));
    checkCleanTransfers();
}

TEST(IsoTpErrors, SendWhileBusyIsRefused) {
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    CHECK(Status::kBusy == a->send(payload, 3));
    LONGS_EQUAL(1, a->stats().sendBusy);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpSendBusy));
    for (std::size_t s = 0; s < kMaxSteps && a->txBusy(); ++s) {
        step();
    }
    std::size_t got = 0;
    CHECK(Status::kOk == b->receive(received, sizeof received, &got));
    LONGS_EQUAL(20, got);  // the first message, untouched by the refused one
    MEMCMP_EQUAL(payload, received, 20);
    checkCleanTransfers();
}

TEST(IsoTpErrors, FullReceiveFifoDropsTheNewerMessage) {
    std::uint8_t first[kIsoTpMaxMessage] = {};
    std::uint8_t second[kIsoTpMaxMessage] = {};
    fillPattern(first, kIsoTpMaxMessage, 1);
    fillPattern(second, kIsoTpMaxMessage, 2);
    const std::uint8_t* messages[] = {first, second, payload};
    fillPattern(payload, kIsoTpMaxMessage, 3);
    for (const std::uint8_t* m : messages) {
        CHECK(Status::kOk == b->send(m, kIsoTpMaxMessage));
        for (std::size_t s = 0; s < kMaxSteps && b->txBusy(); ++s) {
            step();
        }
        step();
    }
    LONGS_EQUAL(1, a->stats().rxOverruns);
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpRxOverrun));
    LONGS_EQUAL(2, a->pendingMessages());
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    MEMCMP_EQUAL(first, received, kIsoTpMaxMessage);
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    MEMCMP_EQUAL(second, received, kIsoTpMaxMessage);
    CHECK(Status::kEmpty == a->receive(received, sizeof received, &got));
    checkCleanTransfers();
}

TEST(IsoTpErrors, ReservedStMinFromThePeerMeans127Ms) {
    fillPattern(payload, 6 + 7 * 3, 1);
    CHECK(Status::kOk == a->send(payload, 6 + 7 * 3));
    inject({0x30, 0x00, 0x80});
    core::TimeNs times[4] = {};
    std::size_t cfs = 0;
    for (std::size_t s = 0; s < 500 && a->txBusy(); ++s) {
        stepA();
        CanFrame f;
        while (fromA(&f)) {
            if ((f.data[0] >> 4) == 2 && cfs < 4) {
                times[cfs++] = f.timestamp;
            }
        }
    }
    LONGS_EQUAL(3, cfs);
    CHECK(times[1] - times[0] >= 127 * kMs);
    CHECK(times[2] - times[1] >= 127 * kMs);
    CHECK(times[2] - times[1] < 130 * kMs);
    checkCleanTransfers();
}

TEST(IsoTpErrors, BlockSizeAndStMinComeFromTheFirstClearToSend) {
    fillPattern(payload, 6 + 7 * 4, 1);
    CHECK(Status::kOk == a->send(payload, 6 + 7 * 4));
    inject({0x30, 0x02, 0x00});  // BS 2, STmin 0
    stepA();
    CanFrame f;
    std::size_t cfs = 0;
    while (fromA(&f)) {
        cfs += (f.data[0] >> 4) == 2 ? 1U : 0U;
    }
    LONGS_EQUAL(2, cfs);
    inject({0x30, 0x00, 0x7F});  // later FC values are not used: still BS 2, STmin 0
    stepA();
    cfs = 0;
    while (fromA(&f)) {
        cfs += (f.data[0] >> 4) == 2 ? 1U : 0U;
    }
    LONGS_EQUAL(2, cfs);
    CHECK(IsoTpTxResult::kDone == a->txResult());
    checkCleanTransfers();
}

TEST(IsoTpErrors, FramesForOtherIdsAreNotOurs) {
    CanFrame f;
    f.id = 0x123;
    f.dlc = 2;
    f.data[0] = 0x01;
    a->onFrame(f);
    f.id = kRoverRx;
    f.flags = CanFrame::kExtended;
    a->onFrame(f);
    LONGS_EQUAL(2, a->stats().foreignFrames);
    LONGS_EQUAL(0, a->stats().rxFrames);
    LONGS_EQUAL(0, a->pendingMessages());
    LONGS_EQUAL(0, events.total());
}

TEST(IsoTpErrors, InvalidConfigLeavesTheChannelInert) {
    IsoTpConfig same = makeConfig(kRoverTx, kRoverTx);
    IsoTpConfig reserved = makeConfig(kRoverTx, kRoverRx);
    reserved.stMin = 0x80;
    IsoTpConfig wide = makeConfig(0x800, kRoverRx);
    IsoTpConfig noTimeout = makeConfig(kRoverTx, kRoverRx);
    noTimeout.nCr = 0;
    const IsoTpConfig* bad[] = {&same, &reserved, &wide, &noTimeout};
    for (const IsoTpConfig* c : bad) {
        CHECK(!isValidIsoTpConfig(*c));
    }
    build(reserved);
    CHECK(!a->configValid());
    LONGS_EQUAL(1, eventsWithId(events::kIsoTpConfigInvalid));
    CHECK(Status::kNotInitialized == a->send(payload, 5));
    inject({0x03, 1, 2, 3});
    LONGS_EQUAL(0, a->pendingMessages());
    CHECK(isValidIsoTpConfig(makeConfig(kRoverTx, kRoverRx)));
}

// --- A peer that was not listening (resendFirstFrameOnPeerMessage) ---------------

namespace {

IsoTpConfig resendingConfig() {
    IsoTpConfig c = makeConfig(kRoverTx, kRoverRx);
    c.resendFirstFrameOnPeerMessage = true;
    return c;
}

}  // namespace

TEST(IsoTpErrors, AnUnansweredFirstFrameGoesAgainWhenThePeerStartsAMessage) {
    build(resendingConfig());
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    CanFrame f;
    CHECK(fromA(&f));
    LONGS_EQUAL(0x10, f.data[0]);  // the FF, heard by nobody
    stepA(600 * kMs);
    CHECK(!fromA(&f));
    inject({0x02, 0xA1, 0xA2});  // the peer is there now: a message of its own
    CHECK(fromA(&f));
    LONGS_EQUAL(0x10, f.data[0]);  // the same FF again
    LONGS_EQUAL(0x14, f.data[1]);
    MEMCMP_EQUAL(payload, &f.data[2], 6);
    CHECK(!fromA(&f));
    LONGS_EQUAL(1, a->stats().ffResent);
    // N_Bs runs from the second FF: 1.6 s after the first, still waiting.
    stepA(999 * kMs);
    CHECK(a->txBusy());
    LONGS_EQUAL(0, a->stats().timeoutBs);
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());
    CHECK(fromA(&f));
    LONGS_EQUAL(0x21, f.data[0]);
    CHECK(fromA(&f));
    LONGS_EQUAL(0x22, f.data[0]);
    CHECK(!fromA(&f));
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));  // the peer's message too
    LONGS_EQUAL(2, got);
    LONGS_EQUAL(0, eventsWithId(events::kIsoTpTimeoutBs));
    checkCleanTransfers();
}

TEST(IsoTpErrors, APeerFirstFrameIsAnsweredAndOurUnansweredFirstFrameGoesAgain) {
    build(resendingConfig());
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    drain(*evil);
    inject({0x10, 0x0A, 50, 51, 52, 53, 54, 55});  // the peer starts a 10-byte message
    expectFlowControl(0x0);                         // answered first, from onFrame
    CanFrame f;
    CHECK(fromA(&f));
    LONGS_EQUAL(0x10, f.data[0]);  // then our FF again, from poll
    LONGS_EQUAL(1, a->stats().ffResent);
    inject({0x21, 56, 57, 58, 59});
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());
    std::size_t got = 0;
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(10, got);
    checkCleanTransfers();
}

TEST(IsoTpErrors, OnlyAFirstFrameNobodyAnsweredGoesAgain) {
    CanFrame f;
    std::size_t got = 0;
    // Not configured (the default): the FF waits out N_Bs as before.
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));
    drain(*evil);
    inject({0x02, 0xA1, 0xA2});
    CHECK(!fromA(&f));
    LONGS_EQUAL(0, a->stats().ffResent);
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());

    build(resendingConfig());
    drain(*evil);
    // The peer asked us to wait: it is listening.
    CHECK(Status::kOk == a->send(payload, 20));
    inject({0x31, 0x00, 0x00});
    drain(*evil);
    inject({0x02, 0xA1, 0xA2});
    CHECK(!fromA(&f));
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());
    // Waiting for the FC after a block: the peer answered the FF.
    drain(*evil);
    fillPattern(payload, 6 + 7 * 4, 2);
    CHECK(Status::kOk == a->send(payload, 6 + 7 * 4));
    inject({0x30, 0x02, 0x00});  // BS 2: two CFs, then wait
    drain(*evil);
    inject({0x02, 0xA1, 0xA2});
    CHECK(!fromA(&f));
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());
    // The FC arrives in the same cycle as the peer's message: it counts first.
    drain(*evil);
    CHECK(Status::kOk == a->send(payload, 20));
    drain(*evil);
    f.id = kRoverRx;
    f.dlc = 3;
    f.data[0] = 0x02;
    f.data[1] = 0xA1;
    f.data[2] = 0xA2;
    CHECK(Status::kOk == evil->send(f));
    f.data[0] = 0x30;
    f.data[1] = 0x00;
    f.data[2] = 0x00;
    CHECK(Status::kOk == evil->send(f));
    stepA();
    CHECK(IsoTpTxResult::kDone == a->txResult());
    CHECK(fromA(&f));
    LONGS_EQUAL(0x21, f.data[0]);  // CFs, no second FF
    LONGS_EQUAL(0, a->stats().ffResent);
    LONGS_EQUAL(0, a->stats().unexpectedFc);
    for (int i = 0; i < 3; ++i) {  // the peer's three messages since build()
        CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    }
    CHECK(Status::kEmpty == a->receive(received, sizeof received, &got));
    checkCleanTransfers();
}

TEST(IsoTpErrors, APeerHeardBeforeOurMessageBeganDoesNotMakeItsFirstFrameGoTwice) {
    build(resendingConfig());
    drain(*evil);
    CanFrame f;
    f.id = kRoverRx;
    f.dlc = 3;
    f.data[0] = 0x02;
    f.data[1] = 0xA1;
    f.data[2] = 0xA2;
    CHECK(Status::kOk == evil->send(f));
    clock.advance(kMs);
    dispatch(busA, a);  // the owner hands over the peer's SF ...
    fillPattern(payload, 20, 1);
    CHECK(Status::kOk == a->send(payload, 20));  // ... starts a message before its poll() ...
    a->poll();
    std::size_t ffs = 0;
    while (fromA(&f)) {
        ffs += (f.data[0] >> 4) == 1 ? 1U : 0U;
    }
    LONGS_EQUAL(1, ffs);  // ... and the FF goes once
    LONGS_EQUAL(0, a->stats().ffResent);
    inject({0x30, 0x00, 0x00});
    CHECK(IsoTpTxResult::kDone == a->txResult());
    checkCleanTransfers();
}
