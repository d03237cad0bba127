// The autonomous mission in lockstep (rse-demo, `make demo`): the flight
// software and the simulator booted on one virtual clock (LockstepRig), the
// drives brought up, then the operator's commands - the scenario's COARSE_MAP,
// SET_MODE AUTONOMOUS and GOTO x,y,risk (or, for a plan mission, SET_RISK_BOUND
// and the plan as PLAN_LOAD chunks and PLAN_START), authenticated with the lab
// key - through the in-memory ground link (MemoryGround), never on the
// software bus. The run lasts until the deliberative layer publishes
// (PlanStatusMsg) that every goal is reached or that it called home (a plan
// mission: until the plan executive publishes its plan complete or failed),
// or fault protection calls home, plus kMissionTailNs so the last events
// reach the console; or until the duration. The simulator's truth is read only for the
// summary at the end (and the report's driven track and hidden rocks).
//
// By default the frames run as fast as the CPU allows; MissionOptions::pace
// paces them against the wall clock, and the UDP options add rse-fsw's UDP
// ground link beside the in-memory one, so a ground (rse-ground watch, the
// mission control display) receives the telemetry as it would a rover's.
//
// The ten points of the RSE demonstration are read from the flight software's
// events and plan status as they come (MissionRecorder, ground/mission_points.hpp),
// printed as "POINT n" lines, judged ("ten points: all in order" or what is
// missing or out of order) and written with the rest of the mission to
// <reportDir>/report.md and <reportDir>/map.svg (ground/mission_report.hpp).
//
// The parts, each in its file (docs/mission.md, "rse-demo's parts"):
//   mission_options    MissionOptions: the command line and the scenario's [mission]
//   flight_watch       what the operator sees of the flight software (plan status, mode, events, marks)
//   mission_recorder   the ten points and the mission record
//   map_upload         the scenario's COARSE_MAP uplinked as TABLE_LOAD chunks
//   plan_uplink        a plan mission's ground check and PLAN_LOAD / PLAN_START
//   frame_pacer        --pace: the frames against the wall clock
//   mission_summary    MissionSummary and its printing
//   mission_runner     runMission: set-up, links, commands, frames to the outcome, the summary;
//                      and rse-demo's main (missionMain)
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdio>

#include "fsw/core/clock.hpp"
#include "sim_stub/lockstep/mission_options.hpp"
#include "sim_stub/lockstep/mission_summary.hpp"

namespace rse::sim {

constexpr core::TimeNs kMissionTailNs = 2 * core::kNsPerSec;

// Runs the mission. out gets the narration, the console (unless quiet), the
// mission summary and the flight software's timing summary (nullptr: nothing).
MissionSummary runMission(const MissionOptions& options, std::FILE* out);

// rse-demo itself: 0 when the mission ran and showed the ten points in order
// (or ran at all, with --any-outcome) or for --help (the usage on out), 3
// when it ran but the ten points were not all seen in order, 2 for a bad
// command line (one line on err says why, a second points to --help), 1 when
// the setup failed or the report could not be written.
int missionMain(int argc, const char* const* argv, std::FILE* out, std::FILE* err);

}  // namespace rse::sim
