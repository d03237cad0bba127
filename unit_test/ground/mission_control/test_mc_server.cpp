// The mission control server (ground/mission_control/mc_server.hpp) over real
// sockets on 127.0.0.1, an ephemeral port: static files and their types, ".."
// refused, the API's answers and errors, packets fed through onPacket (the
// entry the link loop calls) in /api/history and pushed over WebSocket to the
// clients subscribed to their packet only, a slow client's datums dropped and
// counted without holding the others, the archive kept across a restart; and
// `rse-ground serve` through the command line on a fake link.
#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <cstdint>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/ground_cli.hpp"
#include "ground/mission_control/mc_server.hpp"
#include "ground/mission_control/openmct_dictionary.hpp"
#include "ground/mission_control/serve_command.hpp"
#include "ground/mission_control/telemetry_archive.hpp"
#include "unit_test/ground/mission_control/mc_test_support.hpp"

#include "CppUTest/TestHarness.h"
#include "CppUTest/MemoryLeakWarningPlugin.h"

namespace cmdtlm = rse::cmdtlm;
namespace mcs = rse::ground::mission_control;
using mcs::Json;
using rse::test::mc::httpGet;
using rse::test::mc::HttpReply;
using rse::test::mc::packetOf;
using rse::test::mc::RealtimeClient;
using rse::test::mc::ScratchDir;

namespace {

constexpr std::int64_t kT0 = 1700000000000;  // a utc in ms

std::vector<std::uint8_t> roverState(double x) {
    cmdtlm::ROVER_STATE_Tlm state{};
    state.estimate_valid = 1;
    state.x = x;
    state.y = -2.25;
    state.covariance[4] = 0.5f;
    return packetOf(state);
}

std::vector<std::uint8_t> housekeeping(std::uint32_t accepted) {
    cmdtlm::HK_Tlm hk{};
    hk.mode = 2;
    hk.cmd_accepted = accepted;
    return packetOf(hk);
}

// A big datum (200 array elements): fills a slow client's socket quickly.
std::vector<std::uint8_t> tableDump(std::uint16_t offset) {
    cmdtlm::TABLE_DUMP_Tlm dump{};
    dump.offset = offset;
    for (std::size_t i = 0; i < 200; ++i) {
        dump.data[i] = static_cast<std::uint8_t>(200 + (i % 50));
    }
    return packetOf(dump);
}

Json parse(const std::string& text) {
    Json j = Json::parse(text, nullptr, false);
    CHECK_TEXT(!j.is_discarded(), text.c_str());
    return j;
}

// A web folder as npm ci and the plugin leave it.
void writeWebFolder(const ScratchDir& dir) {
    dir.write("web/index.html", "<!doctype html><title>RSE</title>");
    dir.write("web/rse-plugin.js", "export default function RsePlugin() {}");
    dir.write("web/style.css", "body { margin: 0 }");
    dir.write("web/icon.svg", "<svg xmlns=\"http://www.w3.org/2000/svg\"/>");
    dir.write("web/node_modules/openmct/dist/openmct.js", "/* openmct */ window.openmct = {};");
    dir.write("web/node_modules/openmct/dist/openmct.js.map", "{\"version\":3}");
    dir.write("secret.txt", "not for the web");
}

// The server on an ephemeral port in a scratch folder, started.
struct ServerRig {
    ScratchDir dir;
    mcs::ServerOptions options;
    std::unique_ptr<mcs::MissionControl> server;

    explicit ServerRig(std::size_t queueLimit = mcs::kDefaultClientQueueLimit) {
        writeWebFolder(dir);
        options.httpPort = 0;
        options.archivePath = dir.file("archive/archive.sqlite");
        options.webRoot = dir.file("web");
        options.tablesDir = "tables";
        options.link = "test link";
        options.clientQueueLimit = queueLimit;
        restart();
    }
    void restart() {
        server.reset();
        server = std::make_unique<mcs::MissionControl>(options);
        server->start();
    }
    std::uint16_t port() const { return server->httpPort(); }
    HttpReply get(const std::string& target) const { return httpGet(port(), target); }
    Json status() const { return parse(get("/api/status").body); }
    // Waits (at most 5 s) until f() holds.
    template <typename F>
    bool waitFor(F f) const {
        for (int i = 0; i < 500; ++i) {
            if (f()) {
                return true;
            }
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        return f();
    }
};

// Messages are handled in order: once the client has the answer to a bad
// message, everything it sent before has been taken into account.
void sync(RealtimeClient& client) {
    client.send("{\"subscribe\": \"SYNC_NO_SUCH_PACKET\"}");
    const Json reply = parse(client.receive());
    CHECK_TEXT(reply.contains("error"), reply.dump().c_str());
    STRCMP_CONTAINS("SYNC_NO_SUCH_PACKET", reply["error"].get<std::string>().c_str());
}

}  // namespace

// The server's thread allocates and frees on its own schedule (Asio's
// per-thread recycling, connections ending after a test): CppUTest's per-test
// new/delete bookkeeping cannot follow memory across threads, so it is off here.
TEST_GROUP(McServer) {
    void setup() override { MemoryLeakWarningPlugin::saveAndDisableNewDeleteOverloads(); }
    void teardown() override { MemoryLeakWarningPlugin::restoreNewDeleteOverloads(); }
};

TEST(McServer, ServesStaticFilesWithTheirTypes) {
    ServerRig rig;
    const HttpReply index = rig.get("/");
    CHECK_EQUAL(200U, index.status);
    STRCMP_EQUAL("<!doctype html><title>RSE</title>", index.body.c_str());
    STRCMP_EQUAL("text/html; charset=utf-8", index.header("Content-Type").c_str());
    const HttpReply plugin = rig.get("/rse-plugin.js");
    CHECK_EQUAL(200U, plugin.status);
    STRCMP_EQUAL("text/javascript; charset=utf-8", plugin.header("Content-Type").c_str());
    STRCMP_EQUAL("text/css; charset=utf-8", rig.get("/style.css").header("Content-Type").c_str());
    STRCMP_EQUAL("image/svg+xml", rig.get("/icon.svg").header("Content-Type").c_str());
    // /openmct/ is the npm package's dist folder.
    const HttpReply openmct = rig.get("/openmct/openmct.js");
    CHECK_EQUAL(200U, openmct.status);
    STRCMP_EQUAL("/* openmct */ window.openmct = {};", openmct.body.c_str());
    STRCMP_EQUAL("application/json", rig.get("/openmct/openmct.js.map").header("Content-Type").c_str());
    // Missing: 404 with a JSON error.
    const HttpReply missing = rig.get("/nothing.js");
    CHECK_EQUAL(404U, missing.status);
    CHECK_TRUE(parse(missing.body).contains("error"));
    CHECK_EQUAL(404U, rig.get("/node_modules").status);  // a folder is no file
    // Only GET.
    CHECK_EQUAL(405U, httpGet(rig.port(), "/", rse::test::mc::http::verb::post).status);
}

TEST(McServer, DotDotIsRefused) {
    ServerRig rig;
    for (const char* target : {"/../secret.txt", "/%2e%2e/secret.txt", "/openmct/../../../../secret.txt",
                               "/node_modules/../../secret.txt"}) {
        const HttpReply reply = rig.get(target);
        CHECK_EQUAL_TEXT(400U, reply.status, target);
        CHECK_TEXT(reply.body.find("not for the web") == std::string::npos, target);
        CHECK_TEXT(parse(reply.body).contains("error"), target);
    }
}

TEST(McServer, DictionaryMapAndStatus) {
    ServerRig rig;
    const HttpReply dictionary = rig.get("/api/dictionary");
    CHECK_EQUAL(200U, dictionary.status);
    STRCMP_EQUAL("application/json", dictionary.header("Content-Type").c_str());
    CHECK_TRUE(parse(dictionary.body) == mcs::displayDictionary());
    std::size_t packets = 0;
    cmdtlm::telemetryDescs(&packets);
    CHECK_EQUAL(packets, parse(dictionary.body)["packets"].size());

    const HttpReply map = rig.get("/api/map");
    CHECK_EQUAL(200U, map.status);
    const Json mapJson = parse(map.body);
    CHECK_TRUE(mapJson["site"].contains("x_min"));
    CHECK_TRUE(mapJson["rocks"].size() >= 1);
    CHECK_TRUE(mapJson["rocks"][0]["points"].size() >= 3);

    const Json status = rig.status();
    CHECK_EQUAL(0U, status["packets_received"].get<unsigned>());
    CHECK_EQUAL(0U, status["clients"].get<unsigned>());
    STRCMP_EQUAL(rig.options.archivePath.c_str(), status["archive"].get<std::string>().c_str());
    STRCMP_EQUAL("test link", status["link"].get<std::string>().c_str());
    CHECK_EQUAL(404U, rig.get("/api/nothing").status);
}

TEST(McServer, MapWithoutTablesIs404WithTheReason) {
    ServerRig rig;
    rig.options.tablesDir = rig.dir.file("no_tables");
    rig.restart();
    CHECK_FALSE(rig.server->siteMap().json.has_value());
    const HttpReply map = rig.get("/api/map");
    CHECK_EQUAL(404U, map.status);
    STRCMP_CONTAINS("no_tables/coarse_map.toml", parse(map.body)["error"].get<std::string>().c_str());
}

TEST(McServer, FedPacketsAreInHistoryAndSurviveARestart) {
    ServerRig rig;
    rig.server->onPacket(roverState(1.5), kT0);
    rig.server->onPacket(housekeeping(7), kT0 + 10);
    rig.server->onPacket(roverState(2.5), kT0 + 1000);
    rig.server->onPacket({0x01, 0x02, 0x03}, kT0 + 1001);  // not a packet: counted, archived undecoded
    const std::string query = "/api/history?packet=ROVER_STATE&start=" + std::to_string(kT0) +
                              "&end=" + std::to_string(kT0 + 1000);
    HttpReply history = rig.get(query);
    CHECK_EQUAL(200U, history.status);
    Json datums = parse(history.body);
    CHECK_TRUE(datums.is_array());
    CHECK_EQUAL(2U, datums.size());
    CHECK_EQUAL(kT0, datums[0]["utc"].get<std::int64_t>());
    DOUBLES_EQUAL(1.5, datums[0]["x"].get<double>(), 0.0);
    DOUBLES_EQUAL(-2.25, datums[0]["y"].get<double>(), 0.0);
    DOUBLES_EQUAL(0.5, datums[0]["covariance.4"].get<double>(), 0.0);
    DOUBLES_EQUAL(2.5, datums[1]["x"].get<double>(), 0.0);
    CHECK_TRUE(history.header("X-RSE-Truncated").empty());
    // The packet filter and the bounds.
    const Json hk = parse(rig.get("/api/history?packet=HK&start=" + std::to_string(kT0) + "&end=" +
                                  std::to_string(kT0 + 5000)).body);
    CHECK_EQUAL(1U, hk.size());
    CHECK_EQUAL(7U, hk[0]["cmd_accepted"].get<unsigned>());
    CHECK_EQUAL(1U, parse(rig.get("/api/history?packet=ROVER_STATE&start=" + std::to_string(kT0 + 1) + "&end=" +
                                  std::to_string(kT0 + 5000)).body).size());
    CHECK_EQUAL(0U, parse(rig.get("/api/history?packet=PLAN&start=0&end=" + std::to_string(kT0 * 2)).body).size());
    // Fractional ms bounds: start rounds up, end down.
    CHECK_EQUAL(1U, parse(rig.get("/api/history?packet=ROVER_STATE&start=" + std::to_string(kT0 - 1) + ".5&end=" +
                                  std::to_string(kT0) + ".9").body).size());
    const Json status = rig.status();
    CHECK_EQUAL(4U, status["packets_received"].get<unsigned>());
    CHECK_EQUAL(4U, status["packets_archived"].get<unsigned>());
    CHECK_EQUAL(1U, status["decode_errors"].get<unsigned>());

    // Restart on the same archive: the history is still there.
    rig.restart();
    history = rig.get(query);
    CHECK_EQUAL(200U, history.status);
    datums = parse(history.body);
    CHECK_EQUAL(2U, datums.size());
    DOUBLES_EQUAL(2.5, datums[1]["x"].get<double>(), 0.0);
    CHECK_EQUAL(0U, rig.status()["packets_received"].get<unsigned>());  // counters are this run's
}

TEST(McServer, HistoryParametersAreValidated) {
    ServerRig rig;
    const HttpReply unknown = rig.get("/api/history?packet=NO_SUCH&start=0&end=1");
    CHECK_EQUAL(404U, unknown.status);
    STRCMP_EQUAL("application/json", unknown.header("Content-Type").c_str());
    STRCMP_CONTAINS("NO_SUCH", parse(unknown.body)["error"].get<std::string>().c_str());
    for (const char* target : {"/api/history?packet=HK&start=abc&end=1", "/api/history?packet=HK&start=0&end=",
                               "/api/history?packet=HK&start=0&end=1e999", "/api/history?packet=HK&start=nan",
                               "/api/history?packet=HK&start=5&end=4", "/api/history?start=0&end=1",
                               "/api/history?packet=HK&packet=PLAN", "/api/history?packet=HK&start=%zz"}) {
        const HttpReply reply = rig.get(target);
        CHECK_EQUAL_TEXT(400U, reply.status, target);
        CHECK_TEXT(parse(reply.body).contains("error"), target);
    }
    // Open bounds, and parameters the server does not use, are fine.
    CHECK_EQUAL(200U, rig.get("/api/history?packet=HK").status);
    CHECK_EQUAL(200U, rig.get("/api/history?packet=HK&start=0&end=1&strategy=latest&size=1").status);
}

TEST(McServer, HistoryIsCutToTheNewestAndSaysSo) {
    ServerRig rig;
    rig.options.historyLimit = 3;
    rig.restart();
    for (int i = 0; i < 5; ++i) {
        rig.server->onPacket(housekeeping(static_cast<std::uint32_t>(i)), kT0 + i);
    }
    const HttpReply reply = rig.get("/api/history?packet=HK&start=0&end=" + std::to_string(kT0 * 2));
    STRCMP_EQUAL("true", reply.header("X-RSE-Truncated").c_str());
    const Json datums = parse(reply.body);
    CHECK_EQUAL(3U, datums.size());
    CHECK_EQUAL(2U, datums[0]["cmd_accepted"].get<unsigned>());
    CHECK_EQUAL(4U, datums[2]["cmd_accepted"].get<unsigned>());
}

TEST(McServer, RealtimePushesSubscribedPacketsOnly) {
    ServerRig rig;
    RealtimeClient client(rig.port());
    client.send("{\"subscribe\": \"ROVER_STATE\"}");
    sync(client);
    CHECK_TRUE(rig.waitFor([&] { return rig.status()["clients"].get<unsigned>() == 1; }));

    rig.server->onPacket(housekeeping(1), kT0);  // not subscribed
    rig.server->onPacket(roverState(3.25), kT0 + 5);
    Json message = parse(client.receive());
    STRCMP_EQUAL("ROVER_STATE", message["packet"].get<std::string>().c_str());
    CHECK_EQUAL(kT0 + 5, message["datum"]["utc"].get<std::int64_t>());
    DOUBLES_EQUAL(3.25, message["datum"]["x"].get<double>(), 0.0);

    // HK subscribed too: both arrive, in order.
    client.send("{\"subscribe\": \"HK\"}");
    sync(client);
    rig.server->onPacket(housekeeping(2), kT0 + 6);
    rig.server->onPacket(roverState(4.0), kT0 + 7);
    message = parse(client.receive());
    STRCMP_EQUAL("HK", message["packet"].get<std::string>().c_str());
    CHECK_EQUAL(2U, message["datum"]["cmd_accepted"].get<unsigned>());
    STRCMP_EQUAL("ROVER_STATE", parse(client.receive())["packet"].get<std::string>().c_str());

    // Unsubscribed: ROVER_STATE no longer comes (the next message is the
    // answer to the sync, not a datum).
    client.send("{\"unsubscribe\": \"ROVER_STATE\"}");
    sync(client);
    rig.server->onPacket(roverState(5.0), kT0 + 8);
    sync(client);
    rig.server->onPacket(housekeeping(3), kT0 + 9);
    STRCMP_EQUAL("HK", parse(client.receive())["packet"].get<std::string>().c_str());
}

TEST(McServer, MalformedMessagesGetAnErrorAndTheConnectionStays) {
    ServerRig rig;
    RealtimeClient client(rig.port());
    for (const char* bad : {"not json", "[1,2]", "{\"subscribe\": 5}", "{\"subscribe\": \"HK\", \"x\": 1}",
                            "{\"listen\": \"HK\"}", "{\"subscribe\": \"NO_SUCH\"}", "{}"}) {
        client.send(bad);
        const Json reply = parse(client.receive());
        CHECK_TEXT(reply.contains("error"), bad);
        CHECK_TEXT(reply["error"].is_string(), bad);
    }
    client.sendBinary("{\"subscribe\": \"HK\"}");
    STRCMP_CONTAINS("text message", parse(client.receive())["error"].get<std::string>().c_str());
    // Still connected, and still works.
    client.send("{\"subscribe\": \"HK\"}");
    sync(client);
    rig.server->onPacket(housekeeping(9), kT0);
    CHECK_EQUAL(9U, parse(client.receive())["datum"]["cmd_accepted"].get<unsigned>());
    // A WebSocket path only: a plain GET of /realtime is told so.
    CHECK_EQUAL(426U, rig.get("/realtime").status);
}

TEST(McServer, ASlowClientLosesItsOldestDatumsAndHoldsNobody) {
    ServerRig rig(64);                      // 64 datums may wait per client
    RealtimeClient slow(rig.port(), 4096);  // subscribes, then never reads
    slow.send("{\"subscribe\": \"TABLE_DUMP\"}");
    sync(slow);
    RealtimeClient fast(rig.port());
    fast.send("{\"subscribe\": \"TABLE_DUMP\"}");
    sync(fast);
    // ~2.5 kB a datum: 4000 of them (10 MB) are far more than the slow
    // client's socket buffers (the server's send buffer grows to 4 MB at
    // most) and queue hold. Fed in batches smaller than the queue, each read
    // by the fast client before the next (within its 10 s): the fast client
    // keeps getting every datum while the slow one holds its connection full.
    constexpr int kPackets = 4000;
    constexpr int kBatch = 32;
    Json last;
    const auto started = std::chrono::steady_clock::now();
    for (int i = 0; i < kPackets; i += kBatch) {
        for (int j = i; j < i + kBatch; ++j) {
            rig.server->onPacket(tableDump(static_cast<std::uint16_t>(j % 2048)), kT0 + j);
        }
        for (int j = i; j < i + kBatch; ++j) {
            last = parse(fast.receive());
            CHECK_EQUAL(j % 2048, last["datum"]["offset"].get<int>());  // every one, in order
        }
    }
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    CHECK_EQUAL((kPackets - 1) % 2048, last["datum"]["offset"].get<int>());
    // The slow one lost datums, counted.
    const Json status = rig.status();
    CHECK_TRUE(status["realtime_dropped"].get<std::uint64_t>() > 0);
    CHECK_EQUAL(rig.server->counters().realtimeDropped, status["realtime_dropped"].get<std::uint64_t>());
    CHECK_EQUAL(static_cast<unsigned>(kPackets), status["packets_archived"].get<unsigned>());
    CHECK_EQUAL(2U, status["clients"].get<unsigned>());
    // Nothing waited for the slow client (archiving is what the time is).
    CHECK_TEXT(seconds < 60.0, std::to_string(seconds).c_str());
}

TEST(McServer, RefusesABadArchiveAndABusyPort) {
    ScratchDir dir;
    dir.write("bad.sqlite", std::string(8192, 'z'));
    mcs::ServerOptions options;
    options.httpPort = 0;
    options.archivePath = dir.file("bad.sqlite");
    options.webRoot = dir.file("web");
    try {
        mcs::MissionControl server(options);
        FAIL("a file that is not an archive was taken");
    } catch (const mcs::ArchiveError& e) {
        STRCMP_CONTAINS("not an RSE telemetry archive", e.what());
    }
    ServerRig rig;
    options.archivePath = dir.file("good.sqlite");
    options.httpPort = rig.port();
    try {
        mcs::MissionControl second(options);
        FAIL("a port in use was bound");
    } catch (const mcs::ServerError& e) {
        STRCMP_CONTAINS(std::to_string(rig.port()).c_str(), e.what());
    }
}

namespace {

// The link `serve` reads: the packets given, then nothing.
class ScriptedLink final : public rse::ground::GroundLink {
public:
    explicit ScriptedLink(std::vector<std::vector<std::uint8_t>> packets) : packets_(std::move(packets)) {}
    void send(const std::vector<std::uint8_t>&) override {}
    std::optional<std::vector<std::uint8_t>> receive(double timeoutSeconds) override {
        if (next_ < packets_.size()) {
            return packets_[next_++];
        }
        std::this_thread::sleep_for(std::chrono::duration<double>(std::min(timeoutSeconds, 0.01)));
        return std::nullopt;
    }
    std::string describe() const override { return "scripted link"; }

private:
    std::vector<std::vector<std::uint8_t>> packets_;
    std::size_t next_ = 0;
};

struct CliRun {
    int rc = -1;
    std::string out;
    std::string err;
};

CliRun runCli(std::vector<std::string> args, const rse::ground::ServeCommand& serve) {
    args.insert(args.begin(), "rse-ground");
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    std::ostringstream out;
    std::ostringstream err;
    const rse::ground::LinkFactory link = [](bool) -> std::unique_ptr<rse::ground::GroundLink> {
        return std::make_unique<ScriptedLink>(
            std::vector<std::vector<std::uint8_t>>{roverState(1.0), housekeeping(5), {0xFF}, roverState(2.0)});
    };
    CliRun run;
    run.rc = rse::ground::runGroundCli(static_cast<int>(argv.size()), argv.data(), out, err, link, serve);
    run.out = out.str();
    run.err = err.str();
    return run;
}

}  // namespace

TEST(McServer, ServeCommandArchivesTheLinksPackets) {
    ScratchDir dir;
    const std::string archive = dir.file("archive.sqlite");
    const CliRun run = runCli({"serve", "--http", "127.0.0.1:0", "--archive", archive, "--web", dir.file("web"),
                               "--tables", "tables", "--seconds", "0.5"},
                              mcs::runServe);
    CHECK_EQUAL_TEXT(0, run.rc, run.err.c_str());
    STRCMP_CONTAINS("serving http://127.0.0.1:", run.out.c_str());
    STRCMP_CONTAINS("telemetry from scripted link", run.out.c_str());
    STRCMP_CONTAINS("4 packets received, 4 archived, 1 not decoded", run.out.c_str());
    STRCMP_CONTAINS("closed", run.out.c_str());
    mcs::TelemetryArchive reopened(archive);
    CHECK_EQUAL(4U, reopened.rows());
    CHECK_EQUAL(2U, reopened.history("ROVER_STATE", 0, INT64_MAX, 10).datums.size());
}

TEST(McServer, ServeCommandUsage) {
    const CliRun bad = runCli({"serve", "--bogus"}, mcs::runServe);
    CHECK_EQUAL(rse::ground::kExitUsage, bad.rc);
    STRCMP_CONTAINS("--bogus", bad.err.c_str());
    const CliRun badPort = runCli({"serve", "--http", "127.0.0.1:99999"}, mcs::runServe);
    CHECK_EQUAL(rse::ground::kExitUsage, badPort.rc);
    STRCMP_CONTAINS("--http", badPort.err.c_str());
    const CliRun badSeconds = runCli({"serve", "--seconds", "-1"}, mcs::runServe);
    CHECK_EQUAL(rse::ground::kExitUsage, badSeconds.rc);
    STRCMP_CONTAINS("rse-ground: see 'rse-ground --help'", badSeconds.err.c_str());
    const CliRun help = runCli({"serve", "--help"}, mcs::runServe);
    CHECK_EQUAL(0, help.rc);
    STRCMP_CONTAINS("serve [--http [ADDR:]PORT]", help.out.c_str());
    // A program built without the server says so.
    const CliRun without = runCli({"serve"}, rse::ground::ServeCommand());
    CHECK_EQUAL(rse::ground::kExitUsage, without.rc);
    STRCMP_CONTAINS("not built into this program", without.err.c_str());
    // A bad archive: exit 1, the reason said.
    ScratchDir dir;
    dir.write("bad.sqlite", std::string(8192, 'z'));
    const CliRun badArchive = runCli({"serve", "--http", "127.0.0.1:0", "--archive", dir.file("bad.sqlite")}, mcs::runServe);
    CHECK_EQUAL(rse::ground::kExitLink, badArchive.rc);
    STRCMP_CONTAINS("not an RSE telemetry archive", badArchive.err.c_str());
}

namespace {
void ignoreSignal(int) {}
}  // namespace

TEST(McServer, SigtermStopsServeCleanly) {
    ScratchDir dir;
    const std::string archive = dir.file("archive.sqlite");
    // Should SIGTERM come before serve set its handler, it must not end the
    // suite: serve would then run its 30 s and the test fail.
    struct sigaction harmless {};
    harmless.sa_handler = ignoreSignal;
    struct sigaction previous {};
    sigaction(SIGTERM, &harmless, &previous);
    std::thread killer([&] {
        // The archive exists once the server is up; serve handles SIGTERM right after.
        for (int i = 0; i < 500 && !std::filesystem::exists(archive); ++i) {
            std::this_thread::sleep_for(std::chrono::milliseconds(10));
        }
        std::this_thread::sleep_for(std::chrono::milliseconds(300));
        ::kill(::getpid(), SIGTERM);
    });
    const auto started = std::chrono::steady_clock::now();
    const CliRun run = runCli({"serve", "--http", "127.0.0.1:0", "--archive", archive, "--web", dir.file("web"),
                               "--seconds", "30"},
                              mcs::runServe);
    killer.join();
    sigaction(SIGTERM, &previous, nullptr);
    CHECK_TRUE(std::chrono::steady_clock::now() - started < std::chrono::seconds(10));
    CHECK_EQUAL_TEXT(0, run.rc, run.err.c_str());
    STRCMP_CONTAINS("SIGTERM: stopping", run.out.c_str());
    STRCMP_CONTAINS(("archive " + archive + " closed").c_str(), run.out.c_str());
    // Closed means checkpointed: no WAL left beside it.
    CHECK_FALSE(std::filesystem::exists(archive + "-wal"));
    CHECK_EQUAL(4U, mcs::TelemetryArchive(archive).rows());
}
