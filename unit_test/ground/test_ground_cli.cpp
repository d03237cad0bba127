// rse-ground's command line end to end: exit codes, messages, the packet file of
// `encode`, the dictionary export, and `send` over real UDP sockets (ephemeral
// ports) to a fake rover thread that checks packets with the flight validator.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "ground/command_encoder.hpp"
#include "ground/dictionary_export.hpp"
#include "ground/ground_cli.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

struct CliResult {
    int rc = -1;
    std::string out;
    std::string err;
};

CliResult cli(std::vector<std::string> args) {
    args.insert(args.begin(), "rse-ground");
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(a.data());
    }
    argv.push_back(nullptr);
    std::ostringstream out;
    std::ostringstream err;
    CliResult r;
    r.rc = ground::runGroundCli(static_cast<int>(args.size()), argv.data(), out, err);
    r.out = out.str();
    r.err = err.str();
    return r;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<std::uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// The fake rover on a UDP socket of its own thread: answers every command to
// the port it came from (rse-ground sends from its telemetry socket).
class UdpRover {
public:
    UdpRover() {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        socklen_t length = sizeof a;
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length);
        port_ = ntohs(a.sin_port);
    }
    ~UdpRover() {
        stop();
        ::close(fd_);
    }
    void start() {
        thread_ = std::thread([this] { loop(); });
    }
    void stop() {
        running_ = false;
        if (thread_.joinable()) {
            thread_.join();
        }
    }
    std::uint16_t port() const { return port_; }
    test::FakeRover rover;

private:
    void loop() {
        while (running_) {
            pollfd p{fd_, POLLIN, 0};
            if (::poll(&p, 1, 20) <= 0) {
                continue;
            }
            std::uint8_t buffer[2048];
            sockaddr_in from{};
            socklen_t length = sizeof from;
            const ssize_t n = ::recvfrom(fd_, buffer, sizeof buffer, 0, reinterpret_cast<sockaddr*>(&from), &length);
            if (n <= 0) {
                continue;
            }
            for (const auto& tlm : rover.handle(buffer, static_cast<std::size_t>(n))) {
                ::sendto(fd_, tlm.data(), tlm.size(), 0, reinterpret_cast<sockaddr*>(&from), length);
            }
        }
    }

    int fd_ = -1;
    std::uint16_t port_ = 0;
    std::atomic<bool> running_{true};
    std::thread thread_;
};

}  // namespace

TEST_GROUP(GroundCli){};

TEST(GroundCli, NoArgumentsOrUnknownCommandIsUsage) {
    CliResult r = cli({});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "usage: rse-ground"));
    r = cli({"launch"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "unknown command 'launch'"));
    r = cli({"--help"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "send NAME [arg=value ...]"));
}

TEST(GroundCli, BadCommandsAndArgumentsExitTwoBeforeAnyLinkIsOpened) {
    test::TempDir dir;
    CliResult r = cli({"--state-dir", dir.path(), "send", "WARP", "factor=9"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "unknown command 'WARP'"));
    r = cli({"--state-dir", dir.path(), "send", "GOTO", "x=1", "y=2", "risk=2"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "GOTO: risk=2 is out of range 1e-09..0.5"));
    r = cli({"--state-dir", dir.path(), "send", "GOTO", "x=1", "y=2"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "missing argument 'risk'"));
    r = cli({"--state-dir", dir.path(), "send", "NOOP", "--bogus"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "unknown option --bogus"));
    r = cli({"--timeout", "-1", "send", "NOOP"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "--timeout '-1'"));
    r = cli({"--key-id", "5", "--state-dir", dir.path(), "send", "NOOP"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "only the lab key (id 1) is built in"));
    // Nothing consumed a sequence number.
    CHECK_FALSE(std::ifstream(dir.file("auth_seq_key1")).good());
}

TEST(GroundCli, NoRoverMeansExitOneWithTheLinkHint) {
    test::TempDir dir;
    UdpRover silent;  // bound, never answering
    const CliResult r = cli({"--udp", "127.0.0.1:" + std::to_string(silent.port()), "--tlm-port", "127.0.0.1:0",
                             "--timeout", "0.2", "--state-dir", dir.path(), "send", "NOOP"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "NOOP: no acknowledgement within 0.2 s: is rse-fsw running and is the link up?"));
}

TEST(GroundCli, SendAcceptedRejectedAndReplayed) {
    test::TempDir dir;
    UdpRover rover;
    rover.start();
    const std::vector<std::string> link = {"--udp", "127.0.0.1:" + std::to_string(rover.port()), "--tlm-port",
                                           "127.0.0.1:0", "--state-dir", dir.path()};
    auto with = [&](std::vector<std::string> rest) {
        std::vector<std::string> all = link;
        all.insert(all.end(), rest.begin(), rest.end());
        return cli(all);
    };
    CliResult r = with({"send", "goto", "x=10", "y=-5", "risk=1e-3"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "GOTO (0x181/0, auth seq 1) accepted"));
    CHECK_TRUE(contains(r.err, "built-in lab key"));

    r = with({"send", "DRIVE", "v=0.1", "omega=0", "duration=2"});  // STANDBY: DRIVE needs MANUAL
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "DRIVE (0x182/2, auth seq 2) rejected: wrong_mode (detail 1: rover in STANDBY)"));

    r = with({"send", "NOOP", "--auth-seq", "2"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: replayed_sequence"));
    CHECK_TRUE(contains(r.err, "hint: the rover has seen this anti-replay number"));

    r = with({"--no-auth", "send", "NOOP"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: mac_missing"));

    r = with({"send", "NOOP", "--no-wait"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "NOOP sent (auth seq 3)"));
    rover.stop();
    CHECK_EQUAL(5U, rover.rover.verdicts.size());
    CHECK_EQUAL(1U, rover.rover.verdicts[1].keyId);
    CHECK_EQUAL(0U, rover.rover.verdicts[3].keyId);
}

TEST(GroundCli, EncodeWritesThePacketFile) {
    test::TempDir dir;
    const std::string path = dir.file("goto.bin");
    const CliResult r =
        cli({"--state-dir", dir.path(), "encode", "GOTO", "x=1", "y=2", "risk=0.01", "--auth-seq", "42", "-o", path});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "GOTO, 54 bytes, key id 1, auth seq 42"));
    CHECK_TRUE(fileBytes(path) == ground::encodeCommand("GOTO", {"x=1", "y=2", "risk=0.01"}, ground::labKeyAuth(), 42));

    // Without -o: hex on stdout, with the next number from the store.
    const CliResult hex = cli({"--state-dir", dir.path(), "encode", "NOOP"});
    CHECK_EQUAL(0, hex.rc);
    CHECK_TRUE(hex.out.rfind("19 80 C0 ", 0) == 0);
}

TEST(GroundCli, DictExportsMarkdownAndJson) {
    CliResult r = cli({"dict", "--json"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(r.out == ground::exportDictionaryJson());
    r = cli({"dict", "--markdown"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(r.out == ground::exportDictionaryMarkdown());
    r = cli({"dict"});
    CHECK_EQUAL(2, r.rc);
}

TEST(GroundCli, WatchPrintsDecodedPacketsAndStopsAtCount) {
    // A rover socket that sends three packets to the ground's telemetry port.
    int probe = ::socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    ::bind(probe, reinterpret_cast<sockaddr*>(&a), sizeof a);
    socklen_t length = sizeof a;
    ::getsockname(probe, reinterpret_cast<sockaddr*>(&a), &length);
    const std::uint16_t port = ntohs(a.sin_port);
    ::close(probe);  // a free port for watch to bind

    std::thread sender([port] {
        std::this_thread::sleep_for(std::chrono::milliseconds(100));
        int fd = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in to{};
        to.sin_family = AF_INET;
        to.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        to.sin_port = htons(port);
        cmdtlm::HK_Tlm hk{};
        hk.mode = 1;
        cmdtlm::EVENT_Tlm e{};
        e.event_id = 7;
        e.severity = 3;
        std::strncpy(e.text, "drive 3 faulted", sizeof e.text);
        const std::vector<std::vector<std::uint8_t>> packets = {
            test::telemetryPacket(hk), {1, 2, 3}, test::telemetryPacket(e), test::telemetryPacket(hk)};
        for (const auto& p : packets) {
            ::sendto(fd, p.data(), p.size(), 0, reinterpret_cast<sockaddr*>(&to), sizeof to);
        }
        ::close(fd);
    });
    const CliResult r = cli({"--tlm-port", "127.0.0.1:" + std::to_string(port), "watch", "--count", "3", "--seconds",
                             "3"});
    sender.join();
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "HK           apid=0x001 seq=0"));
    CHECK_TRUE(contains(r.out, "MALFORMED    length 3 is shorter"));
    CHECK_TRUE(contains(r.out, "EVT 7 ERROR drive 3 faulted"));
}

TEST(GroundCli, WatchWithNothingToSeeExitsOne) {
    const CliResult r = cli({"--tlm-port", "127.0.0.1:0", "watch", "--seconds", "0.2"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "no telemetry within 0.2 s"));
    CHECK_EQUAL(2, cli({"watch", "--only", "NOPE"}).rc);
}

TEST(GroundCli, TableDumpOfAnUnknownTableIsUsage) {
    const CliResult r = cli({"table", "dump", "NO_SUCH_TABLE"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "no table 'NO_SUCH_TABLE' (tables: 1 ROVER_GEOMETRY"));
}

TEST(GroundCli, TableToolCommandsAreForwarded) {
    const CliResult r = cli({"table", "check", "/nonexistent.tbl"});
    CHECK_TRUE(r.rc != 0);
    CHECK_FALSE(contains(r.err, "usage: rse-ground [global options]"));
}
