// Event ids raised by the habitual layer (range 800-849). Texts start with
// "habitual: ". Documented in docs/habitual.md.
#pragma once

#include "fsw/core/event_log.hpp"

namespace rse::habitual::events {

// "(throttled)": evented on the 1st, 2nd, 4th, 8th ... occurrence, every one counted.
constexpr core::EventId kLegAccepted = 800;        // INFO: leg id, goal, bounds
constexpr core::EventId kLegRefused = 801;         // WARN: leg id and why (throttled)
constexpr core::EventId kLegCancelled = 802;       // INFO: legId 0: stopped, idle
constexpr core::EventId kPlanSent = 803;           // INFO: trajectory id, points, length / energy against the allowed
constexpr core::EventId kPathBlocked = 804;        // WARN: a remembered hazard blocks the remaining path: stop and replan
constexpr core::EventId kMinorAnomaly = 805;       // WARN: replanned within the constraints: logged, not failed up
constexpr core::EventId kRepairAttempt = 806;      // INFO: planning run n of N failed a constraint: repairing
constexpr core::EventId kFailUp = 807;             // ERROR: which constraint, predicted, allowed, excess
constexpr core::EventId kLegAchieved = 808;        // INFO: the follower reached the waypoint
constexpr core::EventId kEnergyViolated = 809;     // WARN: new power factors: the remaining path needs more than allowed
constexpr core::EventId kCannotFollow = 810;       // WARN: the follower gave up (reason): replan or fail up
constexpr core::EventId kLeftAutonomous = 811;     // INFO: mode left AUTONOMOUS: stopped, leg dropped
constexpr core::EventId kPoseNotReady = 812;       // WARN: no initialised, finite, fresh pose: planning waits (throttled)
constexpr core::EventId kMalformedInput = 813;     // ERROR: bus message that does not decode or fails its checks (throttled)
constexpr core::EventId kHazardTableFull = 814;    // WARN: remembered-hazard table full: the oldest replaced (throttled)
constexpr core::EventId kHazardKnown = 815;        // DEBUG: sighting on a coarse-map obstacle, not added (throttled)
constexpr core::EventId kHazardRemembered = 816;   // INFO: first sighting of an obstacle id: disc centre and radius
constexpr core::EventId kMapRefused = 817;         // ERROR: the local map refused the coarse map or a disc (throttled)
constexpr core::EventId kPlannerRefused = 818;     // WARN: RRT* refused the query (start or goal not free) (throttled)
constexpr core::EventId kInitFailed = 819;         // ERROR: pipe creation or subscription refused at init
constexpr core::EventId kMissionHeld = 820;        // WARN: fault protection holds the mission (reasons): rover stopped, leg kept
constexpr core::EventId kMissionReleased = 821;    // INFO: hold released: waiting for the leg to be re-sent (planning resumes)
constexpr core::EventId kEscape = 822;             // WARN: start inside a seen hazard's footprint: backing out to a free point, then replan
constexpr core::EventId kContactRemembered = 823;  // WARN: a contact the follower felt remembered as a hazard (where, cover)

}  // namespace rse::habitual::events
