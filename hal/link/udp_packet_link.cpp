#include "hal/link/udp_packet_link.hpp"

#include <arpa/inet.h>
#include <linux/errqueue.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "hal/link/link_events.hpp"

namespace rse::hal {

using core::Severity;
using core::Status;

namespace {

// What an errno means to an operator, without strerror (which may translate and
// allocate): the ones a UDP link meets, the rest by number.
const char* errnoText(int error) {
    switch (error) {
        case EADDRINUSE: return "address in use";
        case EADDRNOTAVAIL: return "address not local";
        case EACCES: return "permission denied";
        case EPERM: return "not permitted";
        case ECONNREFUSED: return "port closed";  // ground not listening
        case EHOSTUNREACH: return "host unreachable";
        case ENETUNREACH: return "network unreachable";
        case ENETDOWN: return "network down";
        case EMSGSIZE: return "packet too large";
        case ENOBUFS: return "no buffer space";
        case EAGAIN: return "would block";
        case EAFNOSUPPORT: return "no IPv4 on this host";
        case EMFILE: return "too many open files";
        default: return "OS error";
    }
}

// A numeric IPv4 address into network byte order and its canonical text.
bool parseIpv4(const char* text, std::uint32_t* address, char (&canonical)[kIpv4TextSize]) {
    in_addr parsed{};
    if (text == nullptr || inet_pton(AF_INET, text, &parsed) != 1) {
        return false;
    }
    *address = parsed.s_addr;
    return inet_ntop(AF_INET, &parsed, canonical, sizeof canonical) != nullptr;
}

sockaddr_in makeAddress(std::uint32_t address, std::uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = address;
    a.sin_port = htons(port);
    return a;
}

unsigned u(std::uint32_t v) { return static_cast<unsigned>(v); }

// The socket buffer or the device queue is full: try again later.
bool isBufferFull(int error) { return error == EAGAIN || error == EWOULDBLOCK || error == ENOBUFS; }

}  // namespace

UdpPacketLink::~UdpPacketLink() { closeSocket(); }

void UdpPacketLink::event(core::EventId id, Severity severity, const char* format, ...) {
    if (events_ == nullptr) {
        return;
    }
    char text[core::kEventTextSize];
    va_list args;
    va_start(args, format);
    std::vsnprintf(text, sizeof text, format, args);
    va_end(args);
    events_->report(id, severity, "%s", text);
}

void UdpPacketLink::closeSocket() {
    if (fd_ >= 0) {
        ::close(fd_);
        fd_ = -1;
    }
    boundPort_ = 0;
    // Read from the kernel but never handed over: lost with the socket, counted.
    stats_.rxDropped += static_cast<std::uint32_t>(rxCount_ - rxNext_);
    rxNext_ = 0;
    rxCount_ = 0;
    receiveBufferBytes_ = 0;
    kernelDropsCounted_ = false;
    kernelDropsSeen_ = 0;
}

// The receive buffer and the kernel-drop count (SO_RXQ_OVFL). Neither failure
// closes the link: commands still arrive, and the operator is told.
void UdpPacketLink::configureReceive(int fd) {
    const int want = receiveBufferRequest_;
    // SO_RCVBUFFORCE passes net.core.rmem_max with CAP_NET_ADMIN; SO_RCVBUF is capped there.
    if (setsockopt(fd, SOL_SOCKET, SO_RCVBUFFORCE, &want, sizeof want) != 0) {
        (void)setsockopt(fd, SOL_SOCKET, SO_RCVBUF, &want, sizeof want);
    }
    int granted = 0;
    socklen_t size = sizeof granted;
    if (getsockopt(fd, SOL_SOCKET, SO_RCVBUF, &granted, &size) != 0) {
        granted = 0;
    }
    receiveBufferBytes_ = granted;
    if (granted < want) {  // the kernel reports twice what it was asked; less means it was capped
        event(events::kLinkRxDegraded, Severity::kWarning,
              "udp: receive buffer %d bytes, asked %d: a flood loses more (net.core.rmem_max)", granted, want);
    }
    const int on = 1;
    kernelDropsCounted_ = setsockopt(fd, SOL_SOCKET, SO_RXQ_OVFL, &on, sizeof on) == 0;
    if (!kernelDropsCounted_) {
        const int error = errno;
        event(events::kLinkRxDegraded, Severity::kError, "udp: SO_RXQ_OVFL refused: %s (errno %d): drops uncounted",
              errnoText(error), error);
    }
}

void UdpPacketLink::close() {
    if (fd_ >= 0) {
        event(events::kLinkClosed, Severity::kInfo, "udp: closed (%u packets in, %u out)", u(stats_.rxPackets),
              u(stats_.txPackets));
    }
    closeSocket();
}

Status UdpPacketLink::open(const char* bindAddress, std::uint16_t commandPort, const char* groundHost,
                           std::uint16_t telemetryPort) {
    close();
    std::uint32_t bindIp = 0;
    if (!parseIpv4(bindAddress, &bindIp, bindHost_)) {
        lastErrno_ = EINVAL;
        event(events::kLinkBadAddress, Severity::kError,
              "udp: bad bind address '%.32s' (numeric IPv4 only): link closed",
              bindAddress == nullptr ? "(null)" : bindAddress);
        return Status::kInvalidArgument;
    }
    const Status destination = setTelemetryDestination(groundHost, telemetryPort);
    if (!core::isOk(destination)) {
        return destination;  // evented there
    }

    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
    if (fd < 0) {
        lastErrno_ = errno;
        event(events::kLinkOpenFailed, Severity::kError, "udp: no socket: %s (errno %d)", errnoText(lastErrno_),
              lastErrno_);
        return Status::kUnavailable;
    }
    const int on = 1;
    if (setsockopt(fd, IPPROTO_IP, IP_RECVERR, &on, sizeof on) != 0) {
        lastErrno_ = errno;
        ::close(fd);
        event(events::kLinkOpenFailed, Severity::kError, "udp: IP_RECVERR refused: %s (errno %d)",
              errnoText(lastErrno_), lastErrno_);
        return Status::kUnavailable;
    }
    const sockaddr_in local = makeAddress(bindIp, commandPort);
    if (bind(fd, reinterpret_cast<const sockaddr*>(&local), sizeof local) != 0) {
        lastErrno_ = errno;
        ::close(fd);
        event(events::kLinkOpenFailed, Severity::kError, "udp: bind %s:%u failed: %s (errno %d)", bindHost_,
              static_cast<unsigned>(commandPort), errnoText(lastErrno_), lastErrno_);
        return Status::kUnavailable;
    }
    sockaddr_in bound{};
    socklen_t boundSize = sizeof bound;
    if (getsockname(fd, reinterpret_cast<sockaddr*>(&bound), &boundSize) != 0) {
        lastErrno_ = errno;
        ::close(fd);
        event(events::kLinkOpenFailed, Severity::kError, "udp: getsockname failed: %s (errno %d)",
              errnoText(lastErrno_), lastErrno_);
        return Status::kUnavailable;
    }
    configureReceive(fd);
    fd_ = fd;
    boundPort_ = ntohs(bound.sin_port);
    lastErrno_ = 0;
    event(events::kLinkOpened, Severity::kInfo, "udp: commands on %s:%u (rx buffer %d), telemetry to %s:%u",
          bindHost_, static_cast<unsigned>(boundPort_), receiveBufferBytes_, telemetryHost_,
          static_cast<unsigned>(telemetryPort_));
    return Status::kOk;
}

Status UdpPacketLink::setTelemetryDestination(const char* groundHost, std::uint16_t telemetryPort) {
    std::uint32_t address = 0;
    char text[kIpv4TextSize] = {};
    if (!parseIpv4(groundHost, &address, text) || telemetryPort == 0) {
        lastErrno_ = EINVAL;
        event(events::kLinkBadAddress, Severity::kError,
              "udp: bad telemetry destination '%.24s':%u (numeric IPv4, port > 0)",
              groundHost == nullptr ? "(null)" : groundHost, static_cast<unsigned>(telemetryPort));
        return Status::kInvalidArgument;
    }
    const bool changed = telemetryAddress_ != address || telemetryPort_ != telemetryPort;
    telemetryAddress_ = address;
    telemetryPort_ = telemetryPort;
    std::memcpy(telemetryHost_, text, sizeof telemetryHost_);
    if (changed && fd_ >= 0) {
        event(events::kLinkTelemetryRedirected, Severity::kInfo, "udp: telemetry now to %s:%u", telemetryHost_,
              static_cast<unsigned>(telemetryPort_));
    }
    return Status::kOk;
}

std::size_t UdpPacketLink::drainErrorReports() {
    std::size_t drained = 0;
    for (; drained < kUdpMaxReportsPerCall; ++drained) {
        // The report carries the start of the refused datagram; it is not needed,
        // but a buffer is given: qemu-user answers a zero-iovec recvmsg with 0.
        std::uint8_t head[8];
        iovec iov{head, sizeof head};
        alignas(cmsghdr) unsigned char control[CMSG_SPACE(sizeof(sock_extended_err) + sizeof(sockaddr_in))];
        msghdr msg{};
        msg.msg_iov = &iov;
        msg.msg_iovlen = 1;
        msg.msg_control = control;
        msg.msg_controllen = sizeof control;
        if (recvmsg(fd_, &msg, MSG_ERRQUEUE | MSG_DONTWAIT) < 0) {
            break;  // EAGAIN: no more reports
        }
        bool isReport = false;
        int reported = 0;
        for (cmsghdr* c = CMSG_FIRSTHDR(&msg); c != nullptr; c = CMSG_NXTHDR(&msg, c)) {
            if (c->cmsg_level == IPPROTO_IP && c->cmsg_type == IP_RECVERR) {
                sock_extended_err report{};
                std::memcpy(&report, CMSG_DATA(c), sizeof report);
                reported = static_cast<int>(report.ee_errno);
                isReport = true;
            }
        }
        if (!isReport) {
            break;  // not what IP_RECVERR queues: nothing to count
        }
        lastErrno_ = reported;
        ++stats_.errors;
        ++undeliverable_;
        if (core::isReportableOccurrence(undeliverable_)) {
            event(events::kLinkTxUndeliverable, Severity::kWarning,
                  "udp: tlm to %s:%u undeliverable: %s (errno %d, %u times)", telemetryHost_,
                  static_cast<unsigned>(telemetryPort_), errnoText(reported), reported, u(undeliverable_));
        }
    }
    return drained;
}

void UdpPacketLink::service() {
    if (fd_ >= 0) {
        (void)drainErrorReports();
    }
}

Status UdpPacketLink::receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) {
    if (length == nullptr || (out == nullptr && capacity > 0)) {
        return Status::kInvalidArgument;
    }
    *length = 0;
    if (fd_ < 0) {
        return Status::kUnavailable;
    }
    if (rxNext_ == rxCount_) {
        const Status status = readBatch();
        if (!core::isOk(status)) {
            return status;
        }
    }
    const std::size_t slot = rxNext_++;
    const std::size_t size = rxMessages_[slot].msg_len;  // the whole datagram's size (MSG_TRUNC)
    *length = size;
    if (size > capacity || size > kUdpMaxDatagram) {
        ++stats_.rxDropped;
        ++rxTooLarge_;
        if (core::isReportableOccurrence(rxTooLarge_)) {
            event(events::kLinkRxTooLarge, Severity::kWarning, "udp: %zu-byte datagram dropped, longer than %zu (%u times)",
                  size, capacity < kUdpMaxDatagram ? capacity : kUdpMaxDatagram, u(rxTooLarge_));
        }
        return Status::kTooLarge;
    }
    if (size > 0) {
        std::memcpy(out, rxData_[slot], size);
    }
    ++stats_.rxPackets;
    return Status::kOk;
}

// Reads up to kUdpRxBatch datagrams with one recvmmsg(): kOk (at least one),
// kEmpty, kUnavailable (an OS error, counted and evented).
Status UdpPacketLink::readBatch() {
    rxNext_ = 0;
    rxCount_ = 0;
    // Two attempts: the first call may return a pending undeliverable report
    // instead of the datagrams that wait behind it.
    for (int attempt = 0; attempt < 2; ++attempt) {
        for (std::size_t i = 0; i < kUdpRxBatch; ++i) {
            rxVectors_[i].iov_base = rxData_[i];
            rxVectors_[i].iov_len = kUdpMaxDatagram;
            msghdr& m = rxMessages_[i].msg_hdr;
            m = msghdr{};
            m.msg_iov = &rxVectors_[i];
            m.msg_iovlen = 1;
            m.msg_control = rxControl_[i];
            m.msg_controllen = sizeof rxControl_[i];
            rxMessages_[i].msg_len = 0;
        }
        const int n = recvmmsg(fd_, rxMessages_, static_cast<unsigned>(kUdpRxBatch), MSG_DONTWAIT | MSG_TRUNC, nullptr);
        if (n > 0) {
            rxCount_ = static_cast<std::size_t>(n);
            bool newDrops = false;
            for (std::size_t i = 0; i < rxCount_; ++i) {
                const std::uint32_t before = stats_.rxKernelDropped;
                countKernelDrops(rxMessages_[i].msg_hdr);
                newDrops = newDrops || stats_.rxKernelDropped != before;
            }
            if (newDrops) {
                ++kernelDropBatches_;
                if (core::isReportableOccurrence(kernelDropBatches_)) {
                    event(events::kLinkRxKernelDrops, Severity::kWarning,
                          "udp: %u datagrams dropped by the OS, receive buffer full (%u reads saw drops)",
                          u(stats_.rxKernelDropped), u(kernelDropBatches_));
                }
            }
            return Status::kOk;
        }
        const int error = n < 0 ? errno : EAGAIN;
        if (error == EAGAIN || error == EWOULDBLOCK) {
            return Status::kEmpty;
        }
        lastErrno_ = error;
        if (drainErrorReports() == 0) {
            ++stats_.errors;
            ++rxErrors_;
            if (core::isReportableOccurrence(rxErrors_)) {
                event(events::kLinkRxError, Severity::kError, "udp: receive failed: %s (errno %d, %u times)",
                      errnoText(error), error, u(rxErrors_));
            }
            return Status::kUnavailable;
        }
    }
    return Status::kEmpty;  // reports only; a datagram behind them is read next call
}

// SO_RXQ_OVFL: the socket's cumulative drop count when this datagram was queued
// (sent only once it is not 0). The increase since the last one seen is new drops.
void UdpPacketLink::countKernelDrops(msghdr& message) {
    for (cmsghdr* c = CMSG_FIRSTHDR(&message); c != nullptr; c = CMSG_NXTHDR(&message, c)) {
        if (c->cmsg_level == SOL_SOCKET && c->cmsg_type == SO_RXQ_OVFL) {
            std::uint32_t total = 0;
            std::memcpy(&total, CMSG_DATA(c), sizeof total);
            const std::uint32_t delta = total - kernelDropsSeen_;  // modulo 2^32, like the kernel's counter
            if (delta != 0 && delta < 0x80000000U) {
                stats_.rxKernelDropped += delta;
                kernelDropsSeen_ = total;
            }
        }
    }
}

Status UdpPacketLink::send(const std::uint8_t* data, std::size_t length) {
    if (fd_ < 0) {
        ++stats_.txDropped;
        return Status::kUnavailable;
    }
    if (data == nullptr || length == 0) {
        ++stats_.txDropped;
        ++txInvalid_;
        if (core::isReportableOccurrence(txInvalid_)) {
            event(events::kLinkTxInvalid, Severity::kError, "udp: empty packet refused (%u times)", u(txInvalid_));
        }
        return Status::kInvalidArgument;
    }
    const sockaddr_in to = makeAddress(telemetryAddress_, telemetryPort_);
    const auto* address = reinterpret_cast<const sockaddr*>(&to);
    ssize_t n = sendto(fd_, data, length, MSG_DONTWAIT, address, sizeof to);
    int error = n < 0 ? errno : 0;
    if (n < 0 && !isBufferFull(error) && error != EMSGSIZE && drainErrorReports() > 0) {
        // The errno was an earlier datagram's report (now counted), and Linux did
        // not send this one: send it again, once, so the result is about this packet.
        n = sendto(fd_, data, length, MSG_DONTWAIT, address, sizeof to);
        error = n < 0 ? errno : 0;
    }
    if (n >= 0) {  // a datagram goes whole or not at all
        ++stats_.txPackets;
        return Status::kOk;
    }
    lastErrno_ = error;
    ++stats_.txDropped;
    if (isBufferFull(error)) {
        ++txFull_;
        if (core::isReportableOccurrence(txFull_)) {
            event(events::kLinkTxFull, Severity::kWarning,
                  "udp: socket buffer full, %zu-byte packet dropped (%u times)", length, u(txFull_));
        }
        return Status::kFull;
    }
    if (error == EMSGSIZE) {
        ++txInvalid_;
        if (core::isReportableOccurrence(txInvalid_)) {
            event(events::kLinkTxInvalid, Severity::kError, "udp: %zu-byte packet too large for a datagram (%u times)",
                  length, u(txInvalid_));
        }
        return Status::kTooLarge;
    }
    ++stats_.errors;
    ++txErrors_;
    if (core::isReportableOccurrence(txErrors_)) {
        event(events::kLinkTxError, Severity::kError, "udp: send to %s:%u failed: %s (errno %d, %u times)",
              telemetryHost_, static_cast<unsigned>(telemetryPort_), errnoText(error), error, u(txErrors_));
    }
    return Status::kUnavailable;
}

}  // namespace rse::hal
