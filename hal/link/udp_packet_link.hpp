// The ground link over UDP/IPv4, the way cFS's lab applications do it: commands
// arrive as datagrams on a port the rover binds (CI_LAB listens on 1234) and
// telemetry leaves as datagrams to the ground's port (TO_LAB sends to 1235). One
// CCSDS packet per datagram, both ways; datagrams from any sender are accepted
// (command authentication is command ingest's job, not the transport's).
//
// Never blocks and never stops the rover: the socket is non-blocking and every
// call is MSG_DONTWAIT. Behaviour chosen where UDP leaves room:
//   - receive() hands over one datagram per call, in arrival order. The link reads
//     them from the kernel kUdpRxBatch at a time (one recvmmsg()), so a flood costs
//     one system call per batch, not per packet; datagrams read but not yet handed
//     over wait in the link (a close() counts them in rxDropped). A datagram longer
//     than the caller's buffer or than kUdpMaxDatagram is detected with MSG_TRUNC,
//     dropped whole (never passed on cut short), counted in rxDropped and evented
//     (kLinkRxTooLarge). An empty datagram is passed on as a packet of length 0,
//     for command ingest to refuse and count.
//   - Datagrams the kernel drops because the receive buffer is full are counted:
//     the socket asks for SO_RXQ_OVFL, so each datagram read carries the socket's
//     drop count when it was queued, and the increase is added to rxKernelDropped
//     and evented (kLinkRxKernelDrops, on the 1st, 2nd, 4th ... batch that shows new
//     drops). Drops after the last datagram read show with the next one read. The
//     receive buffer is sized at open() (kUdpReceiveBufferBytes, SO_RCVBUFFORCE when
//     permitted, else SO_RCVBUF up to net.core.rmem_max); a smaller grant, or a
//     kernel that refuses SO_RXQ_OVFL, is evented (kLinkRxDegraded) and the link
//     still opens.
//   - send() is one sendto(). A full socket buffer (EAGAIN, ENOBUFS) is kFull; any
//     other OS error is kUnavailable and counted in errors. Either way the packet
//     is counted in txDropped and the next send() tries again.
//   - A ground that is not listening answers with ICMP "port unreachable". The
//     socket asks for those reports (IP_RECVERR) so the operator learns that
//     telemetry goes nowhere: each report is counted in errors and evented
//     (kLinkTxUndeliverable); the packets still count as sent (txPackets), since
//     they left. service() drains the reports every minor frame; left there they
//     would take the receive buffer that commands need. Linux also hands a report
//     once to the next sendto() or recv() as its errno, without sending or reading
//     anything: the report is then drained and counted the same way and the call
//     made again, once, so its result is about this packet (and a link whose
//     owner never calls service() still keeps its receive buffer free).
//   - Only numeric IPv4 addresses (inet_pton), no name lookup: resolving a name
//     can block for seconds.
// Events (hal/link/link_events.hpp): open, close and redirection every time;
// conditions that repeat per packet on their 1st, 2nd, 4th ... occurrence.
#pragma once

#include <sys/socket.h>
#include <sys/uio.h>

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/core/status.hpp"
#include "hal/link/packet_link.hpp"

namespace rse::hal {

// cFS convention (CI_LAB / TO_LAB, the lab command ingest and telemetry output
// apps): commands to the flight on UDP 1234, telemetry to the ground on UDP 1235.
// Ground tools written for cFS talk to the rover without configuration.
constexpr std::uint16_t kDefaultCommandPort = 1234;
constexpr std::uint16_t kDefaultTelemetryPort = 1235;
// Error-queue reports handled per service() (or per failed call); more wait for
// the next frame.
constexpr std::size_t kUdpMaxReportsPerCall = 16;
constexpr std::size_t kIpv4TextSize = 16;  // "255.255.255.255" and its NUL (INET_ADDRSTRLEN)
// Receive buffer asked for at open(). The kernel charges a small datagram on
// loopback about 1 KB of it, so 4 MiB (8 MiB of accounting once the kernel
// doubles it) holds tens of milliseconds of a 100 000 packet/s flood: a frame
// that starts late loses nothing. docs/icd.md, "Floods".
constexpr int kUdpReceiveBufferBytes = 4 * 1024 * 1024;
constexpr std::size_t kUdpRxBatch = 32;        // datagrams read per recvmmsg()
constexpr std::size_t kUdpMaxDatagram = 512;   // longest datagram received (kMaxTelemetryPacket; commands are <= 256)

class UdpPacketLink final : public PacketLink {
public:
    // Without an event log (rse-fsw reserves the link before the application that
    // owns the log exists): events are dropped until attachEvents(); counters,
    // statuses and lastErrno() work regardless.
    UdpPacketLink() = default;
    explicit UdpPacketLink(core::EventLog& events) : events_(&events) {}
    ~UdpPacketLink();  // closes the socket, without an event (the log may be gone)
    UdpPacketLink(const UdpPacketLink&) = delete;
    UdpPacketLink& operator=(const UdpPacketLink&) = delete;

    void attachEvents(core::EventLog& events) { events_ = &events; }
    // The receive buffer the next open() asks for (default kUdpReceiveBufferBytes;
    // tests ask for a small one to overfill it).
    void setReceiveBufferRequest(int bytes) { receiveBufferRequest_ = bytes; }

    // Binds a non-blocking UDP socket to bindAddress:commandPort ("0.0.0.0" for
    // every interface; port 0 lets the kernel choose, see boundPort()) and sends
    // telemetry to groundHost:telemetryPort. A link already open is closed first.
    // kInvalidArgument: an address that is not numeric IPv4, or telemetryPort 0
    // (lastErrno() EINVAL, event kLinkBadAddress). kUnavailable: the socket could
    // not be made or bound, e.g. the port is in use (lastErrno() EADDRINUSE, event
    // kLinkOpenFailed). Either way the link stays closed.
    core::Status open(const char* bindAddress, std::uint16_t commandPort, const char* groundHost,
                      std::uint16_t telemetryPort);
    // Points telemetry elsewhere (open or not; open() sets it too). kInvalidArgument
    // for a bad address or port 0: evented, the previous destination is kept.
    core::Status setTelemetryDestination(const char* groundHost, std::uint16_t telemetryPort);
    // Closes the socket (evented when it was open). receive()/send() then return kUnavailable.
    void close();

    bool isOpen() const { return fd_ >= 0; }
    std::uint16_t boundPort() const { return boundPort_; }  // the command port actually bound; 0 when closed
    const char* telemetryHost() const { return telemetryHost_; }
    std::uint16_t telemetryPort() const { return telemetryPort_; }
    int lastErrno() const { return lastErrno_; }  // of the last OS call that failed (or EINVAL, bad address)
    std::uint32_t undeliverableReports() const { return undeliverable_; }  // ICMP reports, also in errors
    // The receive buffer the kernel granted (SO_RCVBUF as read back: twice the
    // bytes of datagrams it holds, the kernel's bookkeeping); 0 when closed.
    int receiveBufferBytes() const { return receiveBufferBytes_; }
    // Whether kernel drops are counted (SO_RXQ_OVFL granted at open()).
    bool kernelDropsCounted() const { return kernelDropsCounted_; }

    // The next datagram: kOk, kEmpty, kTooLarge (longer than capacity or than
    // kUdpMaxDatagram: dropped and counted; *length says how long it was), kUnavailable (closed, or an OS error:
    // counted and evented), kInvalidArgument (null length, or null out with capacity > 0).
    core::Status receive(std::uint8_t* out, std::size_t capacity, std::size_t* length) override;
    // One datagram to the telemetry destination (a second sendto() only after an
    // undeliverable report, see above): kOk, kFull (socket buffer full), kTooLarge
    // (EMSGSIZE), kInvalidArgument (empty or null), kUnavailable (closed, or an OS
    // error such as no route: counted in errors, evented). Every refusal counts in txDropped.
    core::Status send(const std::uint8_t* data, std::size_t length) override;
    // Every minor frame: drains the socket's error queue (undeliverable reports).
    void service() override;
    const char* name() const override { return "udp"; }
    const PacketLinkStats& stats() const override { return stats_; }

private:
    std::size_t drainErrorReports();
    core::Status readBatch();
    void countKernelDrops(msghdr& message);
    void configureReceive(int fd);
    void closeSocket();
    void event(core::EventId id, core::Severity severity, const char* format, ...)
        __attribute__((format(printf, 4, 5)));

    core::EventLog* events_ = nullptr;
    int fd_ = -1;
    int lastErrno_ = 0;
    std::uint16_t boundPort_ = 0;
    char bindHost_[kIpv4TextSize] = {};
    std::uint32_t telemetryAddress_ = 0;  // network byte order
    std::uint16_t telemetryPort_ = 0;
    char telemetryHost_[kIpv4TextSize] = {};
    PacketLinkStats stats_;
    // Occurrences per reason, for the 1, 2, 4, 8 ... event throttle.
    std::uint32_t rxTooLarge_ = 0;
    std::uint32_t rxErrors_ = 0;
    std::uint32_t txFull_ = 0;
    std::uint32_t txErrors_ = 0;
    std::uint32_t txInvalid_ = 0;
    std::uint32_t undeliverable_ = 0;
    std::uint32_t kernelDropBatches_ = 0;  // batches that showed new kernel drops (event throttle)
    // Receive side: the buffer asked for and granted, the socket's cumulative drop
    // count as last seen (SO_RXQ_OVFL), and the batch read by the last recvmmsg().
    int receiveBufferRequest_ = kUdpReceiveBufferBytes;
    int receiveBufferBytes_ = 0;
    bool kernelDropsCounted_ = false;
    std::uint32_t kernelDropsSeen_ = 0;
    std::size_t rxNext_ = 0;   // next datagram of the batch to hand over
    std::size_t rxCount_ = 0;  // datagrams in the batch
    mmsghdr rxMessages_[kUdpRxBatch] = {};
    iovec rxVectors_[kUdpRxBatch] = {};
    alignas(cmsghdr) unsigned char rxControl_[kUdpRxBatch][CMSG_SPACE(sizeof(std::uint32_t))] = {};
    std::uint8_t rxData_[kUdpRxBatch][kUdpMaxDatagram] = {};
};

}  // namespace rse::hal
