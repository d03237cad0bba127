// Event ids raised by the deliberative layer (range 900-929). Texts start with
// "deliberative: ". Documented in docs/deliberative.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::deliberative::events {

constexpr core::EventId kGoalsChanged = 900;      // INFO: goal list revision, count, risk bound: planning restarts
constexpr core::EventId kPlanStarted = 901;       // INFO: goal, start, risk in force, steps, obstacles used / dropped
constexpr core::EventId kPlanFound = 902;         // INFO: status, length, risk used, legs, nodes, work, slices
constexpr core::EventId kNoPlan = 903;            // WARN: no plan within the risk in force (proven or budget)
constexpr core::EventId kRiskRelaxed = 904;       // WARN: the risk bound relaxed to a larger value (factor)
constexpr core::EventId kLegSent = 905;           // INFO: leg id, index, goal, length and energy bounds
constexpr core::EventId kLegAchieved = 906;       // INFO: leg id reached
constexpr core::EventId kGoalReached = 907;       // INFO: goal index reached
constexpr core::EventId kMissionComplete = 908;   // INFO: every goal reached
constexpr core::EventId kFailUpReceived = 909;    // WARN: leg id, violated constraint, excess
constexpr core::EventId kBoundRelaxed = 910;      // WARN: a leg's length or energy bound relaxed (factor): leg resent
constexpr core::EventId kReplan = 911;            // WARN: replanning from the current state (n of the limit)
constexpr core::EventId kCallHome = 912;          // CRITICAL: no plan within the bounds: rover safed, reason
constexpr core::EventId kProblemRefused = 913;    // ERROR: the map problem could not be built (why)
constexpr core::EventId kDroppedObstacles = 914;  // WARN: more coarse-map obstacles than the planner holds: n left out of the problem (risk checked)
constexpr core::EventId kLeftAutonomous = 915;    // INFO: mode left AUTONOMOUS: plan dropped, legs cancelled
constexpr core::EventId kMalformedInput = 916;    // ERROR: a bus message that does not decode or fails its checks (throttled)
constexpr core::EventId kInitFailed = 917;        // ERROR: pipe creation or subscription refused at init
constexpr core::EventId kPublishFailed = 918;     // ERROR: a leg, status, plan path or safe request the bus refused (throttled)
constexpr core::EventId kLegEndSkipped = 919;     // WARN: a leg end lies inside a seen hazard: merged into the next leg (re-sent when in force)
constexpr core::EventId kMissionHeld = 920;       // WARN: fault protection holds the mission (reasons): no new legs, fail-ups ignored
constexpr core::EventId kMissionResumed = 921;    // INFO: hold released (resume count): the current leg re-sent from the current pose
constexpr core::EventId kGoalUnconfirmed = 922;   // WARN: the goal's last leg reached while the pose is uncertain: waiting for a certain pose
constexpr core::EventId kGoalLegResent = 923;     // WARN: pose certain again but off the goal (distance): the last leg re-sent from the pose
constexpr core::EventId kBackingUp = 925;         // WARN: no path after the replans: backing up along the driven track (distance, target, n of limit)
constexpr core::EventId kBackedUp = 926;          // INFO: back-up reached: replanning from there
constexpr core::EventId kOffMapReplan = 927;      // WARN: off the map (fault protection's request): waypoint cancelled, replanning from the pose
constexpr core::EventId kPlannedFromReentry = 928; // WARN: the start lies off the site: planned from the nearest point on it (the habitual layer drives there)
constexpr core::EventId kWideSearch = 929;        // INFO: no plan within Boole's bound: the search widened (factor), the plan certified within the risk
// 990: the deliberative range 900-929 is full; 990-999 are the deliberative layer's too.
constexpr core::EventId kFailedDriveModel = 990;  // WARN: plans now take these drives as failed (drive mode estimate): power factor, motion noise
constexpr core::EventId kWholeMapReplan = 991;    // WARN: the plan passes obstacles its problem left out (risk above the left-out share): planned again with them in (round)
constexpr core::EventId kRouteFound = 993;        // INFO: site mode: the global route to the goal (length, points, expansions, runs)
constexpr core::EventId kNoRoute = 994;           // WARN: site mode: no route to the goal over the site map (refused, none, budget spent): call home
constexpr core::EventId kLookAheadStarted = 995;  // INFO: site mode: the next horizon planned while driving, from the horizon's end (start sigma, steps to go)
constexpr core::EventId kLookAheadDropped = 996;  // INFO: site mode: that look-ahead dropped (why: stale, a replan, new goals, ...)
constexpr core::EventId kHorizonEnd = 997;        // INFO: site mode: a horizon's end reached: driven through (the look-ahead's first leg sent), or stopped to plan (why)
constexpr core::EventId kWholeMapRefused = 992;   // WARN: plan not taken: the obstacles left out of its problem carry more than the left-out share, no room or rounds left
constexpr core::EventId kFailUpWhileHeld = 924;   // INFO: a fail-up that arrived during a hold: ignored, the leg is re-sent on release

}  // namespace rse::deliberative::events
