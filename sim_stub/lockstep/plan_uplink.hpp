// A plan mission's plan from the operator to the flight software, as
// `rse-ground plan load` sends it: checked on the ground first, then the
// operator's risk bound, the plan's PLAN_LOAD chunks and PLAN_START through the
// authenticated in-memory ground link (MemoryGround), and the plan executive's
// verdict read from its status and events (FlightWatch).
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <functional>
#include <string>

#include "sim_stub/lockstep/mission_options.hpp"

namespace rse::sim {

class FlightWatch;
class LockstepRig;
class MemoryGround;

// The plan (options.planText from options.planFile) checked on the ground
// before anything is sent, as `rse-ground plan load` does: its size, the
// flight parser and method selection with every component ok. False with the
// reason in *error.
bool planPassesGroundCheck(const MissionOptions& options, std::string* error);

// The uplink once the plan passed the ground's check: SET_RISK_BOUND (the
// bound the plan's drives get), PLAN_LOAD chunks (one every 20 ms: at most one
// a frame, a few between two runs of the executive), PLAN_START with the
// text's length and CRC-32, and the executive's verdict. service runs once a
// frame (the mission's: downlink, watch, recorder). False with the reason in
// *error.
bool uplinkPlan(const MissionOptions& options, MemoryGround& ground, LockstepRig& rig, const FlightWatch& watch,
                const std::function<void()>& service, std::string* error);

}  // namespace rse::sim
