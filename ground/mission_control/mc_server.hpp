// The mission control server of `rse-ground serve` (docs/mission_control.md):
// every telemetry packet fed to it is decoded by the flight dictionary
// (ground/telemetry_decoder.hpp), archived (telemetry_archive.hpp) and pushed
// to the WebSocket clients subscribed to its packet; HTTP serves the display's
// files, the display dictionary, the archive's history, the site map and the
// server's status.
//
// Threads: HTTP and WebSocket run on an Asio io_context in a thread of the
// server's own (start()); onPacket() is called by the link reader on its
// thread. onPacket never waits for a client: it archives the packet and
// posts its datum to the server's thread, which queues it for each subscribed
// client. A client's queue is bounded (clientQueueLimit): when a client reads
// too slowly the oldest datum waiting for it is dropped and counted
// (realtime_dropped in /api/status), so a slow client costs the others and
// the link nothing.
//
// Host code (ground/): full C++17, Boost.Beast (header-only), SQLite.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "ground/mission_control/site_map.hpp"

namespace rse::ground::mission_control {

// The port cannot be bound, or the address is not one.
class ServerError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

constexpr std::uint16_t kDefaultHttpPort = 8090;
constexpr std::size_t kDefaultClientQueueLimit = 256;
constexpr std::size_t kHistoryLimit = 20000;

struct ServerOptions {
    std::string httpAddress = "127.0.0.1";  // IPv4 or IPv6 literal
    std::uint16_t httpPort = kDefaultHttpPort;  // 0: any free port (httpPort() says which)
    std::string archivePath = "build/mission_control/archive.sqlite";
    std::string webRoot = "ground/mission_control/web";
    std::string tablesDir = "tables";
    std::string link;  // the link's description, for /api/status
    std::size_t clientQueueLimit = kDefaultClientQueueLimit;  // datums waiting per client, at least 1
    std::size_t historyLimit = kHistoryLimit;                 // datums per /api/history answer
};

// What /api/status reports.
struct ServerCounters {
    std::uint64_t packetsReceived = 0;  // packets fed to onPacket
    std::uint64_t packetsArchived = 0;  // of them, written to the archive
    std::uint64_t decodeErrors = 0;     // of them, not decoded (archived as UNDECODED)
    std::uint64_t archiveErrors = 0;    // of them, not archived (SQLite failed)
    std::uint64_t realtimeDropped = 0;  // datums dropped from slow clients' queues
    std::uint64_t clients = 0;          // WebSocket clients connected now
};

struct MissionControlState;  // mc_server.cpp: the io_context, the connections, the archive

class MissionControl {
public:
    // Opens the archive (ArchiveError), reads the site map (a map that cannot
    // be read is reported by siteMap() and /api/map, it does not stop the
    // server) and binds the HTTP port (ServerError). Nothing is served before start().
    explicit MissionControl(const ServerOptions& options);
    // stop(), then the archive is closed.
    ~MissionControl();
    MissionControl(const MissionControl&) = delete;
    MissionControl& operator=(const MissionControl&) = delete;

    // Serves from a thread of its own until stop().
    void start();
    // Closes the listening socket and every connection (WebSocket clients get
    // a close frame), then joins the server's thread. Idempotent.
    void stop();

    // The port bound (the one asked for, or the one picked for port 0).
    std::uint16_t httpPort() const;
    const SiteMap& siteMap() const;

    // One packet as received from the link at utcMs (ms since 1970): decoded,
    // archived, pushed to its subscribers. Thread-safe; never waits for a client.
    void onPacket(const std::vector<std::uint8_t>& bytes, std::int64_t utcMs);

    ServerCounters counters() const;
    // The last archive failure ("" none): what archiveErrors counted.
    std::string lastArchiveError() const;

private:
    std::unique_ptr<MissionControlState> impl_;
};

// This machine's UTC now, ms since 1970 (the datum's utc).
std::int64_t utcNowMs();

}  // namespace rse::ground::mission_control
