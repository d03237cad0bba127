#include "sim_stub/lockstep/plan_uplink.hpp"

#include <cstdio>
#include <memory>
#include <sstream>
#include <vector>

#include "ground/command_encoder.hpp"
#include "ground/plan_transfer.hpp"
#include "sim_stub/lockstep/flight_watch.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"

namespace rse::sim {

bool planPassesGroundCheck(const MissionOptions& o, std::string* error) {
    std::ostringstream checkOut;
    std::ostringstream checkErr;
    const auto components = std::make_unique<plan_executive::SelectionInput>();
    if (ground::checkPlanForUplink(o.planText, o.planFile, ground::kPlanUploadBytes, *components, false, checkOut,
                                   checkErr) != 0) {
        *error = "the plan did not pass the ground check: " + checkErr.str();
        return false;
    }
    return true;
}

bool uplinkPlan(const MissionOptions& o, MemoryGround& ground, LockstepRig& rig, const FlightWatch& watch,
                const std::function<void()>& service, std::string* error) {
    std::vector<std::uint8_t> risk;
    try {
        risk = ground::encodeArguments(*ground::lookupCommand("SET_RISK_BOUND"), {encoderArgument("risk", o.risk)});
    } catch (const ground::CommandError& e) {
        *error = e.what();
        return false;
    }
    const std::uint32_t accepted = watch.planExec().plansAccepted;
    const std::uint32_t refused = watch.planExec().plansRefused;
    const auto step = [&](core::TimeNs t) { (void)rig.runUntil([&] { service(); return false; }, t); };
    if (!ground.send("SET_RISK_BOUND", risk.data(), risk.size())) {
        *error = "SET_RISK_BOUND could not be sent";
        return false;
    }
    step(20 * core::kNsPerMs);
    for (const std::vector<std::uint8_t>& chunk : ground::planLoadChunks(o.planText)) {
        if (!ground.send("PLAN_LOAD", chunk.data(), chunk.size())) {
            *error = "PLAN_LOAD could not be sent";
            return false;
        }
        step(20 * core::kNsPerMs);
    }
    const std::vector<std::uint8_t> start = ground::planStartArgs(o.planText);
    if (!ground.send("PLAN_START", start.data(), start.size())) {
        *error = "PLAN_START could not be sent";
        return false;
    }
    const auto verdict = static_cast<core::TimeNs>(ground::kPlanVerdictSeconds * 1e9);
    (void)rig.runUntil(
        [&] {
            service();
            return watch.planExec().plansAccepted != accepted || watch.planExec().plansRefused != refused;
        },
        verdict);
    if (watch.planExec().plansRefused != refused) {
        *error = "the plan executive refused the plan: " + watch.planRefusal();
        return false;
    }
    if (watch.planExec().plansAccepted == accepted) {
        char why[80];
        std::snprintf(why, sizeof why, "no verdict from the plan executive within %.0f s", ground::kPlanVerdictSeconds);
        *error = why;
        return false;
    }
    return true;
}

}  // namespace rse::sim
