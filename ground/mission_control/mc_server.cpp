#include "ground/mission_control/mc_server.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <deque>
#include <filesystem>
#include <future>
#include <limits>
#include <mutex>
#include <optional>
#include <set>
#include <thread>
#include <utility>

#include <boost/asio/executor_work_guard.hpp>
#include <boost/asio/io_context.hpp>
#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/post.hpp>
#include <boost/beast/core.hpp>
#include <boost/beast/http.hpp>
#include <boost/beast/websocket.hpp>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/mission_control/http_request.hpp"
#include "ground/mission_control/openmct_dictionary.hpp"
#include "ground/mission_control/telemetry_archive.hpp"
#include "ground/mission_control/telemetry_datum.hpp"
#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground::mission_control {

namespace beast = boost::beast;
namespace http = beast::http;
namespace websocket = beast::websocket;
namespace net = boost::asio;
using tcp = net::ip::tcp;

namespace {

constexpr const char* kServerName = "rse-ground serve";
constexpr const char* kRealtimePath = "/realtime";
constexpr const char* kTruncatedHeader = "X-RSE-Truncated";
// A request (headers and body) beyond this is refused: every request the
// display makes is a GET of a few hundred bytes.
constexpr std::uint64_t kMaxRequestBytes = 64 * 1024;
// A WebSocket message from a client: {"subscribe": "NAME"} is a few dozen bytes.
constexpr std::size_t kMaxClientMessageBytes = 4096;
// An idle HTTP connection is closed after this.
constexpr std::chrono::seconds kHttpIdle{60};
// A WebSocket client that answers no ping within this is dropped (pinged at half of it).
constexpr std::chrono::seconds kWebSocketIdle{30};
// stop(): how long the connections get to close before the thread is stopped.
constexpr std::chrono::seconds kStopGrace{2};

std::string jsonError(const std::string& message) { return jsonText(Json{{"error", message}}); }

// "1700000000000" or "1.7e12" -> ms; nullopt unless a finite number.
std::optional<double> parseMs(const std::string& text) {
    double value = 0.0;
    if (!parseDouble(text, &value) || !std::isfinite(value)) {
        return std::nullopt;
    }
    return value;
}

std::int64_t clampToInt64(double value) {
    // 2^63 is exactly representable; anything at or beyond it is clamped.
    constexpr double kLimit = 9223372036854775808.0;
    if (value >= kLimit) {
        return std::numeric_limits<std::int64_t>::max();
    }
    if (value <= -kLimit) {
        return std::numeric_limits<std::int64_t>::min();
    }
    return static_cast<std::int64_t>(value);
}

}  // namespace

class HttpSession;
class RealtimeSession;

struct MissionControlState {
    explicit MissionControlState(const ServerOptions& o)
        : options(o),
          archive(o.archivePath),
          siteMap(loadSiteMap(o.tablesDir)),
          dictionaryText(jsonText(displayDictionary())),
          acceptor(ioc) {}

    void listen();
    void accept();
    void broadcast(const std::string& packet, const std::shared_ptr<const std::string>& message);
    void closeAll();
    void handle(HttpSession& session, http::request<http::string_body>&& request);
    std::string statusJson() const;
    std::string historyAnswer(const RequestTarget& target, http::status* status, bool* truncated) const;

    ServerOptions options;
    TelemetryArchive archive;
    SiteMap siteMap;
    std::string dictionaryText;

    std::atomic<std::uint64_t> received{0};
    std::atomic<std::uint64_t> archived{0};
    std::atomic<std::uint64_t> decodeErrors{0};
    std::atomic<std::uint64_t> archiveErrors{0};
    std::atomic<std::uint64_t> dropped{0};
    std::atomic<std::uint64_t> clients{0};
    mutable std::mutex archiveErrorMutex;
    std::string lastArchiveError;

    // The connections, on the server's thread only (each removes itself when
    // it ends); declared before the io_context so that they outlive it: its
    // destructor ends the sessions its handlers still hold.
    std::set<HttpSession*> httpSessions;
    std::set<RealtimeSession*> realtimeSessions;

    net::io_context ioc{1};
    tcp::acceptor acceptor;
    std::optional<net::executor_work_guard<net::io_context::executor_type>> work;
    std::thread thread;
    std::future<void> finished;
    std::atomic<bool> stopped{false};
};

// ---- WebSocket /realtime ---------------------------------------------------------
class RealtimeSession : public std::enable_shared_from_this<RealtimeSession> {
public:
    RealtimeSession(tcp::socket&& socket, MissionControlState& server) : ws_(std::move(socket)), server_(server) {}
    ~RealtimeSession() {
        if (registered_) {
            server_.realtimeSessions.erase(this);
            server_.clients.fetch_sub(1);
        }
    }

    void run(http::request<http::string_body>&& request) {
        // Pings keep a quiet connection (no subscribed packet for a while) open
        // and find a client that went away without closing.
        websocket::stream_base::timeout timeouts = websocket::stream_base::timeout::suggested(beast::role_type::server);
        timeouts.idle_timeout = kWebSocketIdle;
        timeouts.keep_alive_pings = true;
        ws_.set_option(timeouts);
        ws_.set_option(websocket::stream_base::decorator(
            [](websocket::response_type& response) { response.set(http::field::server, kServerName); }));
        ws_.read_message_max(kMaxClientMessageBytes);
        ws_.async_accept(request, [self = shared_from_this()](beast::error_code ec) { self->onAccept(ec); });
    }

    bool subscribed(const std::string& packet) const { return subscriptions_.count(packet) != 0; }

    // Queues a message; when more than the limit wait, the oldest waiting
    // (not the one being written) is dropped and counted.
    void send(const std::shared_ptr<const std::string>& message) {
        if (closing_) {
            return;
        }
        const std::size_t inFlight = writing_ ? 1 : 0;
        if (queue_.size() - inFlight >= server_.options.clientQueueLimit) {
            if (queue_.size() > inFlight) {
                queue_.erase(queue_.begin() + static_cast<std::ptrdiff_t>(inFlight));
            }
            server_.dropped.fetch_add(1);
        }
        queue_.push_back(message);
        if (!writing_) {
            write();
        }
    }

    void close() {
        if (closing_) {
            return;
        }
        closing_ = true;
        ws_.async_close(websocket::close_code::going_away, [self = shared_from_this()](beast::error_code) {});
    }

private:
    void onAccept(beast::error_code ec) {
        if (ec) {
            return;
        }
        registered_ = true;
        server_.realtimeSessions.insert(this);
        server_.clients.fetch_add(1);
        read();
    }

    void read() {
        ws_.async_read(buffer_, [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
    }

    void onRead(beast::error_code ec) {
        if (ec) {
            return;  // closed, timed out or a protocol error: the session ends
        }
        const std::string text = beast::buffers_to_string(buffer_.data());
        buffer_.consume(buffer_.size());
        if (!ws_.got_text()) {
            reply("expected a text message: {\"subscribe\": \"NAME\"} or {\"unsubscribe\": \"NAME\"}");
        } else {
            handleMessage(text);
        }
        read();
    }

    // {"subscribe": "NAME"} / {"unsubscribe": "NAME"}; anything else gets
    // {"error": "..."} back and the connection stays.
    void handleMessage(const std::string& text) {
        const Json message = Json::parse(text, nullptr, false);
        if (message.is_discarded()) {
            reply("not JSON: expected {\"subscribe\": \"NAME\"} or {\"unsubscribe\": \"NAME\"}");
            return;
        }
        if (!message.is_object() || message.size() != 1 ||
            (!message.contains("subscribe") && !message.contains("unsubscribe"))) {
            reply("expected {\"subscribe\": \"NAME\"} or {\"unsubscribe\": \"NAME\"}, got " + jsonText(message));
            return;
        }
        const bool subscribe = message.contains("subscribe");
        const Json& name = message.begin().value();
        if (!name.is_string()) {
            reply(std::string(subscribe ? "subscribe" : "unsubscribe") + " takes a packet name (a string), got " +
                  jsonText(name));
            return;
        }
        const std::string packet = name.get<std::string>();
        if (cmdtlm::findTelemetry(packet.c_str()) == nullptr) {
            reply("unknown packet '" + packet + "' (GET /api/dictionary lists them)");
            return;
        }
        if (subscribe) {
            subscriptions_.insert(packet);
        } else {
            subscriptions_.erase(packet);
        }
    }

    void reply(const std::string& error) { send(std::make_shared<const std::string>(jsonError(error))); }

    void write() {
        writing_ = true;
        ws_.text(true);
        ws_.async_write(net::buffer(*queue_.front()),
                        [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onWrite(ec); });
    }

    void onWrite(beast::error_code ec) {
        writing_ = false;
        queue_.pop_front();
        if (ec || closing_) {
            return;
        }
        if (!queue_.empty()) {
            write();
        }
    }

    websocket::stream<beast::tcp_stream> ws_;
    MissionControlState& server_;
    beast::flat_buffer buffer_;
    std::deque<std::shared_ptr<const std::string>> queue_;  // front: being written while writing_
    std::set<std::string> subscriptions_;
    bool writing_ = false;
    bool registered_ = false;
    bool closing_ = false;
};

// ---- HTTP ------------------------------------------------------------------------
class HttpSession : public std::enable_shared_from_this<HttpSession> {
public:
    HttpSession(tcp::socket&& socket, MissionControlState& server) : stream_(std::move(socket)), server_(server) {}
    ~HttpSession() { server_.httpSessions.erase(this); }

    void run() {
        server_.httpSessions.insert(this);
        read();
    }

    void close() {
        beast::error_code ignored;
        stream_.socket().shutdown(tcp::socket::shutdown_both, ignored);
        stream_.cancel();
    }

    template <typename Body>
    void respond(http::response<Body>&& response) {
        auto message = std::make_shared<http::response<Body>>(std::move(response));
        message->set(http::field::server, kServerName);
        message->prepare_payload();
        http::async_write(stream_, *message,
                          [self = shared_from_this(), message](beast::error_code ec, std::size_t) {
                              self->onWrite(ec, message->keep_alive());
                          });
    }

    // Hands the connection to a WebSocket session (GET /realtime with Upgrade).
    void upgrade(http::request<http::string_body>&& request) {
        server_.httpSessions.erase(this);
        std::make_shared<RealtimeSession>(stream_.release_socket(), server_)->run(std::move(request));
    }

private:
    void read() {
        parser_.emplace();
        parser_->header_limit(static_cast<std::uint32_t>(kMaxRequestBytes));
        parser_->body_limit(kMaxRequestBytes);
        stream_.expires_after(kHttpIdle);
        http::async_read(stream_, buffer_, *parser_,
                         [self = shared_from_this()](beast::error_code ec, std::size_t) { self->onRead(ec); });
    }

    void onRead(beast::error_code ec) {
        if (ec == http::error::end_of_stream) {
            beast::error_code ignored;
            stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
            return;
        }
        if (ec) {
            return;
        }
        server_.handle(*this, parser_->release());
    }

    void onWrite(beast::error_code ec, bool keepAlive) {
        if (ec) {
            return;
        }
        if (!keepAlive) {
            beast::error_code ignored;
            stream_.socket().shutdown(tcp::socket::shutdown_send, ignored);
            return;
        }
        read();
    }

    beast::tcp_stream stream_;
    MissionControlState& server_;
    beast::flat_buffer buffer_;
    std::optional<http::request_parser<http::string_body>> parser_;
};

namespace {

http::response<http::string_body> textResponse(const http::request<http::string_body>& request, http::status status,
                                               const char* type, std::string body) {
    http::response<http::string_body> response{status, request.version()};
    response.set(http::field::content_type, type);
    response.set(http::field::cache_control, "no-cache");
    response.keep_alive(request.keep_alive());
    response.body() = std::move(body);
    return response;
}

http::response<http::string_body> jsonResponse(const http::request<http::string_body>& request, http::status status,
                                               std::string body) {
    return textResponse(request, status, "application/json", std::move(body));
}

http::response<http::string_body> errorResponse(const http::request<http::string_body>& request, http::status status,
                                                const std::string& message) {
    return jsonResponse(request, status, jsonError(message));
}

}  // namespace

// ---- The server ------------------------------------------------------------------
void MissionControlState::listen() {
    beast::error_code ec;
    const net::ip::address address = net::ip::make_address(options.httpAddress, ec);
    const std::string where = options.httpAddress + ":" + std::to_string(options.httpPort);
    if (ec) {
        throw ServerError("--http " + where + ": '" + options.httpAddress + "' is not an IP address");
    }
    const tcp::endpoint endpoint(address, options.httpPort);
    acceptor.open(endpoint.protocol(), ec);
    if (!ec) {
        acceptor.set_option(net::socket_base::reuse_address(true), ec);
    }
    if (!ec) {
        acceptor.bind(endpoint, ec);
    }
    if (!ec) {
        acceptor.listen(net::socket_base::max_listen_connections, ec);
    }
    if (ec) {
        throw ServerError("cannot serve HTTP on " + where + ": " + ec.message() +
                          (ec == net::error::address_in_use ? " (another rse-ground serve? give --http PORT)" : ""));
    }
}

void MissionControlState::accept() {
    acceptor.async_accept(ioc, [this](beast::error_code ec, tcp::socket socket) {
        if (ec == net::error::operation_aborted || !acceptor.is_open()) {
            return;
        }
        if (!ec) {
            std::make_shared<HttpSession>(std::move(socket), *this)->run();
        }
        accept();
    });
}

void MissionControlState::broadcast(const std::string& packet, const std::shared_ptr<const std::string>& message) {
    // A copy of the set: a send may end a session (it then leaves the set).
    for (RealtimeSession* session : std::vector<RealtimeSession*>(realtimeSessions.begin(), realtimeSessions.end())) {
        if (session->subscribed(packet)) {
            session->send(message);
        }
    }
}

void MissionControlState::closeAll() {
    beast::error_code ignored;
    acceptor.close(ignored);
    for (RealtimeSession* session : std::vector<RealtimeSession*>(realtimeSessions.begin(), realtimeSessions.end())) {
        session->close();
    }
    for (HttpSession* session : std::vector<HttpSession*>(httpSessions.begin(), httpSessions.end())) {
        session->close();
    }
}

std::string MissionControlState::statusJson() const {
    std::string archiveError;
    {
        std::lock_guard<std::mutex> lock(archiveErrorMutex);
        archiveError = lastArchiveError;
    }
    Json status = {{"packets_received", received.load()},
                   {"packets_archived", archived.load()},
                   {"decode_errors", decodeErrors.load()},
                   {"clients", clients.load()},
                   {"archive", options.archivePath},
                   {"link", options.link},
                   {"archive_errors", archiveErrors.load()},
                   {"realtime_dropped", dropped.load()}};
    if (!archiveError.empty()) {
        status["archive_error"] = archiveError;
    }
    return jsonText(status);
}

// GET /api/history?packet=NAME&start=MS&end=MS: the body, or a JSON error with *status.
std::string MissionControlState::historyAnswer(const RequestTarget& target, http::status* status,
                                                bool* truncated) const {
    *status = http::status::bad_request;
    const auto packet = target.query.find("packet");
    if (packet == target.query.end() || packet->second.empty()) {
        return jsonError("history needs packet=NAME (and start=MS, end=MS)");
    }
    std::optional<double> bounds[2];  // start, end as given
    const char* const names[2] = {"start", "end"};
    for (std::size_t i = 0; i < 2; ++i) {
        const auto given = target.query.find(names[i]);
        if (given == target.query.end()) {
            continue;
        }
        bounds[i] = parseMs(given->second);
        if (!bounds[i]) {
            return jsonError(std::string(names[i]) + "='" + given->second + "': expected a time in ms since 1970");
        }
    }
    if (bounds[0] && bounds[1] && *bounds[0] > *bounds[1]) {
        return jsonError("start is after end");
    }
    // start <= utc <= end on whole ms; a bound not given is open.
    const std::int64_t startMs =
        bounds[0] ? clampToInt64(std::ceil(*bounds[0])) : std::numeric_limits<std::int64_t>::min();
    const std::int64_t endMs = bounds[1] ? clampToInt64(std::floor(*bounds[1])) : std::numeric_limits<std::int64_t>::max();
    if (cmdtlm::findTelemetry(packet->second.c_str()) == nullptr) {
        *status = http::status::not_found;
        return jsonError("unknown packet '" + packet->second + "' (GET /api/dictionary lists them)");
    }
    HistoryResult result;
    try {
        result = archive.history(packet->second, startMs, endMs, options.historyLimit);
    } catch (const ArchiveError& e) {
        *status = http::status::internal_server_error;
        return jsonError(e.what());
    }
    *status = http::status::ok;
    *truncated = result.truncated;
    std::string body = "[";
    for (std::size_t i = 0; i < result.datums.size(); ++i) {
        if (i > 0) {
            body += ',';
        }
        body += result.datums[i];
    }
    body += ']';
    return body;
}

void MissionControlState::handle(HttpSession& session, http::request<http::string_body>&& request) {
    std::string error;
    const std::optional<RequestTarget> target = parseTarget(std::string(request.target()), &error);
    if (!target) {
        session.respond(errorResponse(request, http::status::bad_request, error));
        return;
    }
    if (target->path == kRealtimePath) {
        if (websocket::is_upgrade(request)) {
            session.upgrade(std::move(request));
            return;
        }
        auto response = errorResponse(request, http::status::upgrade_required, "/realtime is a WebSocket");
        response.set(http::field::upgrade, "websocket");
        session.respond(std::move(response));
        return;
    }
    if (request.method() != http::verb::get) {
        auto response = errorResponse(request, http::status::method_not_allowed, "only GET is served");
        response.set(http::field::allow, "GET");
        session.respond(std::move(response));
        return;
    }
    const std::string& path = target->path;
    if (path == "/api/dictionary") {
        session.respond(jsonResponse(request, http::status::ok, dictionaryText));
        return;
    }
    if (path == "/api/history") {
        http::status status = http::status::ok;
        bool truncated = false;
        std::string body = historyAnswer(*target, &status, &truncated);
        auto response = jsonResponse(request, status, std::move(body));
        if (truncated) {
            response.set(kTruncatedHeader, "true");
        }
        session.respond(std::move(response));
        return;
    }
    if (path == "/api/map") {
        if (siteMap.json) {
            session.respond(jsonResponse(request, http::status::ok, jsonText(*siteMap.json)));
        } else {
            session.respond(errorResponse(request, http::status::not_found, "no site map: " + siteMap.error));
        }
        return;
    }
    if (path == "/api/status") {
        session.respond(jsonResponse(request, http::status::ok, statusJson()));
        return;
    }
    if (path.compare(0, 5, "/api/") == 0 || path == "/api") {
        session.respond(errorResponse(request, http::status::not_found,
                                      "no API " + path + " (dictionary, history, map, status)"));
        return;
    }
    const std::optional<std::string> file = staticFilePath(options.webRoot, path, &error);
    if (!file) {
        session.respond(errorResponse(request, http::status::bad_request, error));
        return;
    }
    std::error_code fsError;
    if (!std::filesystem::is_regular_file(*file, fsError)) {
        session.respond(errorResponse(request, http::status::not_found, "no file " + path));
        return;
    }
    http::file_body::value_type body;
    beast::error_code ec;
    body.open(file->c_str(), beast::file_mode::scan, ec);
    if (ec) {
        session.respond(errorResponse(request, http::status::forbidden, "cannot read " + path + ": " + ec.message()));
        return;
    }
    http::response<http::file_body> response{std::piecewise_construct, std::make_tuple(std::move(body)),
                                             std::make_tuple(http::status::ok, request.version())};
    response.set(http::field::content_type, contentType(*file));
    response.set(http::field::cache_control, "no-cache");
    response.keep_alive(request.keep_alive());
    session.respond(std::move(response));
}

// ---- MissionControl --------------------------------------------------------------
MissionControl::MissionControl(const ServerOptions& options) {
    if (options.clientQueueLimit == 0) {
        throw ServerError("the client queue limit must be at least 1");
    }
    impl_ = std::make_unique<MissionControlState>(options);
    impl_->listen();
}

MissionControl::~MissionControl() { stop(); }

void MissionControl::start() {
    if (impl_->thread.joinable() || impl_->stopped) {
        return;
    }
    impl_->work.emplace(impl_->ioc.get_executor());
    impl_->accept();
    std::promise<void> finished;
    impl_->finished = finished.get_future();
    impl_->thread = std::thread([this, done = std::move(finished)]() mutable {
        impl_->ioc.run();
        done.set_value();
    });
}

void MissionControl::stop() {
    if (impl_ == nullptr || impl_->stopped) {
        return;
    }
    impl_->stopped = true;
    if (!impl_->thread.joinable()) {
        return;
    }
    net::post(impl_->ioc, [impl = impl_.get()] { impl->closeAll(); });
    impl_->work.reset();
    // Normally every connection has closed well before the grace; a client that
    // does not answer its close is cut off.
    if (impl_->finished.wait_for(kStopGrace) != std::future_status::ready) {
        impl_->ioc.stop();
    }
    impl_->thread.join();
}

std::uint16_t MissionControl::httpPort() const {
    beast::error_code ec;
    const tcp::endpoint endpoint = impl_->acceptor.local_endpoint(ec);
    return ec ? impl_->options.httpPort : endpoint.port();
}

const SiteMap& MissionControl::siteMap() const { return impl_->siteMap; }

void MissionControl::onPacket(const std::vector<std::uint8_t>& bytes, std::int64_t utcMs) {
    impl_->received.fetch_add(1);
    const DecodedPacket packet = decodeTelemetry(bytes);
    std::optional<std::string> datum;
    std::string name = kUndecodedPacket;
    if (packet.ok) {
        name = packet.name();
        datum = jsonText(datumFromPacket(packet, utcMs));
    } else {
        impl_->decodeErrors.fetch_add(1);
    }
    try {
        impl_->archive.append(utcMs, name, datum, bytes);
        impl_->archived.fetch_add(1);
    } catch (const ArchiveError& e) {
        impl_->archiveErrors.fetch_add(1);
        std::lock_guard<std::mutex> lock(impl_->archiveErrorMutex);
        impl_->lastArchiveError = e.what();
    }
    if (!datum || impl_->stopped) {
        return;
    }
    auto message = std::make_shared<const std::string>("{\"packet\":" + jsonText(Json(name)) + ",\"datum\":" + *datum + "}");
    net::post(impl_->ioc, [impl = impl_.get(), name, message] { impl->broadcast(name, message); });
}

ServerCounters MissionControl::counters() const {
    ServerCounters c;
    c.packetsReceived = impl_->received.load();
    c.packetsArchived = impl_->archived.load();
    c.decodeErrors = impl_->decodeErrors.load();
    c.archiveErrors = impl_->archiveErrors.load();
    c.realtimeDropped = impl_->dropped.load();
    c.clients = impl_->clients.load();
    return c;
}

std::string MissionControl::lastArchiveError() const {
    std::lock_guard<std::mutex> lock(impl_->archiveErrorMutex);
    return impl_->lastArchiveError;
}

std::int64_t utcNowMs() {
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::system_clock::now().time_since_epoch())
        .count();
}

}  // namespace rse::ground::mission_control
