// rse-demo's options (sim_stub/lockstep/mission_options.hpp): the command
// line (getopt_long, docs/operations.md "Command lines") into MissionOptions,
// every accepted form and every refusal with its reason naming the option and
// the value; the goal checked against the dictionary's GOTO ranges by the
// ground's encoder; the scenario's [mission] filling only what the command
// line left open; the encoder's argument text; the usage text. (rse-demo's
// exit statuses and setup failures: unit_test/system/lockstep/test_mission_demo.cpp.)
#include <cstdio>
#include <string>
#include <vector>

#include "fsw/core/byte_codec.hpp"
#include "sim_stub/lockstep/mission_options.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using sim::MissionOptions;
using sim::ParseOutcome;

namespace {

ParseOutcome parse(std::vector<const char*> args, MissionOptions* o, std::string* error) {
    args.insert(args.begin(), "rse-demo");
    return sim::parseMissionArgs(static_cast<int>(args.size()), args.data(), o, error);
}

bool contains(const std::string& text, const char* what) { return text.find(what) != std::string::npos; }

// The GOTO argument bytes as flight decodes them: x, y, risk (f64, big-endian).
void checkGotoArgs(const MissionOptions& o, double x, double y, double risk) {
    LONGS_EQUAL(24, o.gotoArgs.size());
    core::BeReader r(o.gotoArgs.data(), o.gotoArgs.size());
    DOUBLES_EQUAL(x, r.f64(), 0.0);
    DOUBLES_EQUAL(y, r.f64(), 0.0);
    DOUBLES_EQUAL(risk, r.f64(), 0.0);
}

// A scenario of its own with a [mission] goal (own.toml).
sim::Scenario scenarioWithGoal() {
    return sim::parseScenario(
        "seed = 1\nduration_s = 75\n[map]\nx_min_m = -5\nx_max_m = 30\ny_min_m = -10\ny_max_m = 10\n"
        "[start]\nx_m = 0\ny_m = 0\n[mission]\ngoal_x_m = 12.5\ngoal_y_m = -3\nrisk_bound = 1e-5\n",
        "own.toml");
}

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

}  // namespace

TEST_GROUP(MissionOptions) {
    MissionOptions o;
    std::string error;
};

// Without --goto and --duration the mission is the scenario's own: the demo
// scenario's [mission] is GOTO (20, 0) at 10^-3 for 180 s.
TEST(MissionOptions, NoArgumentsIsTheDemoMissionToTwentyMetres) {
    CHECK(ParseOutcome::kRun == parse({}, &o, &error));
    STRCMP_EQUAL("sim_stub/scenarios/demo_mission.toml", o.scenarioPath.c_str());
    CHECK_FALSE(o.anyOutcome);
    CHECK_FALSE(o.clearFaults);
    CHECK_FALSE(o.quiet);
    DOUBLES_EQUAL(0.0, o.durationS, 0.0);  // the scenario's
    CHECK_TRUE(o.gotoArgs.empty());        // the scenario's
    CHECK_TRUE(sim::applyScenarioMission(sim::loadScenarioFile(o.scenarioPath), &o, &error));
    DOUBLES_EQUAL(180.0, o.durationS, 0.0);
    checkGotoArgs(o, 20.0, 0.0, 1e-3);
    CHECK_TRUE(o.planText.empty());
}

// The scenario's [mission] where the command line says nothing, never over it;
// a scenario without one gets the demo's goal and 180 s; a plan mission its
// plan's text and the bound for SET_RISK_BOUND.
TEST(MissionOptions, TheScenariosMissionFillsOnlyWhatTheCommandLineLeftOpen) {
    sim::Scenario s = scenarioWithGoal();
    MissionOptions own;
    CHECK_TRUE(sim::applyScenarioMission(s, &own, &error));
    checkGotoArgs(own, 12.5, -3.0, 1e-5);
    DOUBLES_EQUAL(75.0, own.durationS, 0.0);
    CHECK_TRUE(sim::applyScenarioMission(s, &own, &error));  // again: nothing changes
    checkGotoArgs(own, 12.5, -3.0, 1e-5);
    // --goto and --duration win.
    CHECK(ParseOutcome::kRun == parse({"--goto", "4,1,0.01", "--duration", "30"}, &o, &error));
    CHECK_TRUE(sim::applyScenarioMission(s, &o, &error));
    checkGotoArgs(o, 4.0, 1.0, 0.01);
    DOUBLES_EQUAL(30.0, o.durationS, 0.0);
    // No [mission]: the demo's goal and duration.
    s.mission = sim::MissionSpec{};
    MissionOptions none;
    CHECK_TRUE(sim::applyScenarioMission(s, &none, &error));
    checkGotoArgs(none, 20.0, 0.0, 1e-3);
    DOUBLES_EQUAL(180.0, none.durationS, 0.0);
    // A plan: its text and its bound; no GOTO.
    s.mission.present = true;
    s.mission.planFile = "p.plan";
    s.mission.planText = "plan p\nend\n";
    s.mission.riskBound = 1e-4;
    MissionOptions plan;
    CHECK_TRUE(sim::applyScenarioMission(s, &plan, &error));
    CHECK_TRUE(plan.gotoArgs.empty());
    STRCMP_EQUAL("plan p\nend\n", plan.planText.c_str());
    STRCMP_EQUAL("p.plan", plan.planFile.c_str());
    DOUBLES_EQUAL(1e-4, plan.risk, 0.0);
    DOUBLES_EQUAL(75.0, plan.durationS, 0.0);
}

TEST(MissionOptions, EveryOptionIsTaken) {
    const char* args[] = {"rse-demo", "--report", "some/where", "--any-outcome"};
    MissionOptions withReport;
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(4, args, &withReport, &error));
    STRCMP_EQUAL("some/where", withReport.reportDir.c_str());
    CHECK_TRUE(withReport.anyOutcome);
    const char* none[] = {"rse-demo", "--no-report"};
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(2, none, &withReport, &error));
    CHECK_TRUE(withReport.reportDir.empty());
    CHECK_TRUE(withReport.noReport);
    // Without either, runMission writes nothing; rse-demo's main writes to build/mission.
    MissionOptions defaults;
    const char* bare[] = {"rse-demo"};
    CHECK(ParseOutcome::kRun == sim::parseMissionArgs(1, bare, &defaults, &error));
    CHECK_TRUE(defaults.reportDir.empty());
    CHECK_FALSE(defaults.noReport);
    STRCMP_EQUAL("build/mission", sim::kDefaultReportDir);
    CHECK(ParseOutcome::kRun == parse({"--scenario", "other.toml", "--no-faults", "--goto", "4,-1.5,0.01", "--duration",
                                       "30", "--quiet"},
                                      &o, &error));
    STRCMP_EQUAL("other.toml", o.scenarioPath.c_str());
    CHECK_TRUE(o.clearFaults);
    CHECK_TRUE(o.quiet);
    DOUBLES_EQUAL(30.0, o.durationS, 0.0);
    DOUBLES_EQUAL(4.0, o.goalX, 0.0);
    DOUBLES_EQUAL(-1.5, o.goalY, 0.0);
    DOUBLES_EQUAL(0.01, o.risk, 0.0);
    checkGotoArgs(o, 4.0, -1.5, 0.01);
}

TEST(MissionOptions, AGotoWithoutRiskTakesTheDefaultBound) {
    CHECK(ParseOutcome::kRun == parse({"--goto", "4,0"}, &o, &error));
    checkGotoArgs(o, 4.0, 0.0, 1e-3);
}

TEST(MissionOptions, ABadGotoIsAUsageError) {
    const char* const bad[] = {"4", "4,", ",0", "4,0,1e-3,7", "a,0", "4,0,x", "4,0,0.9", "4,0,0", "1e5,0", "4,nan"};
    for (const char* g : bad) {
        MissionOptions fresh;
        error.clear();
        const ParseOutcome r = parse({"--goto", g}, &fresh, &error);
        if (r != ParseOutcome::kUsageError) {
            FAIL(("--goto " + std::string(g) + " was accepted").c_str());
        }
        CHECK_TRUE(contains(error, "--goto"));
    }
    // Out of the dictionary's range: the ground encoder's reason is shown.
    CHECK(ParseOutcome::kUsageError == parse({"--goto", "4,0,0.9"}, &o, &error));
    CHECK_TRUE(contains(error, "risk"));
}

TEST(MissionOptions, UnknownFlagsMissingValuesAndBadDurationsAreUsageErrors) {
    CHECK(ParseOutcome::kUsageError == parse({"--fast"}, &o, &error));
    CHECK_TRUE(contains(error, "'--fast'"));
    CHECK(ParseOutcome::kUsageError == parse({"--goto"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--scenario"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "-3"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "3s"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--command-at", "-1"}, &o, &error));
    CHECK_TRUE(contains(error, "--command-at"));
    CHECK(ParseOutcome::kUsageError == parse({"--command-at", "soon"}, &o, &error));
    CHECK(ParseOutcome::kRun == parse({"--command-at", "2.5"}, &o, &error));
    DOUBLES_EQUAL(2.5, o.commandAtS, 0.0);
    CHECK(ParseOutcome::kHelp == parse({"--help"}, &o, &error));
}

// getopt_long (docs/operations.md, "Command lines"): "--option=value" too, -h
// for --help, a missing value and a stray argument named in the error.
TEST(MissionOptions, TheCommandLineIsGetoptLongs) {
    CHECK(ParseOutcome::kRun == parse({"--duration=30", "--goto=4,1"}, &o, &error));
    DOUBLES_EQUAL(30.0, o.durationS, 0.0);
    DOUBLES_EQUAL(4.0, o.goalX, 0.0);
    CHECK(ParseOutcome::kHelp == parse({"-h"}, &o, &error));
    CHECK(ParseOutcome::kUsageError == parse({"--quiet", "--goto"}, &o, &error));
    STRCMP_EQUAL("option '--goto' needs a value", error.c_str());
    CHECK(ParseOutcome::kUsageError == parse({"--quiet", "extra"}, &o, &error));
    CHECK_TEXT(contains(error, "unexpected argument 'extra'"), error.c_str());
    CHECK(ParseOutcome::kUsageError == parse({"--quiet=1"}, &o, &error));
    STRCMP_EQUAL("option '--quiet' takes no value", error.c_str());
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "1e7"}, &o, &error));
    STRCMP_EQUAL("--duration '1e7' is not a number of seconds in (0, 1e6]", error.c_str());
}

// --pace F: a factor over real time in [0.1, 1000]; without it, no pacing.
TEST(MissionOptions, ThePaceIsAFactorOverRealTimeWithinItsRange) {
    DOUBLES_EQUAL(0.0, o.pace, 0.0);  // as fast as the CPU allows
    CHECK(ParseOutcome::kRun == parse({"--pace", "10"}, &o, &error));
    DOUBLES_EQUAL(10.0, o.pace, 0.0);
    CHECK(ParseOutcome::kRun == parse({"--pace", "0.1"}, &o, &error));
    DOUBLES_EQUAL(sim::kMinPace, o.pace, 0.0);
    CHECK(ParseOutcome::kRun == parse({"--pace", "1000"}, &o, &error));
    DOUBLES_EQUAL(sim::kMaxPace, o.pace, 0.0);
    for (const char* bad : {"0.09", "1000.5", "0", "-1", "fast", "10x", "nan", "inf", ""}) {
        MissionOptions fresh;
        error.clear();
        if (parse({"--pace", bad}, &fresh, &error) != ParseOutcome::kUsageError) {
            FAIL(("--pace '" + std::string(bad) + "' was accepted").c_str());
        }
        CHECK_TEXT(contains(error, ("--pace '" + std::string(bad) + "' is not a factor over real time in [0.1, 1000]")
                                       .c_str()),
                   error.c_str());
    }
    CHECK(ParseOutcome::kUsageError == parse({"--pace"}, &o, &error));
    CHECK_TRUE(contains(error, "'--pace'"));
}

// --udp-telemetry HOST:PORT (numeric IPv4, the UDP link looks up no names) and
// --udp-commands [ADDR:]PORT, which needs it; without them, no UDP link.
TEST(MissionOptions, TheUdpLinksAddressesAreCheckedAndItsCommandPortWantsItsTelemetry) {
    CHECK_TRUE(o.udpTelemetryHost.empty());
    LONGS_EQUAL(0, o.udpCommandPort);
    CHECK(ParseOutcome::kRun == parse({"--udp-telemetry", "127.0.0.1:1235"}, &o, &error));
    STRCMP_EQUAL("127.0.0.1", o.udpTelemetryHost.c_str());
    LONGS_EQUAL(1235, o.udpTelemetryPort);
    LONGS_EQUAL(0, o.udpCommandPort);  // a port the kernel picks
    STRCMP_EQUAL("127.0.0.1", o.udpCommandHost.c_str());
    MissionOptions both;
    CHECK(ParseOutcome::kRun == parse({"--udp-telemetry", "10.1.2.3:65535", "--udp-commands", "1234"}, &both, &error));
    STRCMP_EQUAL("10.1.2.3", both.udpTelemetryHost.c_str());
    LONGS_EQUAL(65535, both.udpTelemetryPort);
    STRCMP_EQUAL("127.0.0.1", both.udpCommandHost.c_str());
    LONGS_EQUAL(1234, both.udpCommandPort);
    CHECK(ParseOutcome::kRun == parse({"--udp-commands", "0.0.0.0:1240", "--udp-telemetry", "127.0.0.1:1235"}, &both,
                                      &error));
    STRCMP_EQUAL("0.0.0.0", both.udpCommandHost.c_str());
    LONGS_EQUAL(1240, both.udpCommandPort);

    const struct {
        const char* option;
        const char* value;
        const char* why;
    } bad[] = {
        {"--udp-telemetry", "localhost:1235", "'localhost' is not a numeric IPv4 address"},
        {"--udp-telemetry", ":1235", "'' is not a numeric IPv4 address"},
        {"--udp-telemetry", "1.2.3:1235", "'1.2.3' is not a numeric IPv4 address"},
        {"--udp-telemetry", "127.0.0.1", "expected HOST:PORT"},
        {"--udp-telemetry", "1235", "expected HOST:PORT"},
        {"--udp-telemetry", "127.0.0.1:0", "'0' is not a port in 1..65535"},
        {"--udp-telemetry", "127.0.0.1:65536", "'65536' is not a port in 1..65535"},
        {"--udp-telemetry", "127.0.0.1:-5", "'-5' is not a port"},
        {"--udp-telemetry", "127.0.0.1:12x", "'12x' is not a port"},
        {"--udp-commands", "host:1234", "'host' is not a numeric IPv4 address"},
        {"--udp-commands", "0", "'0' is not a port in 1..65535"},
    };
    for (const auto& b : bad) {
        MissionOptions fresh;
        error.clear();
        if (parse({"--udp-telemetry", "127.0.0.1:1235", b.option, b.value}, &fresh, &error) !=
            ParseOutcome::kUsageError) {
            FAIL((std::string(b.option) + " " + b.value + " was accepted").c_str());
        }
        CHECK_TEXT(contains(error, b.option) && contains(error, b.why), error.c_str());
    }
    // A command port with nowhere to send telemetry, or on the telemetry's own address.
    MissionOptions alone;
    CHECK(ParseOutcome::kUsageError == parse({"--udp-commands", "1234"}, &alone, &error));
    CHECK_TEXT(contains(error, "--udp-commands is the UDP link's command port: it wants --udp-telemetry"),
               error.c_str());
    for (const char* commands : {"1235", "127.0.0.1:1235", "0.0.0.0:1235"}) {
        MissionOptions loop;
        CHECK(ParseOutcome::kUsageError ==
              parse({"--udp-telemetry", "127.0.0.1:1235", "--udp-commands", commands}, &loop, &error));
        CHECK_TEXT(contains(error, "telemetry would come back as commands"), error.c_str());
    }
    MissionOptions elsewhere;
    CHECK(ParseOutcome::kRun == parse({"--udp-telemetry", "10.0.0.9:1235", "--udp-commands", "1235"}, &elsewhere, &error));
}

// The dictionary's GOTO ranges, at their edges: x and y in [-10000, 10000],
// risk in [1e-9, 0.49] (the planner needs < 0.5).
TEST(MissionOptions, TheGotoRangesAreTheDictionarysAtTheirEdges) {
    for (const char* good : {"10000,-10000,0.49", "-10000,10000,1e-9", "0,0"}) {
        MissionOptions fresh;
        if (parse({"--goto", good}, &fresh, &error) != ParseOutcome::kRun) {
            FAIL(("--goto " + std::string(good) + " was refused: " + error).c_str());
        }
    }
    const struct {
        const char* value;
        const char* why;
    } bad[] = {
        {"10000.5,0", "--goto '10000.5,0': "},
        {"0,-10001", "--goto '0,-10001': "},
        {"0,0,0.5", "--goto '0,0,0.5': "},
        {"0,0,9e-10", "--goto '0,0,9e-10': "},
    };
    for (const auto& b : bad) {
        MissionOptions fresh;
        error.clear();
        if (parse({"--goto", b.value}, &fresh, &error) != ParseOutcome::kUsageError) {
            FAIL(("--goto " + std::string(b.value) + " was accepted").c_str());
        }
        CHECK_TEXT(error.rfind(b.why, 0) == 0, error.c_str());  // the option and the value first
        CHECK_TEXT(error.find('\n') == std::string::npos, error.c_str());  // one line: no encoder usage after it
        CHECK_TRUE(fresh.gotoArgs.empty());
    }
    // The later of two --goto wins.
    CHECK(ParseOutcome::kRun == parse({"--goto", "1,1", "--goto", "2,-2,0.2"}, &o, &error));
    checkGotoArgs(o, 2.0, -2.0, 0.2);
}

// The duration in (0, 1e6] s, the command time in [0, 1e5] s: the edges.
TEST(MissionOptions, TheDurationAndTheCommandTimeAreTakenToTheirEdges) {
    CHECK(ParseOutcome::kRun == parse({"--duration", "1e6", "--command-at", "0"}, &o, &error));
    DOUBLES_EQUAL(1e6, o.durationS, 0.0);
    DOUBLES_EQUAL(0.0, o.commandAtS, 0.0);
    CHECK(ParseOutcome::kRun == parse({"--duration", "0.01", "--command-at", "1e5"}, &o, &error));
    DOUBLES_EQUAL(0.01, o.durationS, 0.0);
    DOUBLES_EQUAL(1e5, o.commandAtS, 0.0);
    CHECK(ParseOutcome::kUsageError == parse({"--duration", "0"}, &o, &error));
    STRCMP_EQUAL("--duration '0' is not a number of seconds in (0, 1e6]", error.c_str());
    CHECK(ParseOutcome::kUsageError == parse({"--command-at", "100000.5"}, &o, &error));
    STRCMP_EQUAL("--command-at '100000.5' is not a number of seconds in [0, 1e5]", error.c_str());
}

// --report wants a folder; --no-report clears one given before it.
TEST(MissionOptions, AnEmptyReportFolderIsRefusedAndNoReportClearsOne) {
    CHECK(ParseOutcome::kUsageError == parse({"--report", ""}, &o, &error));
    STRCMP_EQUAL("--report wants a folder", error.c_str());
    MissionOptions cleared;
    CHECK(ParseOutcome::kRun == parse({"--report", "there", "--no-report"}, &cleared, &error));
    CHECK_TRUE(cleared.reportDir.empty());
    CHECK_TRUE(cleared.noReport);
}

// A [mission] goal the dictionary refuses is the scenario's error, named by
// its file; nothing is set.
TEST(MissionOptions, AScenarioGoalOutOfTheDictionarysRangeIsRefusedWithTheFile) {
    sim::Scenario s = scenarioWithGoal();
    s.mission.goalX = 20000.0;
    CHECK_FALSE(sim::applyScenarioMission(s, &o, &error));
    CHECK_TEXT(error.rfind("own.toml: [mission]: ", 0) == 0, error.c_str());
    CHECK_TEXT(contains(error, "GOTO: ") && contains(error, "20000 is out of range -10000..10000"), error.c_str());
    CHECK_TRUE(o.gotoArgs.empty());
    s.mission.goalX = 12.5;
    s.mission.riskBound = 0.6;
    CHECK_FALSE(sim::applyScenarioMission(s, &o, &error));
    CHECK_TEXT(contains(error, "risk") && contains(error, "0.6 is out of range"), error.c_str());
}

// A plan given once is kept: a second application (the runner may be handed
// options already filled) changes neither the plan nor the duration.
TEST(MissionOptions, APlanAlreadyAppliedIsKept) {
    sim::Scenario s = scenarioWithGoal();
    o.planText = "plan mine\nend\n";
    o.planFile = "mine.plan";
    o.risk = 2e-3;
    o.durationS = 40.0;
    CHECK_TRUE(sim::applyScenarioMission(s, &o, &error));
    STRCMP_EQUAL("plan mine\nend\n", o.planText.c_str());
    STRCMP_EQUAL("mine.plan", o.planFile.c_str());
    DOUBLES_EQUAL(2e-3, o.risk, 0.0);
    DOUBLES_EQUAL(40.0, o.durationS, 0.0);
    CHECK_TRUE(o.gotoArgs.empty());
}

// name=value with the shortest text that reads back as the value (15 digits
// when they do, else 16 or 17): what the operator would type.
TEST(MissionOptions, TheEncodersArgumentIsTheShortestTextThatReadsBack) {
    STRCMP_EQUAL("x=20", sim::encoderArgument("x", 20.0).c_str());
    STRCMP_EQUAL("y=-1.5", sim::encoderArgument("y", -1.5).c_str());
    STRCMP_EQUAL("risk=0.001", sim::encoderArgument("risk", 1e-3).c_str());
    STRCMP_EQUAL("risk=1e-05", sim::encoderArgument("risk", 1e-5).c_str());
    STRCMP_EQUAL("x=0.1", sim::encoderArgument("x", 0.1).c_str());
    STRCMP_EQUAL("x=0.3333333333333333", sim::encoderArgument("x", 1.0 / 3.0).c_str());  // 16 digits
    STRCMP_EQUAL("x=0.30000000000000004", sim::encoderArgument("x", 0.1 + 0.2).c_str());  // 17 digits
}

// The usage text names every option rse-demo takes, with the defaults and
// the pace's range filled in.
TEST(MissionOptions, TheUsageTextNamesEveryOptionAndItsDefaults) {
    std::FILE* out = std::tmpfile();
    CHECK(out != nullptr);
    sim::printMissionUsage(out);
    const std::string text = readAll(out);
    std::fclose(out);
    CHECK_TRUE(text.rfind("usage: rse-demo ", 0) == 0);
    for (const char* option : {"--scenario FILE", "--no-faults", "--goto X,Y[,RISK]", "--duration SECONDS",
                               "--command-at SECONDS", "--quiet", "--report DIR", "--no-report", "--any-outcome",
                               "--pace F", "--udp-telemetry HOST:PORT", "--udp-commands [ADDR:]PORT",
                               "-h, --help"}) {
        CHECK_TEXT(contains(text, option), option);
    }
    CHECK_TRUE(contains(text, "(default sim_stub/scenarios/demo_mission.toml)"));
    CHECK_TRUE(contains(text, "(default build/mission)"));
    CHECK_TRUE(contains(text, "0.1..1000"));
    CHECK_TRUE(contains(text, "(ADDR default 127.0.0.1"));
    CHECK_TRUE(contains(text, "2 bad usage"));
}
