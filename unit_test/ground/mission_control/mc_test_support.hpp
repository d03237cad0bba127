// Test support for the mission control server (rse-ground serve): a scratch
// folder, telemetry packets as the flight encodes them, and minimal blocking
// HTTP and WebSocket clients (Boost.Beast) for the server on 127.0.0.1. Every
// exchange of a client gives up after kClientTimeoutS, so a server that does
// not answer fails the test instead of hanging the suite.
#pragma once

#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>
#include <vector>

#include <boost/asio/connect.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"

namespace rse::test::mc {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

constexpr int kClientTimeoutS = 10;

// A fresh folder under /tmp, removed with everything in it.
class ScratchDir {
public:
    ScratchDir() {
        char pattern[] = "/tmp/rse_mc_test_XXXXXX";
        const char* made = ::mkdtemp(pattern);
        path_ = made != nullptr ? made : "";
    }
    ~ScratchDir() {
        std::error_code ignored;
        if (!path_.empty()) {
            std::filesystem::remove_all(path_, ignored);
        }
    }
    ScratchDir(const ScratchDir&) = delete;
    ScratchDir& operator=(const ScratchDir&) = delete;
    const std::string& path() const { return path_; }
    std::string file(const std::string& name) const { return path_ + "/" + name; }
    // Writes name (folders made) with text; returns its path.
    std::string write(const std::string& name, const std::string& text) const {
        const std::string where = file(name);
        std::filesystem::create_directories(std::filesystem::path(where).parent_path());
        std::ofstream(where, std::ios::binary | std::ios::trunc) << text;
        return where;
    }

private:
    std::string path_;
};

// A packet as the flight's TelemetryOutput builds it (the flight encoder).
template <typename T>
std::vector<std::uint8_t> packetOf(const T& tlm, std::uint16_t sequence = 0, core::TimeNs met = 0) {
    std::uint8_t payload[cmdtlm::kMaxTelemetryPacket];
    core::BeWriter w(payload, sizeof payload);
    cmdtlm::encodeTelemetry(w, tlm);
    std::vector<std::uint8_t> packet(cmdtlm::kMaxTelemetryPacket);
    packet.resize(cmdtlm::buildTelemetryPacket(T::kApid, sequence, met, payload, w.size(), packet.data(),
                                               packet.size()));
    return packet;
}

// Any packet of the dictionary by its descriptor: the payload a byte pattern.
inline std::vector<std::uint8_t> patternPacket(const cmdtlm::TelemetryDesc& desc, unsigned seed) {
    std::vector<std::uint8_t> payload(desc.payloadSize);
    for (std::size_t i = 0; i < payload.size(); ++i) {
        payload[i] = static_cast<std::uint8_t>(seed * 7 + i * 13 + 1);
    }
    std::vector<std::uint8_t> packet(cmdtlm::kMaxTelemetryPacket);
    packet.resize(cmdtlm::buildTelemetryPacket(desc.apid, 0, 0, payload.data(), payload.size(), packet.data(),
                                               packet.size()));
    return packet;
}

// Runs ioc until the operation started on it sets done; throws when it has
// not within kClientTimeoutS (or ended with an error).
inline void await(net::io_context& ioc, const bool& done, const beast::error_code& ec, const std::string& what) {
    ioc.restart();
    ioc.run_for(std::chrono::seconds(kClientTimeoutS));
    if (!done) {
        throw std::runtime_error(what + ": nothing within " + std::to_string(kClientTimeoutS) + " s");
    }
    if (ec) {
        throw beast::system_error(ec, what);
    }
}

struct HttpReply {
    unsigned status = 0;
    std::string body;
    std::map<std::string, std::string> headers;
    std::string header(const std::string& name) const {
        const auto it = headers.find(name);
        return it == headers.end() ? std::string() : it->second;
    }
};

// GET target from 127.0.0.1:port on a connection of its own. The target is
// sent as given (no normalisation: "/../x" reaches the server as is).
inline HttpReply httpGet(std::uint16_t port, const std::string& target, http::verb method = http::verb::get) {
    net::io_context ioc;
    tcp::socket socket(ioc);
    socket.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
    http::request<http::empty_body> request{method, target, 11};
    request.set(http::field::host, "127.0.0.1:" + std::to_string(port));
    request.keep_alive(false);
    beast::flat_buffer buffer;
    http::response_parser<http::string_body> parser;
    parser.body_limit(64 * 1024 * 1024);
    bool done = false;
    beast::error_code ec;
    http::async_write(socket, request, [&](beast::error_code e, std::size_t) {
        if (e) {
            ec = e;
            done = true;
            return;
        }
        http::async_read(socket, buffer, parser, [&](beast::error_code r, std::size_t) {
            ec = r;
            done = true;
        });
    });
    await(ioc, done, ec, "GET " + target);
    const http::response<http::string_body>& response = parser.get();
    HttpReply reply;
    reply.status = static_cast<unsigned>(response.result_int());
    reply.body = response.body();
    for (const auto& field : response) {
        reply.headers[std::string(field.name_string())] = std::string(field.value());
    }
    beast::error_code ignored;
    socket.shutdown(tcp::socket::shutdown_both, ignored);
    return reply;
}

// A WebSocket client of /realtime.
class RealtimeClient {
public:
    // receiveBuffer > 0: the socket's receive buffer (SO_RCVBUF) that small,
    // for a client that reads slowly.
    explicit RealtimeClient(std::uint16_t port, int receiveBuffer = 0) : ws_(ioc_) {
        tcp::socket& socket = ws_.next_layer();
        socket.open(tcp::v4());
        if (receiveBuffer > 0) {
            socket.set_option(net::socket_base::receive_buffer_size(receiveBuffer));
        }
        socket.connect(tcp::endpoint(net::ip::make_address("127.0.0.1"), port));
        bool done = false;
        beast::error_code ec;
        ws_.async_handshake("127.0.0.1:" + std::to_string(port), "/realtime", [&](beast::error_code e) {
            ec = e;
            done = true;
        });
        await(ioc_, done, ec, "WebSocket handshake");
    }
    ~RealtimeClient() {
        beast::error_code ignored;
        ws_.next_layer().shutdown(tcp::socket::shutdown_both, ignored);
        ws_.next_layer().close(ignored);
    }
    void send(const std::string& text) { write(text, true); }
    void sendBinary(const std::string& bytes) { write(bytes, false); }
    // The next message (throws after kClientTimeoutS or on a closed connection).
    std::string receive() {
        beast::flat_buffer buffer;
        bool done = false;
        beast::error_code ec;
        ws_.async_read(buffer, [&](beast::error_code e, std::size_t) {
            ec = e;
            done = true;
        });
        await(ioc_, done, ec, "WebSocket read");
        return beast::buffers_to_string(buffer.data());
    }

private:
    void write(const std::string& data, bool text) {
        ws_.text(text);
        bool done = false;
        beast::error_code ec;
        ws_.async_write(net::buffer(data), [&](beast::error_code e, std::size_t) {
            ec = e;
            done = true;
        });
        await(ioc_, done, ec, "WebSocket write");
    }

    net::io_context ioc_;
    websocket::stream<tcp::socket> ws_;
};

}  // namespace rse::test::mc
