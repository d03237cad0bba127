// ISO-TP channel: round trips on the in-memory bus, the exact frames on the wire,
// STmin pacing, the per-poll CF cap and a seeded random soak. Error reasons are in
// test_isotp_errors.cpp.
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/can_events.hpp"
#include "hal/can/isotp.hpp"
#include "hal/can/memory_can_bus.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::hal;
using core::Status;

namespace {

constexpr std::uint32_t kRoverRx = 0x6C0;  // docs/icd.md section 2
constexpr std::uint32_t kRoverTx = 0x6C1;
constexpr std::size_t kSpyDepth = 2048;
constexpr core::TimeNs kStep = core::kNsPerMs;
constexpr std::size_t kMaxSteps = 20000;

IsoTpConfig makeConfig(std::uint32_t tx, std::uint32_t rx, std::uint8_t bs, std::uint8_t stMin, bool pad) {
    IsoTpConfig c;
    c.txId = tx;
    c.rxId = rx;
    c.blockSize = bs;
    c.stMin = stMin;
    c.padFrames = pad;
    return c;
}

void fillPattern(std::uint8_t* data, std::size_t n, std::uint32_t seed) {
    std::uint32_t x = seed * 2654435761U + 1U;
    for (std::size_t i = 0; i < n; ++i) {
        x ^= x << 13;
        x ^= x >> 17;
        x ^= x << 5;
        data[i] = static_cast<std::uint8_t>(x);
    }
}

std::uint8_t pciType(const CanFrame& f) { return static_cast<std::uint8_t>(f.data[0] >> 4); }

}  // namespace

// Two channels on two endpoints with swapped ids ("rover" a, "ground" b) and a spy
// endpoint that records every frame on the wire with its time.
TEST_GROUP(IsoTp) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    MemoryCanBus wire{clock};
    MemoryCanEndpoint* epA = wire.attach("rover");
    MemoryCanEndpoint* epB = wire.attach("ground");
    MemoryCanEndpoint* spy = wire.attach("spy");
    IsoTpChannel* a = nullptr;
    IsoTpChannel* b = nullptr;
    CanFrame seen[kSpyDepth];
    std::size_t seenCount = 0;
    std::uint8_t payload[kIsoTpMaxMessage + 1] = {};
    std::uint8_t received[kIsoTpMaxMessage + 1] = {};

    void build(const IsoTpConfig& ca, const IsoTpConfig& cb) {
        delete a;
        delete b;
        a = new IsoTpChannel(*epA, clock, events, ca);
        b = new IsoTpChannel(*epB, clock, events, cb);
        CHECK(a->configValid());
        CHECK(b->configValid());
    }
    void build(std::uint8_t bs, std::uint8_t stMin, bool pad) {
        build(makeConfig(kRoverTx, kRoverRx, bs, stMin, pad), makeConfig(kRoverRx, kRoverTx, bs, stMin, pad));
    }
    void teardown() override {
        delete a;
        delete b;
    }

    void dispatch(MemoryCanEndpoint* ep, IsoTpChannel* ch) {
        CanFrame f;
        for (std::size_t i = 0; i < kMemoryBusRxDepth && core::isOk(ep->receive(&f)); ++i) {
            if (f.id == ch->config().rxId) {
                ch->onFrame(f);
            }
        }
    }
    void recordWire() {
        CanFrame f;
        for (std::size_t i = 0; i < kMemoryBusRxDepth && core::isOk(spy->receive(&f)); ++i) {
            if (seenCount < kSpyDepth) {
                seen[seenCount++] = f;
            }
        }
    }
    // One cycle of both owners: read the bus, hand frames over, poll.
    void step() {
        clock.advance(kStep);
        dispatch(epA, a);
        a->poll();
        recordWire();
        dispatch(epB, b);
        b->poll();
        recordWire();
    }
    // Sends n pattern bytes from -> to and checks they arrive intact.
    void roundTrip(IsoTpChannel* from, IsoTpChannel* to, std::size_t n, std::uint32_t seed) {
        fillPattern(payload, n, seed);
        seenCount = 0;
        CHECK(Status::kOk == from->send(payload, n));
        std::size_t steps = 0;
        while ((from->txBusy() || to->pendingMessages() == 0) && steps < kMaxSteps) {
            step();
            ++steps;
        }
        CHECK(IsoTpTxResult::kDone == from->txResult());
        std::size_t got = 0;
        CHECK(Status::kOk == to->receive(received, sizeof received, &got));
        LONGS_EQUAL(n, got);
        MEMCMP_EQUAL(payload, received, n);
        CHECK(!to->rxBusy());
    }
    // Every CF of from's id on the wire is at least gap after the previous one.
    void checkCfSpacing(std::uint32_t txId, core::TimeNs gap) {
        core::TimeNs last = -1;
        for (std::size_t i = 0; i < seenCount; ++i) {
            if (seen[i].id != txId || pciType(seen[i]) != 2) {
                continue;
            }
            if (last >= 0) {
                CHECK_TEXT(seen[i].timestamp - last >= gap, "CFs closer than STmin");
            }
            last = seen[i].timestamp;
        }
    }
    void checkDlcs(bool padded) {
        for (std::size_t i = 0; i < seenCount; ++i) {
            if (padded) {
                LONGS_EQUAL(8, seen[i].dlc);
            } else if (pciType(seen[i]) == 3) {
                LONGS_EQUAL(3, seen[i].dlc);
            }
        }
    }
    void roundTripsBothWays(std::uint8_t bs, std::uint8_t stMin, bool pad) {
        build(bs, stMin, pad);
        const std::size_t sizes[] = {1, 7, 8, 62, 4000, 4095};
        std::uint32_t seed = 1;
        for (std::size_t n : sizes) {
            roundTrip(a, b, n, seed++);
            checkDlcs(pad);
            checkCfSpacing(kRoverTx, isoTpStMinToNs(stMin));
            roundTrip(b, a, n, seed++);
            checkDlcs(pad);
            checkCfSpacing(kRoverRx, isoTpStMinToNs(stMin));
        }
        LONGS_EQUAL(6, a->stats().txMessages);
        LONGS_EQUAL(6, a->stats().rxMessages);
        LONGS_EQUAL(6, b->stats().txMessages);
        LONGS_EQUAL(6, b->stats().rxMessages);
        LONGS_EQUAL(0, events.total());  // a clean link raises nothing
    }
};

TEST(IsoTp, RoundTripsBs0StMin0Unpadded) { roundTripsBothWays(0, 0, false); }
TEST(IsoTp, RoundTripsBs8StMin0Unpadded) { roundTripsBothWays(8, 0, false); }
TEST(IsoTp, RoundTripsBs0StMin5Unpadded) { roundTripsBothWays(0, 5, false); }
TEST(IsoTp, RoundTripsBs8StMin5Unpadded) { roundTripsBothWays(8, 5, false); }
TEST(IsoTp, RoundTripsBs0StMin0Padded) { roundTripsBothWays(0, 0, true); }
TEST(IsoTp, RoundTripsBs8StMin0Padded) { roundTripsBothWays(8, 0, true); }
TEST(IsoTp, RoundTripsBs0StMin5Padded) { roundTripsBothWays(0, 5, true); }
TEST(IsoTp, RoundTripsBs8StMin5Padded) { roundTripsBothWays(8, 5, true); }

TEST(IsoTp, PaddedAndUnpaddedPeersUnderstandEachOther) {
    build(makeConfig(kRoverTx, kRoverRx, 8, 0, true), makeConfig(kRoverRx, kRoverTx, 3, 0, false));
    const std::size_t sizes[] = {1, 6, 7, 8, 13, 14, 15, 100, 4095};
    std::uint32_t seed = 7;
    for (std::size_t n : sizes) {
        roundTrip(a, b, n, seed++);
        roundTrip(b, a, n, seed++);
    }
}

TEST(IsoTp, TenBytesUnpaddedHaveTheStandardFramesOnTheWire) {
    build(8, 0, false);
    roundTrip(a, b, 10, 3);
    LONGS_EQUAL(3, seenCount);
    // FF: PCI 0x1, length 0x00A, six data bytes, DLC 8.
    LONGS_EQUAL(kRoverTx, seen[0].id);
    LONGS_EQUAL(8, seen[0].dlc);
    const std::uint8_t ff[8] = {0x10, 0x0A, payload[0], payload[1], payload[2], payload[3], payload[4], payload[5]};
    MEMCMP_EQUAL(ff, seen[0].data, 8);
    // FC from the receiver: CTS, BS 8, STmin 0, natural DLC 3.
    LONGS_EQUAL(kRoverRx, seen[1].id);
    LONGS_EQUAL(3, seen[1].dlc);
    const std::uint8_t fc[3] = {0x30, 0x08, 0x00};
    MEMCMP_EQUAL(fc, seen[1].data, 3);
    // Last (only) CF: SN 1, the remaining four bytes, DLC 5.
    LONGS_EQUAL(kRoverTx, seen[2].id);
    LONGS_EQUAL(5, seen[2].dlc);
    const std::uint8_t cf[5] = {0x21, payload[6], payload[7], payload[8], payload[9]};
    MEMCMP_EQUAL(cf, seen[2].data, 5);
    // A 5-byte SF: PCI 0x05, DLC 6.
    roundTrip(b, a, 5, 4);
    LONGS_EQUAL(1, seenCount);
    LONGS_EQUAL(kRoverRx, seen[0].id);
    LONGS_EQUAL(6, seen[0].dlc);
    const std::uint8_t sf[6] = {0x05, payload[0], payload[1], payload[2], payload[3], payload[4]};
    MEMCMP_EQUAL(sf, seen[0].data, 6);
}

TEST(IsoTp, TenBytesPaddedFillEveryFrameWithThePadByte) {
    IsoTpConfig ca = makeConfig(kRoverTx, kRoverRx, 4, 0x0A, true);
    IsoTpConfig cb = makeConfig(kRoverRx, kRoverTx, 4, 0x0A, true);
    cb.padByte = 0x55;
    build(ca, cb);
    roundTrip(a, b, 10, 5);
    LONGS_EQUAL(3, seenCount);
    const std::uint8_t ff[8] = {0x10, 0x0A, payload[0], payload[1], payload[2], payload[3], payload[4], payload[5]};
    MEMCMP_EQUAL(ff, seen[0].data, 8);
    LONGS_EQUAL(8, seen[1].dlc);
    const std::uint8_t fc[8] = {0x30, 0x04, 0x0A, 0x55, 0x55, 0x55, 0x55, 0x55};
    MEMCMP_EQUAL(fc, seen[1].data, 8);
    LONGS_EQUAL(8, seen[2].dlc);
    const std::uint8_t cf[8] = {0x21, payload[6], payload[7], payload[8], payload[9], 0xCC, 0xCC, 0xCC};
    MEMCMP_EQUAL(cf, seen[2].data, 8);
    roundTrip(a, b, 3, 6);
    const std::uint8_t sf[8] = {0x03, payload[0], payload[1], payload[2], 0xCC, 0xCC, 0xCC, 0xCC};
    LONGS_EQUAL(8, seen[0].dlc);
    MEMCMP_EQUAL(sf, seen[0].data, 8);
}

TEST(IsoTp, SequenceNumbersRunFromOneAndWrapFifteenToZero) {
    build(0, 0, false);
    roundTrip(a, b, 6 + 7 * 20, 9);  // FF + 20 CFs
    std::uint8_t expected = 1;
    std::size_t cfs = 0;
    for (std::size_t i = 0; i < seenCount; ++i) {
        if (seen[i].id == kRoverTx && pciType(seen[i]) == 2) {
            LONGS_EQUAL(expected, seen[i].data[0] & 0x0F);
            expected = static_cast<std::uint8_t>((expected + 1) & 0x0F);
            ++cfs;
        }
    }
    LONGS_EQUAL(20, cfs);
}

TEST(IsoTp, BlockSizeEightMeansOneFcPerEightCfs) {
    build(8, 0, false);
    roundTrip(a, b, 6 + 7 * 20, 10);  // 20 CFs: FC after FF, after CF 8 and after CF 16
    std::size_t fcs = 0;
    std::size_t cfsSinceFc = 0;
    for (std::size_t i = 0; i < seenCount; ++i) {
        if (seen[i].id == kRoverRx) {
            LONGS_EQUAL(0x30, seen[i].data[0]);
            LONGS_EQUAL(8, seen[i].data[1]);
            ++fcs;
            cfsSinceFc = 0;
        } else if (pciType(seen[i]) == 2) {
            ++cfsSinceFc;
            CHECK(cfsSinceFc <= 8);
        }
    }
    LONGS_EQUAL(3, fcs);
}

TEST(IsoTp, StMinZeroSendsAtMostTheCapPerPoll) {
    build(0, 0, false);
    fillPattern(payload, kIsoTpMaxMessage, 11);
    CHECK(Status::kOk == a->send(payload, kIsoTpMaxMessage));
    step();  // b answers the FF with FC CTS BS 0 STmin 0
    seenCount = 0;
    step();  // a reads the FC and sends as many CFs as one poll may
    std::size_t cfs = 0;
    for (std::size_t i = 0; i < seenCount; ++i) {
        cfs += (seen[i].id == kRoverTx && pciType(seen[i]) == 2) ? 1U : 0U;
    }
    LONGS_EQUAL(kIsoTpMaxCfPerPoll, cfs);
}

TEST(IsoTp, StMinAboveZeroSendsOneCfPerPollAndHonoursSubMillisecondValues) {
    build(0, 0xF5, false);  // 500 us: below the 1 ms step, so one CF per poll
    fillPattern(payload, 6 + 7 * 5, 12);
    CHECK(Status::kOk == a->send(payload, 6 + 7 * 5));
    step();
    for (std::size_t s = 1; s <= 5; ++s) {
        seenCount = 0;
        step();
        LONGS_EQUAL(1, seenCount);
    }
    CHECK(!a->txBusy());
}

TEST(IsoTp, StMinDecodesPerTheStandard) {
    CHECK_EQUAL(0, isoTpStMinToNs(0x00));
    CHECK_EQUAL(5 * core::kNsPerMs, isoTpStMinToNs(0x05));
    CHECK_EQUAL(127 * core::kNsPerMs, isoTpStMinToNs(0x7F));
    CHECK_EQUAL(100 * core::kNsPerUs, isoTpStMinToNs(0xF1));
    CHECK_EQUAL(900 * core::kNsPerUs, isoTpStMinToNs(0xF9));
    // Reserved values count as the longest gap, 127 ms.
    CHECK_EQUAL(127 * core::kNsPerMs, isoTpStMinToNs(0x80));
    CHECK_EQUAL(127 * core::kNsPerMs, isoTpStMinToNs(0xF0));
    CHECK_EQUAL(127 * core::kNsPerMs, isoTpStMinToNs(0xFA));
    CHECK_EQUAL(127 * core::kNsPerMs, isoTpStMinToNs(0xFF));
}

TEST(IsoTp, FullDuplexTransfersInBothDirectionsAtOnce) {
    build(8, 0, false);
    std::uint8_t other[kIsoTpMaxMessage] = {};
    fillPattern(payload, 3000, 21);
    fillPattern(other, 2500, 22);
    CHECK(Status::kOk == a->send(payload, 3000));
    CHECK(Status::kOk == b->send(other, 2500));
    for (std::size_t s = 0; s < kMaxSteps && (a->txBusy() || b->txBusy()); ++s) {
        step();
    }
    step();  // the last frame b sent reaches a on the next cycle
    std::size_t got = 0;
    CHECK(Status::kOk == b->receive(received, sizeof received, &got));
    LONGS_EQUAL(3000, got);
    MEMCMP_EQUAL(payload, received, 3000);
    CHECK(Status::kOk == a->receive(received, sizeof received, &got));
    LONGS_EQUAL(2500, got);
    MEMCMP_EQUAL(other, received, 2500);
}

TEST(IsoTp, CompletedMessagesQueueInOrderUntilTaken) {
    build(8, 0, false);
    const std::size_t sizes[] = {3, 4095, 20, 7};  // 4 + 4097 + 22 + 9 bytes of FIFO: fits
    std::uint8_t expected[4][kIsoTpMaxMessage] = {};
    for (std::size_t m = 0; m < 4; ++m) {
        fillPattern(expected[m], sizes[m], static_cast<std::uint32_t>(30 + m));
        CHECK(Status::kOk == a->send(expected[m], sizes[m]));
        for (std::size_t s = 0; s < kMaxSteps && a->txBusy(); ++s) {
            step();
        }
        step();  // an SF goes out in send(): b reads it on the next cycle
    }
    LONGS_EQUAL(4, b->pendingMessages());
    for (std::size_t m = 0; m < 4; ++m) {
        std::size_t got = 0;
        CHECK(Status::kOk == b->receive(received, sizeof received, &got));
        LONGS_EQUAL(sizes[m], got);
        MEMCMP_EQUAL(expected[m], received, got);
    }
    std::size_t got = 0;
    CHECK(Status::kEmpty == b->receive(received, sizeof received, &got));
}

TEST(IsoTp, ReceiveFifoWrapsAroundIntact) {
    // One message stays unread while the next arrives, so the FIFO never empties
    // and its records wrap around its end at changing places. The first sizes put
    // the third record's 2-byte length across the wrap (4097 + 4096 = 8193 bytes).
    build(0, 0, false);
    std::uint32_t rng = 77;
    std::size_t sizes[60] = {4095, 4094, 100};
    for (std::size_t k = 3; k < 60; ++k) {
        rng = rng * 1664525U + 1013904223U;
        sizes[k] = 1 + (rng >> 8) % kIsoTpMaxMessage;
    }
    for (std::size_t k = 0; k < 60; ++k) {
        fillPattern(payload, sizes[k], static_cast<std::uint32_t>(500 + k));
        CHECK(Status::kOk == a->send(payload, sizes[k]));
        for (std::size_t s = 0; s < kMaxSteps && a->txBusy(); ++s) {
            step();
        }
        step();
        LONGS_EQUAL(k == 0 ? 1 : 2, b->pendingMessages());
        if (k > 0) {  // take the previous one
            std::size_t got = 0;
            CHECK(Status::kOk == b->receive(received, sizeof received, &got));
            LONGS_EQUAL(sizes[k - 1], got);
            fillPattern(payload, sizes[k - 1], static_cast<std::uint32_t>(500 + k - 1));
            MEMCMP_EQUAL(payload, received, got);
        }
    }
    std::size_t got = 0;
    CHECK(Status::kOk == b->receive(received, sizeof received, &got));
    fillPattern(payload, sizes[59], 559);
    LONGS_EQUAL(sizes[59], got);
    MEMCMP_EQUAL(payload, received, got);
    LONGS_EQUAL(0, b->stats().rxOverruns);
}

TEST(IsoTp, ReceiveIntoATooSmallBufferKeepsTheMessage) {
    build(8, 0, false);
    fillPattern(payload, 100, 40);
    CHECK(Status::kOk == a->send(payload, 100));
    for (std::size_t s = 0; s < kMaxSteps && a->txBusy(); ++s) {
        step();
    }
    std::size_t got = 0;
    CHECK(Status::kTooLarge == b->receive(received, 50, &got));
    LONGS_EQUAL(100, got);
    CHECK(Status::kInvalidArgument == b->receive(received, 50, nullptr));
    CHECK(Status::kOk == b->receive(received, 100, &got));
    MEMCMP_EQUAL(payload, received, 100);
}

TEST(IsoTp, SeededRandomTransfersAllArriveIntact) {
    // 200 transfers: random sizes (half short, half up to 4095), random direction,
    // sometimes both directions at once; the channel pair is rebuilt every 25
    // transfers with another BS / STmin / padding.
    std::uint32_t rng = 0x1505C0DEU;
    auto next = [&rng]() {
        rng ^= rng << 13;
        rng ^= rng >> 17;
        rng ^= rng << 5;
        return rng;
    };
    const std::uint8_t blockSizes[] = {0, 1, 8, 15, 4, 8, 0, 2};
    const std::uint8_t stMins[] = {0, 0, 1, 0xF3, 0, 2, 0, 0};
    std::uint8_t other[kIsoTpMaxMessage] = {};
    std::size_t delivered = 0;
    for (std::size_t t = 0; t < 200; ++t) {
        if (t % 25 == 0) {
            const std::size_t k = t / 25;
            build(makeConfig(kRoverTx, kRoverRx, blockSizes[k], stMins[k], (k & 1U) != 0),
                  makeConfig(kRoverRx, kRoverTx, blockSizes[7 - k], stMins[7 - k], (k & 2U) != 0));
        }
        const std::uint32_t r = next();
        const std::size_t n = (r & 1U) != 0 ? 1 + (next() % 12) : 1 + (next() % kIsoTpMaxMessage);
        const bool aToB = (r & 2U) != 0;
        const bool duplex = (r & 12U) == 0;
        const std::size_t m = 1 + (next() % 600);
        fillPattern(payload, n, next());
        fillPattern(other, m, next());
        IsoTpChannel* from = aToB ? a : b;
        IsoTpChannel* to = aToB ? b : a;
        CHECK(Status::kOk == from->send(payload, n));
        if (duplex) {
            CHECK(Status::kOk == to->send(other, m));
        }
        for (std::size_t s = 0; s < kMaxSteps && (a->txBusy() || b->txBusy()); ++s) {
            step();
        }
        step();  // the last frame b sent reaches a on the next cycle
        std::size_t got = 0;
        CHECK(Status::kOk == to->receive(received, sizeof received, &got));
        LONGS_EQUAL(n, got);
        MEMCMP_EQUAL(payload, received, n);
        if (duplex) {
            CHECK(Status::kOk == from->receive(received, sizeof received, &got));
            LONGS_EQUAL(m, got);
            MEMCMP_EQUAL(other, received, m);
        }
        CHECK(Status::kEmpty == to->receive(received, sizeof received, &got));
        ++delivered;
    }
    LONGS_EQUAL(200, delivered);
    LONGS_EQUAL(0, events.total());
}
