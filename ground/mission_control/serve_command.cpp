#include "ground/mission_control/serve_command.hpp"

#include <csignal>
#include <cmath>
#include <optional>
#include <ostream>

#include "ground/cli_options.hpp"
#include "ground/ground_cli.hpp"
#include "ground/mission_control/telemetry_archive.hpp"
#include "ground/ground_session.hpp"
#include "ground/text_format.hpp"

namespace rse::ground::mission_control {
namespace {

// How long one wait on the link lasts: the longest a signal waits to be seen.
constexpr double kLinkPollSeconds = 0.25;

volatile std::sig_atomic_t gStopSignal = 0;

void onStopSignal(int signal) { gStopSignal = signal; }

// SIGINT and SIGTERM set gStopSignal while it lives (no SA_RESTART: a wait on
// the link returns at once), the previous handlers back after.
class StopSignals {
public:
    StopSignals() {
        gStopSignal = 0;
        struct sigaction action {};
        action.sa_handler = onStopSignal;
        sigemptyset(&action.sa_mask);
        sigaction(SIGINT, &action, &previousInt_);
        sigaction(SIGTERM, &action, &previousTerm_);
    }
    ~StopSignals() {
        sigaction(SIGINT, &previousInt_, nullptr);
        sigaction(SIGTERM, &previousTerm_, nullptr);
    }
    StopSignals(const StopSignals&) = delete;
    StopSignals& operator=(const StopSignals&) = delete;
    int received() const { return gStopSignal; }

private:
    struct sigaction previousInt_ {};
    struct sigaction previousTerm_ {};
};

std::string describeSignal(int signal) { return signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "signal"; }

}  // namespace

ServeOptions parseServeOptions(const std::vector<std::string>& args) {
    const ParsedOptions parsed = parseCliOptions("serve", args,
                                                 {{"http", 0, true},
                                                  {"archive", 0, true},
                                                  {"web", 0, true},
                                                  {"tables", 0, true},
                                                  {"seconds", 0, true}});
    if (!parsed.operands.empty()) {
        throw UsageError("serve: unexpected '" + parsed.operands[0] + "'");
    }
    ServeOptions options;
    if (const std::optional<std::string> text = parsed.value("--http")) {
        try {
            HostPort where = parseHostPort(*text, options.server.httpAddress, kDefaultHttpPort);
            // [::1]:8090: an IPv6 address in brackets.
            if (where.host.size() > 2 && where.host.front() == '[' && where.host.back() == ']') {
                where.host = where.host.substr(1, where.host.size() - 2);
            }
            options.server.httpAddress = where.host;
            options.server.httpPort = where.port;
        } catch (const LinkError& e) {
            throw UsageError(std::string("--http ") + e.what());
        }
    }
    options.server.archivePath = parsed.value("--archive").value_or(options.server.archivePath);
    options.server.webRoot = parsed.value("--web").value_or(options.server.webRoot);
    options.server.tablesDir = parsed.value("--tables").value_or(options.server.tablesDir);
    if (const std::optional<std::string> text = parsed.value("--seconds")) {
        if (!parseDouble(*text, &options.seconds) || !std::isfinite(options.seconds) || options.seconds <= 0.0) {
            throw UsageError("--seconds '" + *text + "': expected seconds, a number > 0");
        }
    }
    for (std::string* path : {&options.server.archivePath, &options.server.webRoot, &options.server.tablesDir}) {
        if (path->empty()) {
            throw UsageError("serve: --archive, --web and --tables need a non-empty path");
        }
    }
    return options;
}

int runServe(const std::vector<std::string>& args, const std::function<std::unique_ptr<GroundLink>()>& openLink,
             std::ostream& out, std::ostream& err) {
    ServeOptions options;
    try {
        options = parseServeOptions(args);
    } catch (const UsageError& e) {
        return reportUsageError(err, e.what());
    }
    std::unique_ptr<GroundLink> link = openLink();
    options.server.link = link->describe();
    std::optional<MissionControl> server;
    try {
        server.emplace(options.server);
    } catch (const ArchiveError& e) {
        err << "rse-ground: serve: " << e.what() << "\n";
        return kExitLink;
    } catch (const ServerError& e) {
        err << "rse-ground: serve: " << e.what() << "\n";
        return kExitLink;
    }
    if (!server->siteMap().json) {
        err << "rse-ground: serve: warning: no site map (/api/map answers 404): " << server->siteMap().error << "\n";
    }
    StopSignals signals;
    server->start();
    const std::string& address = options.server.httpAddress;
    const bool v6 = address.find(':') != std::string::npos;
    out << "serving http://" << (v6 ? "[" + address + "]" : address) << ":" << server->httpPort() << "/ (web "
        << options.server.webRoot << ", archive " << options.server.archivePath << "), telemetry from "
        << link->describe() << (options.seconds > 0 ? " for " + formatNumber(options.seconds) + " s" : "")
        << "; Ctrl-C stops\n"
        << std::flush;
    const double start = monotonicSeconds();
    std::uint64_t archiveErrorsSaid = 0;
    while (signals.received() == 0) {
        double wait = kLinkPollSeconds;
        if (options.seconds > 0) {
            const double left = start + options.seconds - monotonicSeconds();
            if (left <= 0) {
                break;
            }
            wait = left < wait ? left : wait;
        }
        std::optional<std::vector<std::uint8_t>> bytes = link->receive(wait);
        if (bytes) {
            server->onPacket(*bytes, utcNowMs());
        }
        // Said once, then at each tenfold: the count is in /api/status.
        const std::uint64_t archiveErrors = server->counters().archiveErrors;
        if (archiveErrors > archiveErrorsSaid && (archiveErrorsSaid == 0 || archiveErrors >= 10 * archiveErrorsSaid)) {
            err << "rse-ground: serve: " << archiveErrors << " packet(s) not archived: " << server->lastArchiveError()
                << "\n";
            archiveErrorsSaid = archiveErrors;
        }
    }
    if (signals.received() != 0) {
        out << "serve: " << describeSignal(signals.received()) << ": stopping\n";
    }
    server->stop();
    const ServerCounters c = server->counters();
    server.reset();  // the archive closed
    out << "serve: " << c.packetsReceived << " packets received, " << c.packetsArchived << " archived, "
        << c.decodeErrors << " not decoded, " << c.archiveErrors << " archive errors, " << c.realtimeDropped
        << " realtime datums dropped; archive " << options.server.archivePath << " closed\n";
    return kExitOk;
}

}  // namespace rse::ground::mission_control
