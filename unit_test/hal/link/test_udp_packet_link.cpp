// The UDP ground link on the loopback interface, against a plain POSIX socket as
// the ground: round trips, oversized datagrams, a ground that is not listening,
// bad addresses, a port in use, and no heap once open. Ports are chosen by the
// kernel (port 0), so the suite runs beside anything else on the machine.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/link/link_events.hpp"
#include "hal/link/udp_packet_link.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;

namespace {

constexpr const char* kLoopback = "127.0.0.1";
// Attempts (1 ms apart) to wait for a datagram on loopback. Not a timing
// assertion: loopback delivers at once, this only absorbs a busy host.
constexpr int kPatience = 2000;

void pause1ms() {
    const timespec ms{0, 1000000};
    nanosleep(&ms, nullptr);
}

sockaddr_in loopback(std::uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    inet_pton(AF_INET, kLoopback, &a.sin_addr);
    return a;
}

// The ground: a UDP socket on 127.0.0.1 at a port the kernel picks.
struct GroundSocket {
    int fd = -1;
    std::uint16_t port = 0;

    GroundSocket() {
        fd = socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a = loopback(0);
        if (fd >= 0 && bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0) {
            socklen_t size = sizeof a;
            getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size);
            port = ntohs(a.sin_port);
        }
    }
    ~GroundSocket() { close(); }
    void close() {
        if (fd >= 0) {
            ::close(fd);
            fd = -1;
        }
    }
    bool sendTo(std::uint16_t to, const std::uint8_t* data, std::size_t length) const {
        const sockaddr_in a = loopback(to);
        return sendto(fd, data, length, 0, reinterpret_cast<const sockaddr*>(&a), sizeof a) ==
               static_cast<ssize_t>(length);
    }
    // One datagram, or -1 when none comes within the patience.
    long receive(std::uint8_t* out, std::size_t capacity) const {
        pollfd p{fd, POLLIN, 0};
        if (poll(&p, 1, kPatience) != 1) {
            return -1;
        }
        return static_cast<long>(recv(fd, out, capacity, MSG_DONTWAIT));
    }
};

// A port nobody listens on: bound by the kernel's choice, then released.
std::uint16_t closedPort() {
    GroundSocket s;
    const std::uint16_t port = s.port;
    s.close();
    return port;
}

void fill(std::uint8_t* data, std::size_t length, std::uint8_t tag) {
    for (std::size_t i = 0; i < length; ++i) {
        data[i] = static_cast<std::uint8_t>(tag * 17U + i * 3U);
    }
}

// Whether this platform counts a socket's drops at all: a plain socket asked
// for SO_RXQ_OVFL. Linux has it since 2.6.33; qemu-user (the aarch64 suites in
// make test) refuses it (ENOPROTOOPT). Where it is refused the link must say so
// (kLinkRxDegraded) and go on; where it is there it must count.
bool platformCountsKernelDrops() {
    const int fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (fd < 0) {
        return false;
    }
    const int on = 1;
    const bool ok = setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) == 0;
    close(fd);
    return ok;
}

}  // namespace

TEST_GROUP(UdpPacketLink) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    hal::UdpPacketLink link{events};
    GroundSocket ground;
    std::uint8_t sent[2048] = {};
    std::uint8_t got[2048] = {};
    std::size_t length = 0;

    void openToGround() {
        CHECK(ground.port != 0);
        CHECK(Status::kOk == link.open(kLoopback, 0, kLoopback, ground.port));
        CHECK_TRUE(link.isOpen());
        CHECK(link.boundPort() != 0);
    }
    // The link's next datagram, waiting out a busy host.
    Status receiveSoon(std::size_t capacity) {
        Status s = Status::kEmpty;
        for (int i = 0; i < kPatience && s == Status::kEmpty; ++i) {
            s = link.receive(got, capacity, &length);
            if (s == Status::kEmpty) {
                pause1ms();
            }
        }
        return s;
    }
};

TEST(UdpPacketLink, OpenReportsWhereCommandsArriveAndTelemetryGoes) {
    openToGround();
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkOpened));
    STRCMP_EQUAL(kLoopback, link.telemetryHost());
    LONGS_EQUAL(ground.port, link.telemetryPort());
    STRCMP_EQUAL("udp", link.name());
}

TEST(UdpPacketLink, CommandsAndTelemetryMakeTheRoundTripIntact) {
    openToGround();
    fill(sent, 256, 1);
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 256));
    CHECK(Status::kOk == receiveSoon(256));
    LONGS_EQUAL(256, length);
    MEMCMP_EQUAL(sent, got, 256);

    fill(sent, 512, 2);
    CHECK(Status::kOk == link.send(sent, 512));
    LONGS_EQUAL(512, ground.receive(got, sizeof got));
    MEMCMP_EQUAL(sent, got, 512);

    LONGS_EQUAL(1, link.stats().rxPackets);
    LONGS_EQUAL(1, link.stats().txPackets);
    LONGS_EQUAL(0, link.stats().errors);
    CHECK(Status::kEmpty == link.receive(got, sizeof got, &length));
}

TEST(UdpPacketLink, OneDatagramPerCallInArrivalOrder) {
    openToGround();
    for (std::uint8_t i = 0; i < 5; ++i) {
        fill(sent, 10U + i, i);
        CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 10U + i));
    }
    std::uint8_t want[32];
    for (std::uint8_t i = 0; i < 5; ++i) {
        CHECK(Status::kOk == receiveSoon(256));
        LONGS_EQUAL(10U + i, length);
        fill(want, 10U + i, i);
        MEMCMP_EQUAL(want, got, length);
    }
    LONGS_EQUAL(5, link.stats().rxPackets);
}

TEST(UdpPacketLink, OversizedDatagramIsDroppedWholeCountedAndEvented) {
    openToGround();
    fill(sent, 300, 3);
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 300));
    fill(sent, 40, 4);
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 40));
    CHECK(Status::kTooLarge == receiveSoon(256));
    LONGS_EQUAL(300, length);  // how long it really was
    LONGS_EQUAL(1, link.stats().rxDropped);
    LONGS_EQUAL(0, link.stats().rxPackets);
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkRxTooLarge));
    // The next read is the next datagram, not the rest of the long one.
    CHECK(Status::kOk == receiveSoon(256));
    LONGS_EQUAL(40, length);
    MEMCMP_EQUAL(sent, got, 40);
}

TEST(UdpPacketLink, EmptyDatagramIsPassedOnAsAnEmptyPacket) {
    openToGround();
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 0));
    CHECK(Status::kOk == receiveSoon(256));
    LONGS_EQUAL(0, length);
}

TEST(UdpPacketLink, GroundNotListeningNeverStopsTheRoverAndIsCountedAndThrottled) {
    openToGround();
    CHECK(Status::kOk == link.setTelemetryDestination(kLoopback, closedPort()));
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkTelemetryRedirected));
    fill(sent, 100, 5);
    for (int i = 0; i < 10; ++i) {
        CHECK(Status::kOk == link.send(sent, 100));  // never blocks, never refused for it
        link.service();
    }
    for (int i = 0; i < kPatience && link.undeliverableReports() < 10; ++i) {
        pause1ms();
        link.service();
    }
    // Every datagram was reported undeliverable, once: counted, evented 1, 2, 4, 8.
    LONGS_EQUAL(10, link.undeliverableReports());
    LONGS_EQUAL(10, link.stats().txPackets);
    LONGS_EQUAL(0, link.stats().txDropped);
    LONGS_EQUAL(10, link.stats().errors);
    LONGS_EQUAL(ECONNREFUSED, link.lastErrno());
    LONGS_EQUAL(4, rse::test::drainEventsWithId(events, hal::events::kLinkTxUndeliverable));

    // Commands still arrive, and telemetry flows again once the operator points it at a listener.
    fill(sent, 50, 6);
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 50));
    CHECK(Status::kOk == receiveSoon(256));
    MEMCMP_EQUAL(sent, got, 50);
    CHECK(Status::kOk == link.setTelemetryDestination(kLoopback, ground.port));
    CHECK(Status::kOk == link.send(sent, 50));
    LONGS_EQUAL(50, ground.receive(got, sizeof got));
}

TEST(UdpPacketLink, AReportHandedToSendIsCountedOnceAndThePacketStillGoes) {
    openToGround();
    CHECK(Status::kOk == link.setTelemetryDestination(kLoopback, closedPort()));
    fill(sent, 100, 8);
    for (int i = 0; i < 20; ++i) {  // no service(): Linux hands the reports to sendto()
        CHECK(Status::kOk == link.send(sent, 100));
    }
    for (int i = 0; i < kPatience && link.undeliverableReports() < 20; ++i) {
        pause1ms();
        link.service();
    }
    LONGS_EQUAL(20, link.stats().txPackets);
    LONGS_EQUAL(0, link.stats().txDropped);
    LONGS_EQUAL(20, link.undeliverableReports());
    LONGS_EQUAL(20, link.stats().errors);  // each report once, no send error besides
    LONGS_EQUAL(5, rse::test::drainEventsWithId(events, hal::events::kLinkTxUndeliverable));  // 1, 2, 4, 8, 16
}

TEST(UdpPacketLink, AReportReturnedByReceiveDoesNotHideTheCommandBehindIt) {
    openToGround();
    CHECK(Status::kOk == link.setTelemetryDestination(kLoopback, closedPort()));
    fill(sent, 100, 9);
    CHECK(Status::kOk == link.send(sent, 100));
    fill(sent, 30, 10);
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 30));
    CHECK(Status::kOk == receiveSoon(256));  // no service() first
    LONGS_EQUAL(30, length);
    MEMCMP_EQUAL(sent, got, 30);
    LONGS_EQUAL(1, link.undeliverableReports());
    LONGS_EQUAL(1, link.stats().errors);
    LONGS_EQUAL(0, rse::test::drainEventsWithId(events, hal::events::kLinkRxError));
}

TEST(UdpPacketLink, BadAddressesAreRefusedWithStatusEventAndErrno) {
    CHECK(Status::kInvalidArgument == link.open("rover.local", 0, kLoopback, ground.port));
    CHECK_FALSE(link.isOpen());
    LONGS_EQUAL(EINVAL, link.lastErrno());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkBadAddress));

    CHECK(Status::kInvalidArgument == link.open(kLoopback, 0, "300.1.2.3", ground.port));
    CHECK(Status::kInvalidArgument == link.open(kLoopback, 0, nullptr, ground.port));
    CHECK(Status::kInvalidArgument == link.open(kLoopback, 0, kLoopback, 0));
    CHECK_FALSE(link.isOpen());
    LONGS_EQUAL(3, rse::test::drainEventsWithId(events, hal::events::kLinkBadAddress));

    // On an open link a bad destination keeps the one it had.
    openToGround();
    CHECK(Status::kInvalidArgument == link.setTelemetryDestination("ground", 1235));
    LONGS_EQUAL(ground.port, link.telemetryPort());
    STRCMP_EQUAL(kLoopback, link.telemetryHost());
    fill(sent, 8, 7);
    CHECK(Status::kOk == link.send(sent, 8));
    LONGS_EQUAL(8, ground.receive(got, sizeof got));
}

TEST(UdpPacketLink, PortInUseFailsTheOpenWithStatusEventAndErrno) {
    CHECK(Status::kUnavailable == link.open(kLoopback, ground.port, kLoopback, ground.port));
    CHECK_FALSE(link.isOpen());
    LONGS_EQUAL(EADDRINUSE, link.lastErrno());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkOpenFailed));
    LONGS_EQUAL(0, link.boundPort());
}

TEST(UdpPacketLink, AnAddressNotOnThisHostFailsTheBind) {
    CHECK(Status::kUnavailable == link.open("192.0.2.1", 0, kLoopback, ground.port));  // TEST-NET-1
    LONGS_EQUAL(EADDRNOTAVAIL, link.lastErrno());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkOpenFailed));
}

TEST(UdpPacketLink, ClosedLinkRefusesAndCountsAndCloseIsEvented) {
    CHECK(Status::kUnavailable == link.send(sent, 10));
    CHECK(Status::kUnavailable == link.receive(got, sizeof got, &length));
    LONGS_EQUAL(1, link.stats().txDropped);
    openToGround();
    const std::uint16_t port = link.boundPort();
    link.close();
    CHECK_FALSE(link.isOpen());
    LONGS_EQUAL(1, rse::test::drainEventsWithId(events, hal::events::kLinkClosed));
    CHECK(Status::kUnavailable == link.send(sent, 10));
    // The port is free again.
    CHECK(Status::kOk == link.open(kLoopback, port, kLoopback, ground.port));
    LONGS_EQUAL(port, link.boundPort());
}

TEST(UdpPacketLink, DestructorReleasesThePort) {
    std::uint16_t port = 0;
    {
        hal::UdpPacketLink scoped;  // no event log: still works
        CHECK(Status::kOk == scoped.open(kLoopback, 0, kLoopback, ground.port));
        port = scoped.boundPort();
    }
    CHECK(Status::kOk == link.open(kLoopback, port, kLoopback, ground.port));
}

TEST(UdpPacketLink, EmptyOrOversizedSendsAreRefusedAndCounted) {
    openToGround();
    CHECK(Status::kInvalidArgument == link.send(sent, 0));
    CHECK(Status::kInvalidArgument == link.send(nullptr, 10));
    static std::uint8_t huge[70000];
    CHECK(Status::kTooLarge == link.send(huge, sizeof huge));  // beyond any UDP datagram
    LONGS_EQUAL(3, link.stats().txDropped);
    LONGS_EQUAL(0, link.stats().txPackets);
    LONGS_EQUAL(2, rse::test::drainEventsWithId(events, hal::events::kLinkTxInvalid));  // the 1st and 2nd of 3
}

TEST(UdpPacketLink, NullLengthOrBufferIsRefused) {
    openToGround();
    CHECK(Status::kInvalidArgument == link.receive(got, sizeof got, nullptr));
    CHECK(Status::kInvalidArgument == link.receive(nullptr, 10, &length));
}

TEST(UdpPacketLink, ReceiveSendAndServiceAllocateNothingOnceOpen) {
    openToGround();
    std::uint32_t moved = 0;
    rse::test::AllocationWatch watch;
    for (std::uint8_t i = 0; i < 50; ++i) {
        fill(sent, 100, i);
        (void)ground.sendTo(link.boundPort(), sent, 100);
        moved += core::isOk(receiveSoon(256)) ? 1U : 0U;
        moved += core::isOk(link.send(sent, 100)) ? 1U : 0U;
        moved += ground.receive(got, sizeof got) == 100 ? 1U : 0U;
        link.service();
        (void)link.receive(got, 10, &length);  // nothing waiting: kEmpty
    }
    const auto allocations = watch.count();
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(150, moved);
}

// ---- Floods: batches, the receive buffer and kernel drops (docs/icd.md, "Floods") ----

namespace {

// The kernel's own drop count of the UDP socket bound to 127.0.0.1:port
// (/proc/net/udp, last column), or -1 when it cannot be read.
long procUdpDrops(std::uint16_t port) {
    std::FILE* f = std::fopen("/proc/net/udp", "r");
    if (f == nullptr) {
        return -1;
    }
    char line[512];
    long drops = -1;
    char want[32];
    std::snprintf(want, sizeof want, "0100007F:%04X", static_cast<unsigned>(port));
    while (std::fgets(line, sizeof line, f) != nullptr) {
        if (std::strstr(line, want) != nullptr) {
            // The last field (the line ends in spaces).
            const char* last = nullptr;
            for (const char* c = line; *c != '\0'; ++c) {
                if (*c != ' ' && *c != '\n' && (c == line || c[-1] == ' ')) {
                    last = c;
                }
            }
            drops = last != nullptr ? std::strtol(last, nullptr, 10) : -1;
        }
    }
    std::fclose(f);
    return drops;
}

}  // namespace

TEST(UdpPacketLink, ManyDatagramsAreHandedOverInBatchesInArrivalOrder) {
    openToGround();
    const unsigned count = 3 * static_cast<unsigned>(hal::kUdpRxBatch) + 5;
    for (unsigned i = 0; i < count; ++i) {
        fill(sent, 20, static_cast<std::uint8_t>(i));
        sent[0] = static_cast<std::uint8_t>(i);
        CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 20));
    }
    for (unsigned i = 0; i < count; ++i) {
        CHECK(Status::kOk == receiveSoon(256));
        LONGS_EQUAL(20, length);
        LONGS_EQUAL(static_cast<std::uint8_t>(i), got[0]);
    }
    CHECK(Status::kEmpty == link.receive(got, sizeof got, &length));
    LONGS_EQUAL(count, link.stats().rxPackets);
}

TEST(UdpPacketLink, DatagramsReadButNotHandedOverAreCountedWhenTheLinkCloses) {
    openToGround();
    for (std::uint8_t i = 0; i < 10; ++i) {
        CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 30));
    }
    // Loopback queues them at once; the first receive reads all ten in one batch.
    CHECK(Status::kOk == receiveSoon(256));
    const std::uint32_t read = link.stats().rxPackets;
    link.close();
    LONGS_EQUAL(10, read + link.stats().rxDropped);
}

TEST(UdpPacketLink, TheReceiveBufferIsSizedForAFloodOrTheShortfallEvented) {
    openToGround();
    unsigned degraded = 0;
    bool refusalSaid = false;
    core::Event e;
    while (core::isOk(events.pop(&e))) {
        degraded += e.id == hal::events::kLinkRxDegraded ? 1U : 0U;
        refusalSaid = refusalSaid || (e.id == hal::events::kLinkRxDegraded &&
                                      std::strstr(e.text, "SO_RXQ_OVFL refused") != nullptr);
    }
    if (platformCountsKernelDrops()) {
        CHECK(link.receiveBufferBytes() >= hal::kUdpReceiveBufferBytes || degraded == 1);
        CHECK_TRUE(link.kernelDropsCounted());
    } else {
        // No drop count on this platform: said once more, as an error, and the link still opens.
        CHECK(degraded >= 1);
        CHECK_TRUE(refusalSaid);
        CHECK_FALSE(link.kernelDropsCounted());
    }
}

// Old link: the kernel dropped what did not fit the socket buffer and nobody counted it.
TEST(UdpPacketLink, KernelDropsOfAnOverfilledSocketAreCountedAndEvented) {
    link.setReceiveBufferRequest(4096);  // the kernel's minimum: a few datagrams fit
    openToGround();
    if (!platformCountsKernelDrops()) {
        // qemu-user: nothing to count with; the previous test checks the link says so.
        CHECK_FALSE(link.kernelDropsCounted());
        return;
    }
    CHECK_TRUE(link.kernelDropsCounted());
    constexpr unsigned kSent = 2000;
    fill(sent, 100, 11);
    for (unsigned i = 0; i < kSent; ++i) {
        CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 100));  // loopback: queued or dropped at once
    }
    unsigned read = 0;
    while (link.receive(got, 256, &length) == Status::kOk) {
        ++read;
    }
    CHECK(read > 0);
    CHECK(read < kSent);
    // Drops show with the next datagram queued after them.
    CHECK_TRUE(ground.sendTo(link.boundPort(), sent, 100));
    CHECK(Status::kOk == receiveSoon(256));
    ++read;
    LONGS_EQUAL(read, link.stats().rxPackets);
    LONGS_EQUAL(kSent + 1, link.stats().rxPackets + link.stats().rxKernelDropped);
    CHECK(rse::test::drainEventsWithId(events, hal::events::kLinkRxKernelDrops) >= 1);
    // The same number the kernel keeps for the socket.
    const long kernel = procUdpDrops(link.boundPort());
    if (kernel >= 0) {
        LONGS_EQUAL(kernel, static_cast<long>(link.stats().rxKernelDropped));
    }
}
