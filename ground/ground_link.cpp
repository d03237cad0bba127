#include "ground/ground_link.hpp"

#include <arpa/inet.h>
#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <linux/can.h>
#include <linux/can/isotp.h>
#include <net/if.h>
#include <netdb.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

namespace rse::ground {
namespace {

constexpr std::size_t kMaxDatagram = 65536;
constexpr std::size_t kMaxIsoTpMessage = 4095;

std::string errnoText(int error) { return std::strerror(error); }

std::string hexId(std::uint32_t id) {
    char buffer[16];
    std::snprintf(buffer, sizeof buffer, "0x%03X", static_cast<unsigned>(id));
    return buffer;
}

int timeoutMs(double seconds) {
    if (!(seconds > 0.0)) {
        return 0;
    }
    const double ms = std::ceil(seconds * 1000.0);
    return ms > 2.0e9 ? 2000000000 : static_cast<int>(ms);
}

// Waits for the descriptor to be readable; false on timeout. Throws on error.
bool waitReadable(int fd, double timeoutSeconds, const std::string& what) {
    pollfd p{};
    p.fd = fd;
    p.events = POLLIN;
    for (;;) {
        const int n = ::poll(&p, 1, timeoutMs(timeoutSeconds));
        if (n > 0) {
            return true;
        }
        if (n == 0) {
            return false;
        }
        if (errno != EINTR) {
            throw LinkError(what + ": poll failed: " + errnoText(errno));
        }
    }
}

sockaddr_in resolveIpv4(const std::string& host, std::uint16_t port, const std::string& what) {
    sockaddr_in address{};
    address.sin_family = AF_INET;
    address.sin_port = htons(port);
    if (host.empty() || host == "0.0.0.0" || host == "*") {
        address.sin_addr.s_addr = htonl(INADDR_ANY);
        return address;
    }
    if (::inet_pton(AF_INET, host.c_str(), &address.sin_addr) == 1) {
        return address;
    }
    addrinfo hints{};
    hints.ai_family = AF_INET;
    hints.ai_socktype = SOCK_DGRAM;
    addrinfo* found = nullptr;
    const int rc = ::getaddrinfo(host.c_str(), nullptr, &hints, &found);
    if (rc != 0 || found == nullptr) {
        throw LinkError(what + ": cannot resolve host '" + host + "': " + ::gai_strerror(rc));
    }
    // Copied out, not cast: ai_addr is a sockaddr*, less aligned than sockaddr_in
    // (a cast is undefined where alignment is enforced, 32-bit ARM).
    sockaddr_in resolved{};
    std::memcpy(&resolved, found->ai_addr,
                std::min(sizeof resolved, static_cast<std::size_t>(found->ai_addrlen)));
    address.sin_addr = resolved.sin_addr;
    ::freeaddrinfo(found);
    return address;
}

}  // namespace

HostPort parseHostPort(const std::string& text, const std::string& defaultHost, std::uint16_t defaultPort) {
    HostPort result{defaultHost, defaultPort};
    const std::size_t colon = text.rfind(':');
    std::string portText;
    if (colon == std::string::npos) {
        // A bare number is a port, anything else a host.
        if (!text.empty() && text.find_first_not_of("0123456789") == std::string::npos) {
            portText = text;
        } else {
            result.host = text;
        }
    } else {
        if (colon > 0) {
            result.host = text.substr(0, colon);
        }
        portText = text.substr(colon + 1);
        if (portText.empty()) {
            throw LinkError("'" + text + "': port missing after ':'");
        }
    }
    if (!portText.empty()) {
        if (portText.size() > 5 || portText.find_first_not_of("0123456789") != std::string::npos ||
            std::stoul(portText) > 65535) {
            throw LinkError("'" + text + "': port must be a number 0..65535");
        }
        result.port = static_cast<std::uint16_t>(std::stoul(portText));
    }
    if (result.host.empty()) {
        result.host = defaultHost;
    }
    return result;
}

// ---- UDP -------------------------------------------------------------------------
UdpGroundLink::UdpGroundLink(const HostPort& remote, const HostPort& local, bool listen)
    : remote_(remote), localAddress_(local.host.empty() ? "0.0.0.0" : local.host), listening_(listen) {
    const std::string what = "UDP " + remote.host + ":" + std::to_string(remote.port);
    const sockaddr_in to = resolveIpv4(remote.host, remote.port, what);
    remoteAddress_.resize(sizeof to);
    std::memcpy(remoteAddress_.data(), &to, sizeof to);

    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd_ < 0) {
        throw LinkError("cannot open a UDP socket: " + errnoText(errno));
    }
    sockaddr_in bindAddress = resolveIpv4(listen ? localAddress_ : "0.0.0.0", listen ? local.port : 0,
                                          "telemetry address");
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&bindAddress), sizeof bindAddress) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        std::string text = "cannot receive telemetry on UDP " + localAddress_ + ":" + std::to_string(local.port) +
                           ": " + errnoText(error);
        if (error == EADDRINUSE) {
            text += " (another rse-ground watch/run on this port? use another --tlm-port, or send --no-wait)";
        }
        throw LinkError(text);
    }
    sockaddr_in bound{};
    socklen_t length = sizeof bound;
    if (::getsockname(fd_, reinterpret_cast<sockaddr*>(&bound), &length) == 0) {
        localPort_ = ntohs(bound.sin_port);
    }
}

UdpGroundLink::~UdpGroundLink() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void UdpGroundLink::send(const std::vector<std::uint8_t>& packet) {
    sockaddr_in to{};  // the stored bytes, in a properly aligned sockaddr_in
    std::memcpy(&to, remoteAddress_.data(), sizeof to);
    const ssize_t n =
        ::sendto(fd_, packet.data(), packet.size(), 0, reinterpret_cast<const sockaddr*>(&to), sizeof to);
    if (n < 0 || static_cast<std::size_t>(n) != packet.size()) {
        throw LinkError("cannot send to UDP " + remote_.host + ":" + std::to_string(remote_.port) + ": " +
                        (n < 0 ? errnoText(errno) : std::string("short write")));
    }
}

std::optional<std::vector<std::uint8_t>> UdpGroundLink::receive(double timeoutSeconds) {
    if (!listening_) {
        return std::nullopt;
    }
    if (!waitReadable(fd_, timeoutSeconds, describe())) {
        return std::nullopt;
    }
    std::vector<std::uint8_t> buffer(kMaxDatagram);
    const ssize_t n = ::recv(fd_, buffer.data(), buffer.size(), 0);
    if (n < 0) {
        if (errno == EAGAIN || errno == EINTR || errno == ECONNREFUSED) {
            return std::nullopt;
        }
        throw LinkError(describe() + ": receive failed: " + errnoText(errno));
    }
    buffer.resize(static_cast<std::size_t>(n));
    return buffer;
}

std::string UdpGroundLink::describe() const {
    std::string text = "UDP " + remote_.host + ":" + std::to_string(remote_.port);
    if (listening_) {
        text += " (telemetry on " + localAddress_ + ":" + std::to_string(localPort_) + ")";
    }
    return text;
}

// ---- ISO-TP ----------------------------------------------------------------------
IsoTpGroundLink::IsoTpGroundLink(const std::string& interface, std::uint32_t txId, std::uint32_t rxId,
                                 bool padFrames)
    : interface_(interface), txId_(txId), rxId_(rxId), pad_(padFrames) {
    const std::string what = "cannot open ISO-TP on " + interface;
    if (interface.empty() || interface.size() >= IFNAMSIZ) {
        throw LinkError(what + ": not an interface name");
    }
    if (txId > CAN_SFF_MASK || rxId > CAN_SFF_MASK) {
        throw LinkError(what + ": CAN ids must be 11-bit (0x000..0x7FF)");
    }
    fd_ = ::socket(PF_CAN, SOCK_DGRAM | SOCK_CLOEXEC, CAN_ISOTP);
    if (fd_ < 0) {
        const int error = errno;
        std::string text = what + ": " + errnoText(error);
        if (error == EPROTONOSUPPORT || error == EAFNOSUPPORT || error == EINVAL) {
            text += " (this kernel has no CAN or no can-isotp: try 'modprobe can-isotp')";
        }
        throw LinkError(text);
    }
    can_isotp_options options{};
    options.flags = pad_ ? CAN_ISOTP_TX_PADDING : 0U;
    options.txpad_content = 0xCC;
    options.rxpad_content = 0xCC;
    if (::setsockopt(fd_, SOL_CAN_ISOTP, CAN_ISOTP_OPTS, &options, sizeof options) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        throw LinkError(what + ": setting ISO-TP options failed: " + errnoText(error));
    }
    const unsigned index = ::if_nametoindex(interface.c_str());
    if (index == 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        throw LinkError(what + ": no such interface (" + errnoText(error) +
                        "; for a virtual bus: ip link add dev " + interface + " type vcan && ip link set up " +
                        interface + ")");
    }
    sockaddr_can address{};
    address.can_family = AF_CAN;
    address.can_ifindex = static_cast<int>(index);
    address.can_addr.tp.tx_id = txId;
    address.can_addr.tp.rx_id = rxId;
    if (::bind(fd_, reinterpret_cast<const sockaddr*>(&address), sizeof address) != 0) {
        const int error = errno;
        ::close(fd_);
        fd_ = -1;
        throw LinkError(what + ": bind failed: " + errnoText(error) + (error == ENETDOWN ? " (interface down?)" : ""));
    }
}

IsoTpGroundLink::~IsoTpGroundLink() {
    if (fd_ >= 0) {
        ::close(fd_);
    }
}

void IsoTpGroundLink::send(const std::vector<std::uint8_t>& packet) {
    if (packet.empty() || packet.size() > kMaxIsoTpMessage) {
        throw LinkError(describe() + ": a message must be 1..4095 bytes");
    }
    const ssize_t n = ::write(fd_, packet.data(), packet.size());
    if (n < 0 || static_cast<std::size_t>(n) != packet.size()) {
        const int error = errno;
        std::string text = describe() + ": send failed: " + (n < 0 ? errnoText(error) : std::string("short write"));
        if (n < 0 && (error == ECOMM || error == ETIMEDOUT)) {
            text += " (no flow control from the rover: is rse-fsw running on this bus?)";
        } else if (n < 0 && error == ENETDOWN) {
            text += " (interface down)";
        }
        throw LinkError(text);
    }
}

std::optional<std::vector<std::uint8_t>> IsoTpGroundLink::receive(double timeoutSeconds) {
    if (!waitReadable(fd_, timeoutSeconds, describe())) {
        return std::nullopt;
    }
    std::vector<std::uint8_t> buffer(kMaxIsoTpMessage + 1);
    const ssize_t n = ::read(fd_, buffer.data(), buffer.size());
    if (n < 0) {
        const int error = errno;
        // Reception errors of one message (timeouts, bad sequence numbers) are
        // reported per message; the socket stays usable.
        if (error == EAGAIN || error == EINTR || error == ETIMEDOUT || error == EILSEQ || error == ECOMM ||
            error == EBADMSG || error == EPROTO) {
            return std::nullopt;
        }
        throw LinkError(describe() + ": receive failed: " + errnoText(error));
    }
    buffer.resize(static_cast<std::size_t>(n));
    return buffer;
}

std::string IsoTpGroundLink::describe() const {
    return "ISO-TP " + interface_ + " tx " + hexId(txId_) + " rx " + hexId(rxId_) + (pad_ ? " padded" : "");
}

}  // namespace rse::ground
