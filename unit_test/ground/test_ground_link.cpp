// Ground links: UDP round trip on loopback (ephemeral ports, so the suite can run
// beside a live rse-fsw on 1234/1235), address parsing, and clear errors for
// links that cannot open.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cstdint>
#include <string>
#include <vector>

#include "ground/ground_link.hpp"
#include "ground/ground_session.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

// A plain UDP socket on 127.0.0.1, ephemeral port: the rover's side.
class RoverSocket {
public:
    RoverSocket() {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = 0;
        ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        socklen_t length = sizeof a;
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length);
        port_ = ntohs(a.sin_port);
        timeval tv{2, 0};
        ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    }
    ~RoverSocket() { ::close(fd_); }
    std::uint16_t port() const { return port_; }
    // Receives one datagram, remembering who sent it.
    std::vector<std::uint8_t> receive() {
        std::vector<std::uint8_t> buffer(2048);
        socklen_t length = sizeof from_;
        const ssize_t n = ::recvfrom(fd_, buffer.data(), buffer.size(), 0, reinterpret_cast<sockaddr*>(&from_), &length);
        buffer.resize(n > 0 ? static_cast<std::size_t>(n) : 0);
        return buffer;
    }
    void sendTo(std::uint16_t port, const std::vector<std::uint8_t>& data) {
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        a.sin_port = htons(port);
        ::sendto(fd_, data.data(), data.size(), 0, reinterpret_cast<sockaddr*>(&a), sizeof a);
    }
    std::uint16_t lastSenderPort() const { return ntohs(from_.sin_port); }

private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
    sockaddr_in from_{};
};

std::string linkError(void (*open)()) {
    try {
        open();
    } catch (const ground::LinkError& e) {
        return e.what();
    }
    return "";
}

}  // namespace

TEST_GROUP(GroundLink){};

TEST(GroundLink, UdpRoundTripOnLoopback) {
    RoverSocket rover;
    ground::UdpGroundLink link({"127.0.0.1", rover.port()}, {"127.0.0.1", 0});
    CHECK_TRUE(link.localPort() != 0);
    CHECK_TRUE(link.localPort() != ground::kDefaultTelemetryPort);

    const std::vector<std::uint8_t> command = {0x19, 0x80, 0xC0, 0x00, 0x00, 0x07, 1, 2, 3};
    link.send(command);
    CHECK_TRUE(rover.receive() == command);
    // Commands leave from the telemetry socket: the rover can answer the sender.
    CHECK_EQUAL(link.localPort(), rover.lastSenderPort());

    const std::vector<std::uint8_t> telemetry(300, 0xAB);
    rover.sendTo(link.localPort(), telemetry);
    const auto got = link.receive(2.0);
    CHECK_TRUE(got.has_value());
    CHECK_TRUE(*got == telemetry);
    CHECK_TRUE(link.describe().find("UDP 127.0.0.1:" + std::to_string(rover.port())) == 0);
}

TEST(GroundLink, UdpReceiveTimesOutWithNothing) {
    RoverSocket rover;
    ground::UdpGroundLink link({"127.0.0.1", rover.port()}, {"127.0.0.1", 0});
    const double start = ground::monotonicSeconds();
    CHECK_FALSE(link.receive(0.1).has_value());
    const double waited = ground::monotonicSeconds() - start;
    CHECK_TRUE(waited >= 0.09);
    CHECK_TRUE(waited < 1.0);
    CHECK_FALSE(link.receive(0.0).has_value());
}

TEST(GroundLink, SendOnlyLinkDoesNotBindTheTelemetryPort) {
    RoverSocket rover;
    RoverSocket holder;  // a port already taken
    ground::UdpGroundLink link({"127.0.0.1", rover.port()}, {"127.0.0.1", holder.port()}, false);
    link.send({1, 2, 3});
    CHECK_EQUAL(3U, rover.receive().size());
    CHECK_FALSE(link.receive(0.05).has_value());
}

TEST(GroundLink, TelemetryPortInUseIsAClearError) {
    RoverSocket holder;
    std::string message;
    try {
        ground::UdpGroundLink link({"127.0.0.1", 9}, {"127.0.0.1", holder.port()});
    } catch (const ground::LinkError& e) {
        message = e.what();
    }
    CHECK_TRUE(message.find("cannot receive telemetry on UDP 127.0.0.1:" + std::to_string(holder.port())) == 0);
    CHECK_TRUE(message.find("in use") != std::string::npos);
}

TEST(GroundLink, UnresolvableHostIsAClearError) {
    const std::string message = linkError([] {
        ground::UdpGroundLink link({"no-such-host.invalid", 1234}, {"127.0.0.1", 0});
    });
    CHECK_TRUE(message.find("cannot resolve host 'no-such-host.invalid'") != std::string::npos);
}

TEST(GroundLink, HostPortParsing) {
    ground::HostPort a = ground::parseHostPort("10.0.0.2:4000", "127.0.0.1", 1234);
    STRCMP_EQUAL("10.0.0.2", a.host.c_str());
    CHECK_EQUAL(4000, a.port);
    a = ground::parseHostPort("rover.local", "127.0.0.1", 1234);
    STRCMP_EQUAL("rover.local", a.host.c_str());
    CHECK_EQUAL(1234, a.port);
    a = ground::parseHostPort("1300", "0.0.0.0", 1235);
    STRCMP_EQUAL("0.0.0.0", a.host.c_str());
    CHECK_EQUAL(1300, a.port);
    a = ground::parseHostPort(":1301", "0.0.0.0", 1235);
    STRCMP_EQUAL("0.0.0.0", a.host.c_str());
    CHECK_EQUAL(1301, a.port);
    CHECK_THROWS(ground::LinkError, ground::parseHostPort("host:99999", "x", 1));
    CHECK_THROWS(ground::LinkError, ground::parseHostPort("host:12ab", "x", 1));
    CHECK_THROWS(ground::LinkError, ground::parseHostPort("host:", "x", 1));
}

TEST(GroundLink, IsoTpOnAMissingInterfaceIsAClearError) {
    // Whether this kernel has CAN at all or not, the message names the interface.
    const std::string message = linkError([] { ground::IsoTpGroundLink link("rsenocan7"); });
    CHECK_TRUE(message.rfind("cannot open ISO-TP on rsenocan7: ", 0) == 0);
    const std::string bad = linkError([] { ground::IsoTpGroundLink link("vcan0", 0x800, 0x6C1); });
    CHECK_TRUE(bad.find("11-bit") != std::string::npos);
}
