// rse-ground summary and report: a session recording (rse-ground record) read
// back, offline: the mission its telemetry shows (ground/mission_telemetry.hpp),
// and the ten points, report.md and map.svg as rse-demo makes them
// (ground/mission_from_telemetry.hpp).
#include <fstream>
#include <optional>
#include <ostream>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/mission_from_telemetry.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_report.hpp"
#include "ground/mission_telemetry.hpp"
#include "ground/session_recording.hpp"
#include "ground/table_compiler.hpp"

namespace rse::ground {
namespace {

// A recording file for `command`: false (said on stderr) when it cannot be
// opened; its bad lines are named on stderr and skipped.
bool readRecordingFile(CliContext& cli, const char* command, const std::string& path, SessionRecording* recording) {
    std::ifstream in(path);
    if (!in) {
        cli.err() << command << ": cannot read '" << path << "'\n";
        return false;
    }
    *recording = readSessionRecording(in);
    for (const std::string& e : recording->errors) {
        cli.err() << path << ": " << e << "\n";
    }
    return true;
}

// One table image (or its .toml source) decoded and checked with the flight
// code; UsageError naming the file and what is wrong with it.
template <typename Table>
void readCheckedTable(const std::string& path, const char* tableName, Table* table) {
    std::vector<std::uint8_t> image;
    try {
        image = readTableFile(path);
    } catch (const TableSourceError& e) {
        throw UsageError(std::string("report: ") + e.what());
    }
    if (!tables::decodeTable(image.data(), image.size(), table).ok()) {
        throw UsageError("report: " + path + " is not a good " + tableName +
                         " image: " + describeCheck(image.data(), image.size()));
    }
}

// What report prints: the points as the tracker saw them, the outcome and the verdict.
void printReportLines(CliContext& cli, const TelemetryMissionRecord& result, const MissionTelemetry& mission) {
    for (const MissionPoint& p : result.pointsInOrder) {
        cli.out() << TenPointTracker::formatPoint(p) << "\n";
    }
    cli.out() << "outcome:    " << result.record.outcome << "\n";
    cli.out() << "plans:      " << result.plansDrawn << " drawn from PLAN_PATH (" << mission.plansMade
              << " made, events 902)\n";
    cli.out() << "event data: " << result.eventDataPaired << " EVENT_DATA paired, " << result.eventsWithoutData
              << " events without their numbers, " << result.eventDataStray << " stray\n";
    cli.out() << "points:     " << result.record.verdict << "\n";
}

}  // namespace

int runSummary(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("summary", words, {{"facts", 0, false}, {"no-events", 0, false}});
    expectOperands(parsed, 1, "summary", "usage: rse-ground summary FILE [--facts] [--no-events]");
    SessionRecording recording;
    if (!readRecordingFile(cli, "summary", parsed.operands[0], &recording) ||
        (recording.packets.empty() && !recording.errors.empty())) {
        return kExitLink;
    }
    const MissionTelemetry mission = readMissionTelemetry(recording);
    if (parsed.has("--facts")) {
        printMissionFacts(mission, cli.out());
    } else {
        printMissionTelemetry(mission, cli.out(), !parsed.has("--no-events"));
    }
    return kExitOk;
}

// The mission from a recording as rse-demo shows it: the ten points (printed as
// the tracker saw them, then the verdict), build/mission-style report.md and
// map.svg. The coarse map is the one the rover flew: --map (an uploaded image,
// or its .toml source), else DIR/coarse_map.toml of --tables (default
// "tables", the rover's defaults); the footprint from DIR/rover_geometry.toml.
// Exit 0 when the ten points were all seen in order, 3 when not.
int runReport(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions(
        "report", words, {{"map", 0, true}, {"tables", 0, true}, {"out", 0, true}, {"name", 0, true}});
    const std::string tablesDir = parsed.value("--tables").value_or("tables");
    const std::string mapPath = parsed.value("--map").value_or(tablesDir + "/coarse_map.toml");
    const std::string outDir = parsed.value("--out").value_or("build/mission_telemetry");
    expectOperands(parsed, 1, "report",
                   "usage: rse-ground report FILE [--map MAP] [--tables DIR] [--out DIR] [--name TEXT]");
    const std::string& path = parsed.operands[0];
    SessionRecording recording;
    if (!readRecordingFile(cli, "report", path, &recording)) {
        return kExitLink;
    }
    if (recording.packets.empty()) {
        cli.err() << "report: '" << path << "' holds no packet\n";
        return kExitLink;
    }
    tables::CoarseMapTable map{};
    tables::RoverGeometryTable geometry{};
    readCheckedTable(mapPath, "COARSE_MAP", &map);
    readCheckedTable(tablesDir + "/rover_geometry.toml", "ROVER_GEOMETRY", &geometry);
    const MissionTelemetry mission = readMissionTelemetry(recording);
    const TelemetryMissionRecord result = missionRecordFromTelemetry(
        recording, mission, map, geometry::clearanceRadiusM(geometry),
        parsed.value("--name").value_or(path + " (telemetry received on " + recording.link + ")"));
    printReportLines(cli, result, mission);
    std::string reportPath;
    std::string mapFile;
    std::string error;
    if (!writeMissionFiles(result.record, outDir, &reportPath, &mapFile, &error)) {
        cli.err() << "report: " << error << "\n";
        return kExitLink;
    }
    cli.out() << "mission report: " << reportPath << "\nmission map:    " << mapFile << "\n";
    return result.record.allInOrder ? kExitOk : kExitRejected;
}

}  // namespace rse::ground
