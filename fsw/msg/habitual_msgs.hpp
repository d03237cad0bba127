// The deliberative <-> habitual boundary: one leg at a time, with the
// constraints the deliberative layer planned it under, and the habitual layer's
// report back (achieved, or failed up with the violated constraint and by how much).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

// Drive to (goalXM, goalYM) within the bounds. legId 0 cancels: stop safely and wait.
// arriveWithinM: the leg is achieved once the rover stands within
// max(HABITUAL.goal_tolerance_m, arriveWithinM) of the point (the habitual
// layer stops short on the way in rather than driving to the point); 0, as on
// every leg but a region goal's last: the table's tolerance. Finite, >= 0, at
// most kMaxGoalRadiusM (goal_msgs.hpp), else the leg is refused.
struct LegCommandMsg {
    static constexpr core::MsgId kMsgId = ids::kLegCommand;
    std::int64_t timeNs;
    std::uint32_t legId;       // nonzero and new for every leg; 0: cancel the current leg
    std::uint8_t finalLeg;     // 1: the last leg of the plan (arrive and stay)
    std::uint8_t pad[3];
    double goalXM;
    double goalYM;
    double maxPathLengthM;     // not to exceed: path length of the local plan
    double maxEnergyJ;         // not to exceed: energy the drives may draw on this leg
    double maxPowerW;          // not to exceed: power the drives draw at the cruise speed (0: no power bound)
    double arriveWithinM;      // the goal region's radius on a goal's last leg (0: the point)
};

enum class HabitualState : std::uint8_t {
    kIdle = 0,        // waiting for a leg
    kPlanning = 1,    // RRT* running for a new leg
    kDriving = 2,     // trajectory sent, the reflexive layer follows it
    kRepairing = 3,   // a constraint was predicted violated, or the path blocked: planning again
    kFailedUp = 4,    // repair failed: rover stopped, waiting for the deliberative layer
    kAchieved = 5,    // waypoint reached: waiting for the next leg
};

// Which constraint a fail-up is about.
enum class LegConstraint : std::uint8_t {
    kNone = 0,
    kPathLength = 1,   // predicted path length above the allowed length
    kEnergy = 2,       // predicted drive energy above the allowed energy
    kNoPath = 3,       // no collision-free path to the waypoint found within the budget
    kCannotFollow = 4, // the reflexive layer could not follow the trajectory
    kBadLeg = 5,       // the leg command was refused (non-finite, non-positive bound, off the map)
    kPower = 6,        // the drives' predicted power at the cruise speed above the allowed power (no path can
                       // mend it: failed up at once)
};

// Published on every state change and at 1 Hz.
struct LegReportMsg {
    static constexpr core::MsgId kMsgId = ids::kLegReport;
    std::int64_t timeNs;
    std::uint32_t legId;            // the leg this is about (0: none yet)
    HabitualState state;
    LegConstraint violated;         // kNone unless state is kFailedUp
    std::uint8_t pad[2];
    double predictedLengthM;        // of the best local plan (0 if none)
    double allowedLengthM;          // maxPathLengthM less the table's distance margin
    double predictedEnergyJ;        // of the best local plan with the drives' estimated power factors
    double allowedEnergyJ;          // maxEnergyJ less the table's power margin
    double predictedPowerW;         // the drives' power at the cruise speed with their estimated power factors
    double allowedPowerW;           // maxPowerW less the table's power margin (0: the leg has no power bound)
    double excess;                  // by how much the violated constraint is exceeded (m, J or W; 0 otherwise)
    std::uint32_t legsAchieved;
    std::uint32_t failUps;
    std::uint32_t replans;          // local replans (new obstacle on the path, or repair)
    std::uint32_t minorAnomalies;   // replans that kept the constraints: logged, not failed up
};

// What the rover has seen that the coarse map does not show: the hazard discs
// the habitual layer remembers (map_builder.hpp), so that a replan after a
// fail-up plans round them and puts no leg end inside one. Site frame; the
// radius is the remembered disc's, not grown by the rover's footprint.
constexpr std::size_t kMaxKnownHazards = 32;  // the habitual layer's disc table (kMaxMapDiscs)

struct KnownHazard {
    float xM;
    float yM;
    float radiusM;
    std::uint8_t obstacleId;   // the hazard detector's id; 0: a contact the follower felt (ContactMsg), no sighting
    std::uint8_t pad[3];
};

// Published when the remembered set changes (at most once per habitual run)
// and at 1 Hz with the leg report.
struct KnownHazardsMsg {
    static constexpr core::MsgId kMsgId = ids::kKnownHazards;
    std::int64_t timeNs;
    std::uint32_t revision;    // the habitual layer's map revision: grows with every change
    std::uint8_t count;        // hazards[0..count) in use
    std::uint8_t pad[3];
    KnownHazard hazards[kMaxKnownHazards];
};

}  // namespace rse::msg
