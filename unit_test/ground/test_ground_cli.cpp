// rse-ground's command line end to end: exit codes, messages, the packet file of
// `encode`, the dictionary export, `send` and `watch` against a fake rover that
// checks packets with the flight validator, and a real UDP link with no rover.
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/command_auth.hpp"
#include "ground/command_encoder.hpp"
#include "ground/dictionary_export.hpp"
#include "ground/ground_cli.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::CliResult;
using test::CliRig;
using test::cli;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::vector<std::uint8_t> fileBytes(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::vector<std::uint8_t>(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A bound UDP socket that never answers: a rover that is not there.
class SilentSocket {
public:
    SilentSocket() {
        fd_ = ::socket(AF_INET, SOCK_DGRAM, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a);
        socklen_t length = sizeof a;
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length);
        port_ = ntohs(a.sin_port);
    }
    ~SilentSocket() { ::close(fd_); }
    std::uint16_t port() const { return port_; }

private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
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

// docs/operations.md, "Command lines": --help anywhere is the usage on stdout
// (exit 0); a bad command line is one line saying what is wrong and the line
// pointing to --help, on stderr only (exit 2).
TEST(GroundCli, HelpAndBadCommandLinesFollowTheConvention) {
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"-h"}, {"help"}, {"send", "--help"}, {"table", "build", "-h"}, {"plan", "check", "--help"},
             {"--timeout", "1", "watch", "--help"}}) {
        const CliResult r = cli(args);
        CHECK_EQUAL_TEXT(0, r.rc, args[0].c_str());
        CHECK_TRUE(contains(r.out, "global options (before the command):"));
        CHECK_TRUE(r.err.empty());
    }
    for (const std::vector<std::string>& args : std::vector<std::vector<std::string>>{
             {"--bogus", "send", "NOOP"}, {"send", "NOOP", "--bogus"}, {"watch", "--count"},
             {"table", "build", "tables/planner.toml"}, {"plan", "check"}, {"dict", "--json", "--markdown"},
             {"--timeout", "x", "send", "NOOP"}, {"send", "GOTO", "x=1"}, {"launch"}, {}}) {
        const CliResult r = cli(args);
        CHECK_EQUAL_TEXT(2, r.rc, r.err.c_str());
        CHECK_TRUE(r.out.empty());
        const std::size_t first = r.err.find('\n');
        CHECK_TEXT(r.err.rfind("rse-ground: ", 0) == 0, r.err.c_str());
        CHECK_TEXT(r.err.substr(first + 1) == "rse-ground: see 'rse-ground --help'\n", r.err.c_str());
    }
}

// Global options come before the command: after it they are the command's
// options, which it does not know, and it says where they go.
TEST(GroundCli, AGlobalOptionAfterTheCommandIsNamed) {
    const CliResult r = cli({"send", "NOOP", "--timeout", "1"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "send: --timeout is a global option: give it before the command"));
}

TEST(GroundCli, BadCommandsAndArgumentsExitTwoBeforeAnyLinkIsOpened) {
    test::TempDir dir;
    CliResult r = cli({"--state-dir", dir.path(), "send", "WARP", "factor=9"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "unknown command 'WARP'"));
    r = cli({"--state-dir", dir.path(), "send", "GOTO", "x=1", "y=2", "risk=2"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "GOTO: risk=2 is out of range 1e-09..0.49"));
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
    SilentSocket silent;
    const CliResult r = cli({"--udp", "127.0.0.1:" + std::to_string(silent.port()), "--tlm-port", "127.0.0.1:0",
                             "--timeout", "0.2", "--state-dir", dir.path(), "send", "NOOP"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "NOOP: no acknowledgement within 0.2 s: is rse-fsw running and is the link up?"));
}

TEST(GroundCli, ALostRoverStoreIsExplainedAndResynchronisedWithTheNonce) {
    CliRig rig;
    hal::MemoryRecordStore lost;  // nothing in it: the rover's store is missing
    rig.rover.attachAuthStore(&lost, 0x0000000200000003ULL);
    CliResult r = rig.run({"send", "NOOP"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: sequence_unsynchronised (detail 1"));
    CHECK_TRUE(contains(r.err, "rse-ground resync (it reads the nonce from HK"));

    r = rig.run({"send", "AUTH_RESYNC", "challenge_high=2", "challenge_low=4"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: sequence_unsynchronised (detail 4"));
    CHECK_TRUE(contains(r.err, "not the rover's current nonce"));

    r = rig.run({"send", "AUTH_RESYNC", "challenge_high=2", "challenge_low=3"});
    CHECK_EQUAL(0, r.rc);
    r = rig.run({"send", "NOOP"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(lost.present());

    r = rig.run({"send", "NOOP", "--auth-seq", "4294967295"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: sequence_exhausted"));
    CHECK_TRUE(contains(r.err, "load a new key"));
}

// One step instead of two: the nonce from the rover's HK, then AUTH_RESYNC with it.
TEST(GroundCli, ResyncReadsTheNonceFromHkAndResynchronisesInOneStep) {
    CliRig rig;
    hal::MemoryRecordStore lost;
    rig.rover.attachAuthStore(&lost, 0x0000000700000009ULL);
    CliResult r = rig.run({"--timeout", "0.2", "resync"});
    CHECK_EQUAL(1, r.rc);  // no HK comes: nothing is sent
    CHECK_TRUE(contains(r.err, "resync: no HK within 3 s"));
    CHECK_TRUE(rig.link.sent.empty());

    rig.rover.beacon = true;
    r = rig.run({"resync"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "rover nonce 7:9 (auth_store_state 2, keys unsynchronised 1)"));
    CHECK_TRUE(contains(r.out, "AUTH_RESYNC (0x180/4, auth seq 1) accepted"));
    CHECK_TRUE(lost.present());
    r = rig.run({"send", "NOOP"});
    CHECK_EQUAL(0, r.rc);
    // The nonce moved on: the next resync reads the new one.
    r = rig.run({"resync"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "rover nonce 7:10"));

    r = rig.run({"--no-auth", "resync"});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "cannot be sent with --no-auth"));
}

TEST(GroundCli, SendAcceptedRejectedAndReplayed) {
    CliRig rig;
    CliResult r = rig.run({"send", "goto", "x=10", "y=-5", "risk=1e-3"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "GOTO (0x181/0, auth seq 1) accepted"));
    CHECK_TRUE(contains(r.err, "built-in lab key"));
    CHECK_TRUE(rig.lastListen);

    r = rig.run({"send", "DRIVE", "v=0.1", "omega=0", "duration=2"});  // STANDBY: DRIVE needs MANUAL
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "DRIVE (0x182/2, auth seq 2) rejected: wrong_mode (detail 1: rover in STANDBY)"));

    r = rig.run({"send", "NOOP", "--auth-seq", "2"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: replayed_sequence"));
    CHECK_TRUE(contains(r.err, "hint: the rover has seen this anti-replay number"));
    // After a rover restart its floor is at most 1024 above the last number it accepted.
    CHECK_TRUE(contains(r.err, "after a rover restart every number up to its stored reservation is refused"));
    CHECK_TRUE(contains(r.err, "--auth-seq 1027"));

    r = rig.run({"--no-auth", "send", "NOOP"});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "rejected: mac_missing"));
    CHECK_TRUE(contains(r.err, "drop --no-auth"));

    r = rig.run({"send", "NOOP", "--no-wait"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "NOOP sent (auth seq 3)"));
    CHECK_FALSE(rig.lastListen);

    CHECK_EQUAL(5U, rig.rover.verdicts.size());
    CHECK_EQUAL(1U, rig.rover.verdicts[1].keyId);
    CHECK_EQUAL(0U, rig.rover.verdicts[3].keyId);
    CHECK_EQUAL(5, rig.linksOpened);
}

TEST(GroundCli, SendWithoutAnAnswerExitsOne) {
    CliRig rig;
    rig.rover.answer = false;
    const CliResult r = rig.run({"--timeout", "0.1", "send", "NOOP"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "no acknowledgement within 0.1 s"));
}

TEST(GroundCli, TableLoadThroughTheCli) {
    CliRig rig;
    const std::string image = rig.dir.file("geometry.tbl");
    CHECK_EQUAL(0, cli({"table", "build", "tables/rover_geometry.toml", "-o", image}).rc);
    const CliResult r = rig.run({"table", "load", image, "--activate"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(rig.rover.loadedImage == fileBytes(image));
    CHECK_TRUE(contains(r.out, "ROVER_GEOMETRY loaded, validated and activated"));
    CHECK_EQUAL(1, cli({"table", "load", rig.dir.file("missing.tbl")}).rc);
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
    CliRig rig;
    cmdtlm::HK_Tlm hk{};
    hk.mode = 1;
    cmdtlm::EVENT_Tlm e{};
    e.event_id = 7;
    e.severity = 3;
    std::strncpy(e.text, "drive 3 faulted", sizeof e.text);
    for (const auto& p : std::vector<std::vector<std::uint8_t>>{test::telemetryPacket(hk), {1, 2, 3},
                                                                test::telemetryPacket(e), test::telemetryPacket(hk)}) {
        rig.link.queue.push_back(p);
    }
    CliResult r = rig.run({"watch", "--count", "3", "--seconds", "3"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "HK           apid=0x001 seq=0"));
    CHECK_TRUE(contains(r.out, "MALFORMED    length 3 is shorter"));
    CHECK_TRUE(contains(r.out, "EVT 7 ERROR drive 3 faulted"));
    CHECK_EQUAL(1U, rig.link.queue.size());  // stopped at the count

    rig.link.queue.push_back(test::telemetryPacket(e));
    r = rig.run({"watch", "--only", "event", "--seconds", "0.3"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "EVT 7 ERROR"));
    CHECK_FALSE(contains(r.out, "HK "));

    r = rig.run({"watch", "--count", "5", "--seconds", "0.2"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "watch: 0 of 5 packets within 0.2 s"));
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

// Issue 14 item 4: the lab key's bytes under any key id are the public lab key;
// rse-ground says so when it signs with them from a key file.
TEST(GroundCli, SigningWithTheLabKeyFromAKeyFileUnderAnyIdWarns) {
    test::TempDir dir;
    const std::string keys = dir.file("lab.keys");
    std::string hex;
    static const char digits[] = "0123456789abcdef";
    for (std::size_t i = 0; i < cmdtlm::kKeySize; ++i) {
        hex += digits[cmdtlm::kLabKey[i] >> 4];
        hex += digits[cmdtlm::kLabKey[i] & 0x0F];
    }
    {
        std::ofstream out(keys);
        out << "9:" << hex << "\n";
    }
    ::chmod(keys.c_str(), 0600);
    const CliResult r = cli({"--state-dir", dir.path(), "--key-file", keys, "encode", "NOOP", "--auth-seq", "3"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.err, "key id 9 of " + keys + " is the public lab key"));
}
