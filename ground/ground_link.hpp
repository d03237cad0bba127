// The ground end of the rover's ground link: whole CCSDS packets out (commands)
// and in (telemetry), over UDP or over ISO-TP on a SocketCAN interface (the
// Linux kernel's CAN_ISOTP sockets). Host code: errors throw LinkError with a
// message that names the link and what went wrong.
//
// UDP: commands go to HOST:PORT (default 127.0.0.1:1234); telemetry is received
// on a local port (default 1235, where rse-fsw sends it), bound on 0.0.0.0 or a
// given address. ISO-TP: normal addressing, 11-bit ids, the ground sends on
// 0x6C0 and receives on 0x6C1 (docs/icd.md section 2); frames unpadded unless
// asked (padded frames are always accepted on receive).
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "hal/can/ground_link_ids.hpp"

namespace rse::ground {

class LinkError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

constexpr std::uint16_t kDefaultCommandPort = 1234;
constexpr std::uint16_t kDefaultTelemetryPort = 1235;
constexpr std::uint32_t kGroundIsoTpTxId = hal::kGroundUplinkCanId;    // 0x6C0: the rover receives here
constexpr std::uint32_t kGroundIsoTpRxId = hal::kGroundDownlinkCanId;  // 0x6C1: the rover sends here

class GroundLink {
public:
    virtual ~GroundLink() = default;
    // Sends one packet; throws LinkError.
    virtual void send(const std::vector<std::uint8_t>& packet) = 0;
    // The next packet received within timeoutSeconds (0: only one already
    // waiting), or nullopt. Throws LinkError on a failing link.
    virtual std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) = 0;
    // "UDP 127.0.0.1:1234 (telemetry on 0.0.0.0:1235)", "ISO-TP vcan0 tx 0x6C0 rx 0x6C1"
    virtual std::string describe() const = 0;
};

// "HOST", "HOST:PORT" or ":PORT" -> host and port (defaultPort if none given).
// Throws LinkError on a bad port.
struct HostPort {
    std::string host;
    std::uint16_t port = 0;
};
HostPort parseHostPort(const std::string& text, const std::string& defaultHost, std::uint16_t defaultPort);

class UdpGroundLink final : public GroundLink {
public:
    // listen: bind the telemetry port (localAddress:localPort, 0 = ephemeral);
    // without it the socket only sends (from an ephemeral port).
    UdpGroundLink(const HostPort& remote, const HostPort& local, bool listen = true);
    ~UdpGroundLink() override;
    UdpGroundLink(const UdpGroundLink&) = delete;
    UdpGroundLink& operator=(const UdpGroundLink&) = delete;

    void send(const std::vector<std::uint8_t>& packet) override;
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override;
    std::string describe() const override;
    std::uint16_t localPort() const { return localPort_; }

private:
    int fd_ = -1;
    HostPort remote_;
    std::string localAddress_;
    std::uint16_t localPort_ = 0;
    bool listening_ = false;
    std::vector<std::uint8_t> remoteAddress_;  // a sockaddr_in
};

class IsoTpGroundLink final : public GroundLink {
public:
    IsoTpGroundLink(const std::string& interface, std::uint32_t txId = kGroundIsoTpTxId,
                    std::uint32_t rxId = kGroundIsoTpRxId, bool padFrames = false);
    ~IsoTpGroundLink() override;
    IsoTpGroundLink(const IsoTpGroundLink&) = delete;
    IsoTpGroundLink& operator=(const IsoTpGroundLink&) = delete;

    void send(const std::vector<std::uint8_t>& packet) override;
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override;
    std::string describe() const override;

private:
    int fd_ = -1;
    std::string interface_;
    std::uint32_t txId_;
    std::uint32_t rxId_;
    bool pad_;
};

}  // namespace rse::ground
