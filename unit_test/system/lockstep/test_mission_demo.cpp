// rse-demo's logic (sim_stub/lockstep/mission_runner.hpp): its command line
// as rse-demo's main and the runner take it (exit codes, setup failures), short
// lockstep missions judged against the truth the summary reports, and the demo itself: the ten points of the RSE
// demonstration in order, each with its substance, the report and the map
// written; a run that cannot show them all saying so and exiting 3; a run
// paced against the wall clock sending its telemetry over UDP (--pace,
// --udp-telemetry). (The hidden rock whose detour does not fit, point 5's
// other side, is in the scenario suite, test_scenario_suite.cpp. The parts
// alone - the options parser and the scenario's [mission], the summary's
// lines, the frame pacer, the flight watch, the plan uplink - are in
// unit_test/sim_stub/lockstep/.)
#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "ground/telemetry_decoder.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MissionOptions;
using sim::MissionOutcome;
using sim::MissionSummary;
using sim::ParseOutcome;

namespace {

ParseOutcome parse(std::vector<const char*> args, MissionOptions* o, std::string* error) {
    args.insert(args.begin(), "rse-demo");
    return sim::parseMissionArgs(static_cast<int>(args.size()), args.data(), o, error);
}

std::string readFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// A folder of its own under build/ for a run's report and map.
std::string reportFolder(const char* name) { return std::string("build/test_mission_demo/") + name; }

// Everything written to a temporary file so far.
std::string readAll(std::FILE* f) {
    std::fflush(f);
    std::rewind(f);
    std::string text;
    char chunk[4096];
    for (std::size_t n = std::fread(chunk, 1, sizeof chunk, f); n > 0; n = std::fread(chunk, 1, sizeof chunk, f)) {
        text.append(chunk, n);
    }
    return text;
}

bool contains(const std::string& text, const char* what) { return text.find(what) != std::string::npos; }

unsigned countOf(const std::string& text, const char* what) {
    unsigned n = 0;
    for (std::size_t p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) {
        ++n;
    }
    return n;
}

// A UDP socket bound to 127.0.0.1 on a port the kernel picks: a ground's
// telemetry port, or a port taken.
class LoopbackSocket {
public:
    LoopbackSocket() {
        fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_NONBLOCK | SOCK_CLOEXEC, 0);
        sockaddr_in a{};
        a.sin_family = AF_INET;
        a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
        socklen_t length = sizeof a;
        if (fd_ >= 0 && ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0 &&
            ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &length) == 0) {
            port_ = ntohs(a.sin_port);
        }
    }
    ~LoopbackSocket() {
        if (fd_ >= 0) {
            ::close(fd_);
        }
    }
    LoopbackSocket(const LoopbackSocket&) = delete;
    LoopbackSocket& operator=(const LoopbackSocket&) = delete;
    std::uint16_t port() const { return port_; }  // 0: the socket could not be made
    // Every datagram waiting, in arrival order.
    void drainInto(std::vector<std::vector<std::uint8_t>>* datagrams) {
        std::uint8_t buffer[2048];
        for (ssize_t n = ::recv(fd_, buffer, sizeof buffer, 0); n >= 0; n = ::recv(fd_, buffer, sizeof buffer, 0)) {
            datagrams->emplace_back(buffer, buffer + n);
        }
    }

private:
    int fd_ = -1;
    std::uint16_t port_ = 0;
};

}  // namespace

TEST_GROUP(MissionDemoOptions) {
    MissionOptions o;
    std::string error;
};

// A plan the ground's check refuses is never sent: the setup fails before the
// rover boots and says why (the runner checks it as `rse-ground plan load` does).
TEST(MissionDemoOptions, APlanTheGroundCheckRefusesIsNotSent) {
    const char* path = "build/test_mission_demo/bad_plan.toml";
    const char* plan = "build/test_mission_demo/bad.plan";
    std::filesystem::create_directories("build/test_mission_demo");
    std::FILE* f = std::fopen(plan, "w");
    CHECK(f != nullptr);
    std::fputs("plan bad\nactivity a drive start nowhere [1, 2] cost 1 at 1 1\nend\n", f);
    std::fclose(f);
    f = std::fopen(path, "w");
    CHECK(f != nullptr);
    std::fputs("seed = 1\n[map]\nx_min_m = -5\nx_max_m = 30\ny_min_m = -10\ny_max_m = 10\n"
               "[start]\nx_m = 0\ny_m = 0\n[mission]\nplan_file = \"bad.plan\"\n",
               f);
    std::fclose(f);
    CHECK(ParseOutcome::kRun == parse({"--scenario", path, "--quiet"}, &o, &error));
    const MissionSummary s = sim::runMission(o, nullptr);
    CHECK(MissionOutcome::kSetupFailed == s.outcome);
    CHECK_TEXT(contains(s.setupError, "bad.plan: the plan did not pass the ground check"), s.setupError.c_str());
}

// rse-demo itself: a refused pace or address exits 2 with the reason on one
// line and a pointer to --help (docs/operations.md, "Command lines"); nothing
// on stdout.
TEST(MissionDemoOptions, ABadPaceOrUdpAddressExitsTwoWithTheReason) {
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    CHECK(out != nullptr && err != nullptr);
    const char* slow[] = {"rse-demo", "--pace", "0.05"};
    LONGS_EQUAL(2, sim::missionMain(3, slow, out, err));
    const char* named[] = {"rse-demo", "--udp-telemetry", "ground:1235"};
    LONGS_EQUAL(2, sim::missionMain(3, named, out, err));
    const std::string errText = readAll(err);
    CHECK_TRUE(contains(errText, "rse-demo: --pace '0.05' is not a factor over real time in [0.1, 1000]"));
    CHECK_TRUE(contains(errText, "rse-demo: --udp-telemetry 'ground:1235': 'ground' is not a numeric IPv4 address"));
    CHECK_TRUE(contains(errText, "rse-demo: see 'rse-demo --help'\n"));
    CHECK_FALSE(contains(errText, "usage:"));
    CHECK_TRUE(readAll(out).empty());
    std::fclose(out);
    std::fclose(err);
}

// A UDP link that cannot be opened (its command port taken) is a setup
// failure that says so, before the flight software starts.
TEST(MissionDemoOptions, AUdpCommandPortInUseFailsTheSetup) {
    LoopbackSocket taken;
    CHECK(taken.port() != 0);
    CHECK(ParseOutcome::kRun == parse({"--quiet", "--udp-telemetry", "127.0.0.1:9", "--udp-commands",
                                       std::to_string(taken.port()).c_str()},
                                      &o, &error));
    const MissionSummary s = sim::runMission(o, nullptr);
    CHECK(MissionOutcome::kSetupFailed == s.outcome);
    CHECK_TEXT(contains(s.setupError, ("cannot open the UDP ground link (commands on 127.0.0.1:" +
                                       std::to_string(taken.port()) + ", telemetry to 127.0.0.1:9): ")
                                          .c_str()),
               s.setupError.c_str());
    CHECK_TEXT(contains(s.setupError, "in use"), s.setupError.c_str());
}

TEST(MissionDemoOptions, ExitCodesAreTwoForUsageOneForSetupZeroForHelp) {
    std::FILE* out = std::tmpfile();
    std::FILE* err = std::tmpfile();
    CHECK(out != nullptr && err != nullptr);
    const char* unknown[] = {"rse-demo", "--fast"};
    LONGS_EQUAL(2, sim::missionMain(2, unknown, out, err));
    const char* noScenario[] = {"rse-demo", "--scenario", "sim_stub/scenarios/no_such_scenario.toml", "--quiet"};
    LONGS_EQUAL(1, sim::missionMain(4, noScenario, out, err));
    const char* help[] = {"rse-demo", "--help"};
    LONGS_EQUAL(0, sim::missionMain(2, help, out, err));
    const std::string errText = readAll(err);
    CHECK_TRUE(contains(errText, "rse-demo: unknown or incomplete option '--fast'\nrse-demo: see 'rse-demo --help'\n"));
    CHECK_TRUE(contains(errText, "setup failed"));
    CHECK_TRUE(contains(readAll(out), "usage: rse-demo"));
    std::fclose(out);
    std::fclose(err);
}

TEST_GROUP(MissionDemoRun) {
    std::FILE* out = nullptr;
    MissionOptions o;
    std::string error;
    void setup() override { out = std::tmpfile(); }
    void teardown() override {
        if (out != nullptr) {
            std::fclose(out);
        }
    }
};

// A near goal without the faults: planned, driven, complete; the figures the
// summary gives agree with each other and with the truth.
TEST(MissionDemoRun, ANearGoalWithoutFaultsIsReachedAndTheSummaryAgreesWithTheTruth) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--no-faults", "--goto", "4,0", "--duration", "60"}, &o, &error));
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    if (s.outcome != MissionOutcome::kGoalReached) {
        std::printf("%s\n", text.c_str());
    }
    CHECK(MissionOutcome::kGoalReached == s.outcome);
    CHECK(msg::DeliberativeState::kComplete == s.finalState);
    CHECK(s.outcomeTimeS < 60.0);
    DOUBLES_EQUAL(s.outcomeTimeS + 2.0, s.endTimeS, 0.02);  // the tail for the last events
    // Truth: at the goal, without contact, along a path no shorter than the displacement.
    DOUBLES_EQUAL(std::hypot(s.finalX - 4.0, s.finalY), s.goalDistanceM, 1e-12);
    CHECK(s.goalDistanceM < 0.6);
    CHECK(s.distanceM >= std::hypot(s.finalX, s.finalY) - 1e-9);
    CHECK(s.distanceM < 8.0);
    LONGS_EQUAL(0, s.collisions);
    CHECK(s.energyWh > 0.0);
    // Flight software: a plan, every leg sent ended achieved or failed up, no call home.
    CHECK(s.plansMade >= 1);
    CHECK(s.legsSent >= 1);
    LONGS_EQUAL(s.legsSent, s.legsAchieved + s.failUps);
    LONGS_EQUAL(0, s.callHomes);
    CHECK(s.riskUsed <= s.riskInForce);
    DOUBLES_EQUAL(1e-3, s.riskBound, 1e-15);
    CHECK(s.commandsAccepted >= 2);  // SET_MODE and GOTO, authenticated
    LONGS_EQUAL(0, s.commandsRejected);
    // The stream: the demo's lines, the console's, the summaries.
    CHECK_TRUE(contains(text, "DEMO ground: GOTO x=4.00 y=0.00 risk=0.001"));
    CHECK_TRUE(contains(text, "DEMO deliberative layer: COMPLETE"));
    LONGS_EQUAL(1, countOf(text, "EVT 908 INFO  deliberative: every goal reached"));
    CHECK(countOf(text, "] HK  #") >= 10);
    CHECK_TRUE(contains(text, "outcome:    goal (4.00, 0.00) reached"));
    CHECK_TRUE(contains(text, "rse-fsw summary:"));
    CHECK_TRUE(contains(text, "deliberative"));
}

// --pace 10 --udp-telemetry: 2 s of mission take at least about 0.2 s of wall
// time (only a lower bound is asserted: a shared machine may be slower, never
// faster), and a ground's UDP socket receives every telemetry packet the
// flight software sent on the link, CCSDS packets the ground's decoder reads
// (HK, ROVER_STATE, EVENT among them), while the in-memory ground commands
// the mission as before.
TEST(MissionDemoRun, APacedRunTakesItsWallTimeAndSendsItsTelemetryOverUdp) {
    CHECK(out != nullptr);
    LoopbackSocket ground;
    CHECK(ground.port() != 0);
    const std::string to = "127.0.0.1:" + std::to_string(ground.port());
    CHECK(ParseOutcome::kRun == parse({"--no-faults", "--goto", "4,0", "--duration", "2", "--pace", "10",
                                       "--udp-telemetry", to.c_str()},
                                      &o, &error));
    // Read every frame, so the socket's buffer never holds more than a frame's packets.
    std::vector<std::vector<std::uint8_t>> datagrams;
    o.onFrame = [&](sim::LockstepRig&) { ground.drainInto(&datagrams); };
    const auto start = std::chrono::steady_clock::now();
    const MissionSummary s = sim::runMission(o, out);
    const double wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ground.drainInto(&datagrams);
    const std::string text = readAll(out);

    CHECK(MissionOutcome::kTimedOut == s.outcome);
    CHECK_TEXT(wallS >= 0.15, ("2 s of mission at --pace 10 took " + std::to_string(wallS) + " s").c_str());
    DOUBLES_EQUAL(10.0, s.pace, 0.0);
    CHECK(s.pacedFrames >= 199 && s.pacedFrames <= 201);
    CHECK(s.framesBehind <= s.pacedFrames);
    CHECK_TRUE(contains(text, "DEMO paced at 10x real time: a frame every 1.000 ms of wall time"));
    CHECK_TRUE(contains(text, "pace:       10x real time: "));
    CHECK_TRUE(contains(text, "; behind by up to "));
    // The in-memory ground still commands: SET_MODE and GOTO taken; nothing came over UDP.
    CHECK(s.commandsAccepted >= 2);
    LONGS_EQUAL(0, s.commandsRejected);
    CHECK_TRUE(s.udpLink);
    STRCMP_EQUAL(to.c_str(), s.udpTelemetry.c_str());
    LONGS_EQUAL(0, s.udpStats.rxPackets);
    CHECK_TRUE(contains(text, ("DEMO telemetry and events also as UDP datagrams to " + to).c_str()));

    // Every packet sent arrived, and each decodes as the dictionary says.
    LONGS_EQUAL(0, s.udpStats.txDropped);
    LONGS_EQUAL(0, s.udpStats.errors);
    CHECK(s.udpStats.txPackets > 0);
    LONGS_EQUAL(s.udpStats.txPackets, datagrams.size());
    std::map<std::string, unsigned> byName;
    double lastMet = 0.0;
    double roverX = std::nan("");
    for (const std::vector<std::uint8_t>& d : datagrams) {
        const ground::DecodedPacket p = ground::decodeTelemetry(d);
        if (!p.ok) {
            FAIL(("a UDP datagram did not decode: " + p.error + ": " + ground::renderPacket(p)).c_str());
        }
        ++byName[p.name()];
        CHECK(p.met >= lastMet - 1e-9);  // in the order the flight software sent them
        lastMet = p.met;
        if (std::string(p.name()) == "ROVER_STATE") {
            roverX = p.value("x").value_or(std::nan(""));
        }
    }
    CHECK(lastMet <= 2.0 + 1e-9);
    CHECK(byName["HK"] >= 2);  // 1 Hz, from the first frame
    CHECK(byName["ROVER_STATE"] >= 1);
    CHECK(byName["EVENT"] >= 10);
    CHECK(byName["CMD_ACK"] >= 2);  // the in-memory ground's commands are acknowledged on every link
    DOUBLES_EQUAL(0.0, roverX, 0.5);  // where the scenario starts it, 2 s in
}

// The duration ends a mission that has not finished; --quiet leaves the console out.
TEST(MissionDemoRun, TheDurationEndsAnUnfinishedMissionAndQuietLeavesTheConsoleOut) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--no-faults", "--duration", "6", "--quiet"}, &o, &error));
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    CHECK(MissionOutcome::kTimedOut == s.outcome);
    CHECK(s.endTimeS >= 6.0 && s.endTimeS < 6.02);
    CHECK(s.goalDistanceM > 5.0);  // nowhere near (20, 0) yet
    LONGS_EQUAL(0, countOf(text, "] HK  #"));
    LONGS_EQUAL(0, countOf(text, " EVT "));
    CHECK_TRUE(contains(text, "outcome:    timed out at 6.0 s"));
}

// The demonstration (issue 17, must-show 1): the demo scenario shows the ten
// points of the RSE demonstration, each once, in order, each read from what
// the flight software published, with its substance; the report and the map
// are written and carry every point.
TEST(MissionDemoRun, TheDemoShowsTheTenPointsInOrderAndWritesTheReportAndTheMap) {
    CHECK(out != nullptr);
    CHECK(ParseOutcome::kRun == parse({"--quiet"}, &o, &error));
    o.reportDir = reportFolder("demo");
    const MissionSummary s = sim::runMission(o, out);
    const std::string text = readAll(out);
    const ground::MissionRecord& r = s.record;
    if (!s.tenPointsInOrder || std::getenv("RSE_PRINT_CONSOLE") != nullptr) {
        std::printf("%s\n", text.c_str());
    }
    CHECK_TRUE(s.tenPointsInOrder);
    STRCMP_EQUAL("ten points: all in order", r.verdict.c_str());
    for (int n = 1; n <= ground::kMissionPointCount; ++n) {
        const ground::MissionPoint& p = r.points[static_cast<std::size_t>(n - 1)];
        CHECK_TRUE(p.seen);
        LONGS_EQUAL(n, p.number);
        if (n > 1) {
            CHECK(p.timeS >= r.points[static_cast<std::size_t>(n - 2)].timeS);
        }
        // Printed once, numbered, as it was seen.
        const std::string line = "POINT " + std::to_string(n) + " ";
        LONGS_EQUAL(1, countOf(text, line.c_str()));
    }
    const auto fact = [&r](int n, const char* name) {
        const auto& f = r.points[static_cast<std::size_t>(n - 1)].facts;
        const auto it = f.find(name);
        return it == f.end() ? std::nan("") : it->second;
    };
    // 1: the operator's bound, as the flight software took it.
    DOUBLES_EQUAL(1e-3, fact(1, "risk bound"), 1e-15);
    // 2: legs with an energy and a power bound.
    CHECK(fact(2, "energy bound J") > 0.0);
    CHECK(fact(2, "power bound W") > 0.0);
    // 5: the hidden rock (the scenario's obstacle 3, not on the coarse map),
    // replanned round within the leg's bounds: no fail-up from its sighting to
    // the leg achieved, and the deliberative layer not involved.
    DOUBLES_EQUAL(3.0, fact(5, "hazard"), 0.0);
    DOUBLES_EQUAL(0.0, fact(5, "fail-ups"), 0.0);
    CHECK(fact(5, "seen s") < r.points[4].timeS);
    // 6 and 7: the power bound broken by the worn motor, then relaxed above
    // what it was, and driving resumed.
    CHECK(fact(7, "power bound after W") > fact(7, "power bound before W"));
    DOUBLES_EQUAL(fact(6, "power bound W"), fact(7, "power bound before W"), 0.5);
    // 8: after the motor failure (87 s in the scenario).
    CHECK(r.points[7].timeS > 87.0);
    // 10: the risk-bound call home, the rover safed.
    DOUBLES_EQUAL(static_cast<double>(msg::CallHomeReason::kNoPlanWithinRisk), fact(10, "call home reason"), 0.0);
    CHECK(MissionOutcome::kCalledHome == s.outcome);
    CHECK(msg::CallHomeReason::kNoPlanWithinRisk == s.callHome);
    LONGS_EQUAL(0, s.finalMode);  // SAFE
    CHECK(s.riskRelaxations >= 1);
    LONGS_EQUAL(0, s.collisions);

    // The report and the map, named at the end.
    CHECK_TRUE(contains(text, "mission report: build/test_mission_demo/demo/report.md"));
    CHECK_TRUE(contains(text, "mission map:    build/test_mission_demo/demo/map.svg"));
    CHECK_TRUE(contains(text, "points:     ten points: all in order"));
    const std::string report = readFile(s.reportPath);
    const std::string map = readFile(s.mapPath);
    CHECK_TRUE(contains(report, "**ten points: all in order**"));
    CHECK_TRUE(contains(report, "## Timing per task"));
    CHECK_TRUE(contains(report, "| deliberative |"));
    CHECK_TRUE(contains(map, "<svg"));
    CHECK_TRUE(contains(map, "</svg>"));
    for (int n = 1; n <= ground::kMissionPointCount; ++n) {
        const ground::MissionPoint& p = r.points[static_cast<std::size_t>(n - 1)];
        CHECK_TRUE(contains(report, ("| " + std::to_string(n) + " | ").c_str()));
        CHECK_TRUE(p.hasPlace);
        CHECK_TRUE(contains(map, ("id=\"point-" + std::to_string(n) + "\"").c_str()));
    }
    CHECK_TRUE(contains(map, "class=\"hidden-rock\""));
    CHECK_TRUE(contains(map, "class=\"track-truth\""));
    CHECK_TRUE(contains(map, "class=\"track-estimate\""));
    CHECK_TRUE(contains(map, "class=\"mean-path\""));
    CHECK(countOf(map, "class=\"ellipse\"") >= 21);  // a plan of 20 steps: 21 ellipses
}

// A run that cannot show the ten points (the demo without its faults: no worn
// or failed motor) is judged so, and rse-demo exits 3 - or 0 with --any-outcome.
// A ground on a real bus commands later than the lockstep runner (the vcan
// mission's GOTO came at about 2.2 s of flight time, its simulator 0.3 s
// ahead): the demo must show its ten points whenever the GOTO comes in the
// first seconds, not only at 0.5 s. Measured over 0..5.6 s in 0.2 s steps: all
// in order (docs/mission.md, "The same mission from the ground"); these are the
// starts whose runs take other courses (a 4-leg plan and the rock seen before
// its leg; a merged leg whose power fail-up comes on the detour).
TEST(MissionDemoRun, TheTenPointsHoldWhenTheGroundCommandsLater) {
    for (const double at : {1.6, 2.4}) {  // aarch64 at 3.5 s: points 9, 10 missing (libm-level differences); see docs/mission.md
        MissionOptions later;
        CHECK(ParseOutcome::kRun == parse({"--quiet"}, &later, &error));
        later.commandAtS = at;
        const MissionSummary s = sim::runMission(later, out);
        if (!s.tenPointsInOrder) {
            FAIL(("GOTO at " + std::to_string(at) + " s: " + s.record.verdict).c_str());
        }
        CHECK(s.outcome == sim::MissionOutcome::kCalledHome);
        LONGS_EQUAL(static_cast<long>(msg::CallHomeReason::kNoPlanWithinRisk), static_cast<long>(s.callHome));
        LONGS_EQUAL(0, s.collisions);
    }
}

TEST(MissionDemoRun, ARunWithoutTheFaultsMissesPointsAndExitsThree) {
    std::FILE* err = std::tmpfile();
    CHECK(out != nullptr && err != nullptr);
    const char* noFaults[] = {"rse-demo", "--no-faults", "--quiet", "--no-report"};
    LONGS_EQUAL(3, sim::missionMain(4, noFaults, out, err));
    const std::string errText = readAll(err);
    CHECK_TRUE(contains(errText, "ten points: NOT all in order; missing 6, 7, 8, 9, 10"));
    CHECK_TRUE(contains(readAll(out), "outcome:    goal (20.00, 0.00) reached"));
    const char* anyOutcome[] = {"rse-demo", "--no-faults", "--quiet", "--no-report", "--any-outcome", "--duration", "20"};
    LONGS_EQUAL(0, sim::missionMain(7, anyOutcome, out, err));
    std::fclose(err);
}
