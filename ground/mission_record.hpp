// What a mission was, as plain data: the ten points of the RSE demonstration
// (ground/mission_points.hpp finds them), the plans the deliberative layer
// made, the tracks, the hazards seen, the counters and the per-task timing.
// ground/mission_report.hpp writes it as build/mission/report.md and
// build/mission/map.svg.
//
// Whoever fills it decides where each part comes from: rse-demo's mission
// runner (sim_stub/lockstep/mission_runner.hpp) fills it from the software bus
// and the event log it watches, the simulator's truth (the driven track and the
// hidden rocks, which no flight telemetry has) and the executive's task
// statistics; a ground station could fill the same record from downlinked
// telemetry (EVENT, PLAN, ROVER_STATE, HEALTH, TASK_TIMING), leaving out what
// the rover does not send (the truth; the plans' means and covariances).
// Nothing here refers to the lockstep rig or the simulator.
//
// Host only (std::string, std::vector).
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <string>
#include <vector>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::ground {

constexpr int kMissionPointCount = 10;

// One flight event as the ground sees it (an EVENT packet with its EVENT_DATA,
// or the event log). Decisions read its numbers, by name; its text is quoted
// to people, never parsed (rewording an event changes no reading of it).
struct FlightEvent {
    double timeS = 0.0;
    std::uint16_t id = 0;
    std::uint8_t severity = 0;  // core::Severity
    std::string text;
    // Its numbers in the dictionary's order (fsw/cmdtlm/dictionary.def, Event
    // data); count 0: the event carries none, or they were lost on the way.
    core::EventData data;

    // The numbers by name, e.g. cmdtlm::event_data::LEG_SENT: false when this
    // event is not of that layout or its numbers did not come.
    template <typename Layout>
    bool read(Layout* out) const {
        return out->unpack(id, data);
    }
};

// One of the ten points, when the flight software's own output showed it.
struct MissionPoint {
    int number = 0;           // 1 .. 10
    bool seen = false;
    double timeS = 0.0;       // simulated (flight) time of the output that showed it
    std::string layer;        // "operator", "deliberative", "habitual", "estimator + deliberative", ...
    std::string what;         // what happened, from the flight software's events
    double xM = 0.0;          // where: the rover's estimated position then (hasPlace)
    double yM = 0.0;
    bool hasPlace = false;
    // Named figures behind the words ("power bound before W", "fail-ups", ...),
    // for tests and tables; see ground/mission_points.hpp for each point's.
    std::map<std::string, double> facts;
};

struct TrackPoint {
    double timeS = 0.0;
    double xM = 0.0;
    double yM = 0.0;
};

// A plan the deliberative layer made: its problem (start, covariance, noise,
// obstacles, risk bound) and its mean path, for the risk ellipses.
struct PlanDrawing {
    double timeS = 0.0;
    deliberative::CcProblem problem{};
    deliberative::CcPlan plan{};
};

// A hazard disc the habitual layer reported (event 816) and whether it is on
// the coarse map (known) or not (hidden).
struct HazardSeen {
    std::uint8_t id = 0;
    double timeS = 0.0;
    double xM = 0.0;
    double yM = 0.0;
    double radiusM = 0.0;
    bool hidden = false;
};

// A flight-software decision worth a line in the report (fail-up, relaxation,
// replan, call home), with the event's own text.
struct MissionDecision {
    double timeS = 0.0;
    std::string kind;  // "fail-up", "bound relaxed", "risk relaxed", "replan", "call home", ...
    std::string text;
};

struct TaskTimingRow {
    std::string name;
    std::uint32_t runs = 0;
    std::uint32_t overBudget = 0;
    double budgetUs = 0.0;
    double meanUs = 0.0;      // on the executive's clock
    double maxUs = 0.0;
    double hostMeanUs = 0.0;  // host wall time
    double hostMaxUs = 0.0;
};

// A leg as handed down (event 905) and how it ended.
struct LegRecord {
    std::uint32_t legId = 0;
    double sentS = 0.0;
    double xM = 0.0, yM = 0.0;
    double lengthBoundM = 0.0;
    double energyBoundJ = 0.0;
    double powerBoundW = 0.0;
    std::string outcome;       // "achieved", "failed up: power", "superseded", "" (open)
    double drivenM = 0.0;      // the habitual layer's count at "achieved" (event 808)
    double drivenJ = 0.0;
};

struct MissionRecord {
    // What was asked.
    std::string scenario;        // name and file
    double goalX = 0.0, goalY = 0.0, riskBound = 0.0;
    tables::CoarseMapTable map{};
    double footprintRadiusM = 0.0;
    // Truth the flight software never had (empty from telemetry): the hidden
    // rocks' polygons, the driven track.
    std::vector<std::vector<geometry::Point2>> hiddenRocks;
    std::vector<TrackPoint> truthTrack;
    std::vector<TrackPoint> estimatedTrack;
    std::vector<PlanDrawing> plans;
    std::vector<HazardSeen> hazards;
    // Site mode (docs/site_map.md): the site map's rocks the rover had, and
    // every global route it found (ROUTE telemetry), in order.
    std::vector<std::vector<geometry::Point2>> siteRocks;
    std::vector<std::vector<geometry::Point2>> routes;

    // The ten points and the verdict.
    std::array<MissionPoint, kMissionPointCount> points{};
    bool allInOrder = false;
    std::string verdict;         // "all in order" or what is missing / out of order

    // How it went.
    std::string outcome;         // "goal reached at 98.2 s", "called home at 104.7 s: ..."
    double endTimeS = 0.0;
    std::vector<LegRecord> legs;
    std::vector<MissionDecision> decisions;
    std::uint32_t legsSent = 0, legsAchieved = 0, failUps = 0, replans = 0;
    std::uint32_t boundRelaxations = 0, riskRelaxations = 0, callHomes = 0, habitualReplans = 0;
    double energyWh = -1.0;      // truth (battery), -1 unknown
    double drivenM = -1.0;       // truth, -1 unknown
    std::uint32_t collisions = 0;
    double leastClearanceM = -1.0;
    std::vector<TaskTimingRow> timing;
};

}  // namespace rse::ground
