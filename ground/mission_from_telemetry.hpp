// The mission record (ground/mission_record.hpp) a ground station builds from
// the telemetry it received (a session recording): the ten points read by the
// same tracker rse-demo uses (ground/mission_points.hpp), from the recorded
// EVENT (with its EVENT_DATA: the event's numbers, paired by event_sequence in
// the order received; ground/event_data_pairing.hpp), PLAN and ROVER_STATE
// packets; every plan the rover made with its risk
// ellipses from PLAN_PATH; the estimated track; the counts and the per-task
// timing (TASK_TIMING). `rse-ground report` writes it with the same report and
// map writers as rse-demo (ground/mission_report.hpp), so an operator on a real
// link gets what the lockstep demo prints.
//
// What telemetry does not carry is left out and the report says so: the
// simulator's truth (the driven track, the hidden rocks' polygons, the battery's
// energy) and the task budgets (the RATE_GROUP table).
//
// Order: the packets are replayed in the rover's time order, not as received.
// A state packet (PLAN, ROVER_STATE) goes out in the frame after the one whose
// state it carries (the telemetry task runs before the layers in a frame), and
// the CAN link sends events ahead of routine telemetry; each is placed at the
// time of its content: an EVENT at its event_time, a state packet one minor frame
// before its MET, a PLAN_PATH at its plan_time; at equal times the state first,
// as rse-demo's recorder reads the bus before the event log.
//
// Host only.
#pragma once

#include <string>
#include <vector>

#include "fsw/tables/table_types.hpp"
#include "ground/mission_record.hpp"
#include "ground/mission_telemetry.hpp"
#include "ground/session_recording.hpp"

namespace rse::ground {

struct TelemetryMissionRecord {
    MissionRecord record;
    std::vector<MissionPoint> pointsInOrder;  // as the tracker saw them
    std::size_t plansDrawn = 0;               // PLAN_PATH packets received
    // The events' numbers (EVENT_DATA, paired by event_sequence): paired, events
    // read without them (lost or withheld: such an event shows no point), stray.
    std::uint32_t eventDataPaired = 0;
    std::uint32_t eventsWithoutData = 0;
    std::uint32_t eventDataStray = 0;
};

// map: the coarse map the rover flew (the COARSE_MAP uploaded, or its default):
// what tells a hidden obstacle from a known rock. footprintRadiusM: the rover's
// clearance radius (ROVER_GEOMETRY). name: the mission's name for the report.
TelemetryMissionRecord missionRecordFromTelemetry(const SessionRecording& recording, const MissionTelemetry& mission,
                                                  const tables::CoarseMapTable& map, double footprintRadiusM,
                                                  const std::string& name);

}  // namespace rse::ground
