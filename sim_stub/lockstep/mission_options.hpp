// What the lockstep mission flies (rse-demo's command line, and the scenario's
// [mission] where the command line says nothing): MissionOptions, its parser
// and the usage text. The command line follows docs/operations.md, "Command
// lines" (getopt_long, sim_stub/cli/command_line.hpp). The goal is checked
// with the ground's command encoder (the dictionary's ranges), as rse-ground
// would check it.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdint>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

class LockstepRig;

constexpr const char* kDefaultMissionScenario = "sim_stub/scenarios/demo_mission.toml";
constexpr const char* kDefaultReportDir = "build/mission";
// A scenario without [mission]: the demo's goal and duration.
constexpr double kDefaultGoalX = 20.0;
constexpr double kDefaultGoalY = 0.0;
constexpr double kDefaultMissionDurationS = 180.0;
// --pace: the factors over real time accepted.
constexpr double kMinPace = 0.1;
constexpr double kMaxPace = 1000.0;
constexpr const char* kDefaultUdpCommandHost = "127.0.0.1";

// What the mission is: the command line's (parseMissionArgs), and where it
// says nothing, the scenario's own [mission] (applyScenarioMission, which
// runMission calls once the scenario is loaded): a goal (GOTO) or a mission
// plan (PLAN_LOAD, PLAN_START) at a risk bound, and a duration.
struct MissionOptions {
    std::string scenarioPath = kDefaultMissionScenario;
    bool clearFaults = false;  // --no-faults: the scenario's faults left out
    double goalX = kDefaultGoalX;  // --goto X,Y[,RISK], or the scenario's
    double goalY = kDefaultGoalY;
    double risk = kDefaultMissionRiskBound;  // GOTO's, or a plan mission's SET_RISK_BOUND
    // Simulated seconds, boot included (--duration); 0: the scenario's
    // duration_s when it has a [mission], else kDefaultMissionDurationS.
    double durationS = 0.0;
    // --command-at SECONDS: SET_MODE and GOTO (or the plan) wait until this
    // simulated time (0: as soon as the drives are up and the map uploaded,
    // about 0.5 s). A ground on a real bus commands later (the vcan mission's
    // GOTO came at about 2 s); this runs the lockstep mission so.
    double commandAtS = 0.0;
    bool quiet = false;        // no console lines (the summary is still written)
    // --report DIR: report.md and map.svg there; "" writes none. rse-demo's
    // main (missionMain) makes it kDefaultReportDir unless --no-report is given;
    // runMission itself writes only when told where.
    std::string reportDir;
    bool noReport = false;     // --no-report
    bool anyOutcome = false;   // --any-outcome: exit 0 even when the ten points are not all in order
    // The GOTO argument bytes (the ground's encoder): --goto's, or empty for
    // the scenario's goal (or the default, 20,0,1e-3).
    std::vector<std::uint8_t> gotoArgs;
    // A plan mission (the scenario's [mission] plan_file, when no --goto):
    // the text and the file it came from.
    std::string planText;
    std::string planFile;
    // Tests and benchmarks: changes to the loaded scenario (seed, faults, start)
    // before the rig is built; applied after --no-faults.
    std::function<void(Scenario&)> editScenario;
    // Changes to what the operator uplinks as COARSE_MAP (by default the
    // scenario's site and known rocks): an orbital survey that covers less
    // than the world, a rock the survey placed wrong.
    std::function<void(Scenario&)> editUplinkedMap;
    // --pace F: the frames paced against the wall clock, F times faster than
    // real time (frame k of the run due at start + k x 10 ms / F; a frame
    // reached late runs at once and is counted, MissionSummary::framesBehind).
    // 0: as fast as the CPU allows (the default, and rse-montecarlo's).
    double pace = 0.0;
    // --udp-telemetry HOST:PORT: rse-fsw's UDP ground link (hal::UdpPacketLink)
    // added to the flight software beside the in-memory ground, so every
    // telemetry packet and event also goes to HOST:PORT as datagrams (for
    // rse-ground watch / serve). Empty host: no UDP link.
    std::string udpTelemetryHost;
    std::uint16_t udpTelemetryPort = 0;
    // --udp-commands [ADDR:]PORT: where that link takes commands (default
    // address 127.0.0.1). The link always binds a command socket; without this
    // option it binds 127.0.0.1 port 0, a port the kernel picks and nobody is told.
    std::string udpCommandHost = kDefaultUdpCommandHost;
    std::uint16_t udpCommandPort = 0;
    // Tools (rse-montecarlo): called once the rig is up and then after every
    // frame, to read what they measure of the flight software and the
    // simulator; it must change neither.
    std::function<void(LockstepRig&)> onFrame;
};

enum class ParseOutcome : std::uint8_t { kRun, kHelp, kUsageError };

// rse-demo's command line (argv[0] is the program; argv is not written). The
// goal is checked with the ground's command encoder (the dictionary's
// ranges), as rse-ground would; on kUsageError *error says why, naming the
// option and the value (without the program's name).
ParseOutcome parseMissionArgs(int argc, const char* const* argv, MissionOptions* options, std::string* error);
// Fills what the command line left open from the scenario's [mission]: the
// duration when 0; the goal and risk bound (encoded as GOTO) or the plan when
// neither gotoArgs nor planText is set; without [mission], 20,0,1e-3 and
// 180 s. False (why in *error) when the goal does not encode.
bool applyScenarioMission(const Scenario& scenario, MissionOptions* options, std::string* error);
void printMissionUsage(std::FILE* out);

// name=value for the ground's command encoder: the shortest text that reads
// back as v (the operator's GOTO and SET_RISK_BOUND arguments).
std::string encoderArgument(const char* name, double v);

}  // namespace rse::sim
