#include "ground/mission_from_telemetry.hpp"

#include <algorithm>
#include <cstdio>
#include <map>

#include "fsw/habitual/habitual_events.hpp"
#include "ground/event_data_pairing.hpp"
#include "ground/mission_points.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

namespace {

constexpr double kMinorFrameS = 0.01;  // rse-fsw's minor frame: a state packet carries the frame before

double number(const DecodedPacket& p, const char* field, std::size_t index = 0) {
    return p.value(field, index).value_or(0.0);
}

// One decoded packet at the rover time of its content (see the header).
struct Replayed {
    double timeS = 0.0;
    int rank = 0;  // at equal times: state (0) before events (1)
    std::size_t index = 0;
};

PlanDrawing planDrawing(const DecodedPacket& p, double timeS, const tables::CoarseMapTable& map) {
    PlanDrawing d;
    d.timeS = timeS;
    deliberative::CcProblem& problem = d.problem;
    deliberative::CcPlan& plan = d.plan;
    const std::size_t steps =
        std::min<std::size_t>(static_cast<std::size_t>(number(p, "steps")), deliberative::kMaxPlanSteps);
    problem.steps = static_cast<std::uint8_t>(steps);
    plan.steps = static_cast<std::uint8_t>(steps);
    plan.status = static_cast<deliberative::CcStatus>(static_cast<int>(number(p, "status")));
    for (std::size_t i = 0; i <= steps; ++i) {
        plan.meanX[i] = number(p, "mean_x", i);
        plan.meanY[i] = number(p, "mean_y", i);
    }
    plan.riskUsed = number(p, "risk_used");
    plan.euclideanLengthM = number(p, "length");
    problem.startX = plan.meanX[0];
    problem.startY = plan.meanY[0];
    for (std::size_t i = 0; i < 4; ++i) {
        problem.startCov[i] = number(p, "start_cov", i);
    }
    problem.processSigmaM = number(p, "process_sigma");
    problem.goalX = number(p, "goal_x");
    problem.goalY = number(p, "goal_y");
    problem.riskBound = number(p, "risk_bound");
    problem.xMin = map.x_min_m;
    problem.xMax = map.x_max_m;
    problem.yMin = map.y_min_m;
    problem.yMax = map.y_max_m;
    return d;
}

std::string outcomeText(const MissionTelemetry& m) {
    char text[320];
    const double t = m.flightTime(m.outcomeMetS);
    switch (m.outcome) {
        case TelemetryOutcome::kGoalReached:
            std::snprintf(text, sizeof text, "goal reached at %.1f s", t);
            return text;
        case TelemetryOutcome::kCalledHome:
            std::snprintf(text, sizeof text, "called home at %.1f s, reason %u (%s): %s", t,
                          static_cast<unsigned>(m.callHomeReason), m.callHomeBy.c_str(), m.callHomeEvent.c_str());
            return text;
        case TelemetryOutcome::kNone: break;
    }
    return "no outcome in the recording";
}

// The recording's packets that make the mission (events, plan paths, plan
// status, rover states, task timing) decoded, the order to replay them in (by
// rover time, state before events at equal times) and each event's numbers:
// its EVENT_DATA, paired in the order received (before the replay's sorting).
struct Replay {
    std::vector<DecodedPacket> packets;
    std::vector<Replayed> order;
    std::map<std::size_t, core::EventData> data;  // by the EVENT's index in packets
    EventDataPairing pairing;
};

void replayOrder(const SessionRecording& recording, const MissionTelemetry& mission, Replay* replay) {
    std::vector<DecodedPacket>* packets = &replay->packets;
    std::vector<Replayed>& order = replay->order;
    packets->reserve(recording.packets.size());
    for (const RecordedPacket& rp : recording.packets) {
        DecodedPacket p = decodeTelemetry(rp.bytes);
        if (!p.ok) {
            continue;
        }
        const std::string kind = p.name();
        Replayed item;
        item.index = packets->size();
        EventDataPacket data;
        if (readEventData(p, &data)) {
            if (const std::optional<std::size_t> event = replay->pairing.onData(data)) {
                replay->data[*event] = data.data;
            }
            continue;
        }
        if (kind == "EVENT") {
            item.timeS = mission.flightTime(number(p, "event_time"));
            item.rank = 1;
            replay->pairing.onEvent(static_cast<std::uint32_t>(number(p, "event_sequence")),
                                    static_cast<std::uint16_t>(number(p, "event_id")), item.index);
        } else if (kind == "PLAN_PATH") {
            item.timeS = mission.flightTime(number(p, "plan_time"));
        } else if (kind == "ROUTE") {
            // Chunks of one route share its time: the stable sort keeps their order.
            item.timeS = mission.flightTime(number(p, "route_time"));
        } else if (kind == "PLAN" || kind == "ROVER_STATE" || kind == "TASK_TIMING") {
            item.timeS = mission.flightTime(p.met) - kMinorFrameS;
        } else {
            continue;
        }
        order.push_back(item);
        packets->push_back(std::move(p));
    }
    std::stable_sort(order.begin(), order.end(), [](const Replayed& a, const Replayed& b) {
        return a.timeS < b.timeS || (a.timeS == b.timeS && a.rank < b.rank);
    });
}

FlightEvent flightEvent(const DecodedPacket& p, double timeS, const core::EventData* data) {
    FlightEvent e;
    if (data != nullptr) {
        e.data = *data;
    }
    e.timeS = timeS;
    e.id = static_cast<std::uint16_t>(number(p, "event_id"));
    e.severity = static_cast<std::uint8_t>(number(p, "severity"));
    if (const DecodedField* f = p.field("text"); f != nullptr) {
        e.text = f->text;
    }
    return e;
}

TaskTimingRow taskTimingRow(const DecodedPacket& p) {
    TaskTimingRow row;
    if (const DecodedField* f = p.field("task_name"); f != nullptr) {
        row.name = f->text;
    }
    row.runs = static_cast<std::uint32_t>(number(p, "runs"));
    row.overBudget = static_cast<std::uint32_t>(number(p, "over_budget"));
    row.meanUs = number(p, "mean_us");
    row.maxUs = number(p, "max_us");
    row.hostMeanUs = number(p, "cpu_mean_us");
    row.hostMaxUs = number(p, "cpu_max_us");
    return row;
}

}  // namespace

TelemetryMissionRecord missionRecordFromTelemetry(const SessionRecording& recording, const MissionTelemetry& mission,
                                                  const tables::CoarseMapTable& map, double footprintRadiusM,
                                                  const std::string& name) {
    TelemetryMissionRecord out;
    MissionRecord& r = out.record;

    Replay replay;
    replayOrder(recording, mission, &replay);
    const std::vector<DecodedPacket>& packets = replay.packets;

    TenPointTracker tracker(map, footprintRadiusM);
    std::map<unsigned, TaskTimingRow> timing;  // by task index
    std::uint32_t habitualReplans = 0;
    for (const Replayed& item : replay.order) {
        const DecodedPacket& p = packets[item.index];
        const std::string kind = p.name();
        if (kind == "EVENT") {
            const auto data = replay.data.find(item.index);
            const FlightEvent e = flightEvent(p, item.timeS, data == replay.data.end() ? nullptr : &data->second);
            habitualReplans += e.id == habitual::events::kMinorAnomaly ? 1U : 0U;
            tracker.onEvent(e);
        } else if (kind == "PLAN") {
            tracker.onCallHomeReason(static_cast<std::uint8_t>(number(p, "call_home")));
        } else if (kind == "ROVER_STATE") {
            if (number(p, "estimate_valid") != 0.0) {
                tracker.onPose(item.timeS, number(p, "x"), number(p, "y"));
                r.estimatedTrack.push_back(TrackPoint{item.timeS, number(p, "x"), number(p, "y")});
            }
        } else if (kind == "PLAN_PATH") {
            r.plans.push_back(planDrawing(p, item.timeS, map));
            ++out.plansDrawn;
        } else if (kind == "ROUTE") {
            // Chunks in order, chunk 0 first: a first chunk starts a route.
            if (number(p, "chunk_index") == 0.0 || r.routes.empty()) {
                r.routes.emplace_back();
            }
            const auto count = static_cast<std::size_t>(number(p, "count"));
            for (std::size_t k = 0; k < count && k < 32; ++k) {
                r.routes.back().push_back(geometry::Point2{number(p, "x", k), number(p, "y", k)});
            }
        } else if (kind == "TASK_TIMING") {
            timing[static_cast<unsigned>(number(p, "task_index"))] = taskTimingRow(p);  // the latest
        }
        for (const MissionPoint& point : tracker.takeNew()) {
            out.pointsInOrder.push_back(point);
        }
    }

    tracker.fill(&r);
    r.scenario = name;
    r.goalX = mission.goalX;
    r.goalY = mission.goalY;
    r.riskBound = mission.riskBound;
    r.map = map;
    r.footprintRadiusM = footprintRadiusM;
    r.outcome = outcomeText(mission);
    r.endTimeS = mission.lastMetS >= 0.0 ? mission.flightTime(mission.lastMetS) : 0.0;
    r.legsSent = mission.legsSent;
    r.legsAchieved = mission.legsAchieved;
    r.failUps = mission.failUps;
    r.replans = mission.replans;
    r.boundRelaxations = mission.boundRelaxations;
    r.riskRelaxations = mission.riskRelaxations;
    r.callHomes = mission.callHomes;
    r.habitualReplans = habitualReplans;
    out.eventDataPaired = replay.pairing.paired();
    out.eventsWithoutData = replay.pairing.missing();
    out.eventDataStray = replay.pairing.stray();
    for (const auto& [index, row] : timing) {
        (void)index;
        r.timing.push_back(row);
    }
    return out;
}

}  // namespace rse::ground
