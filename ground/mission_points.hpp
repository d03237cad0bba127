// The ten points of the RSE demonstration (issue 17; docs/mission.md), found
// in what the flight software publishes: its events (the EVENT stream, each
// with its numbers: EVENT_DATA, fsw/cmdtlm/dictionary.def "Event data") and
// its plan status (PLAN: the call-home reason), with the estimated pose
// (ROVER_STATE) to place each point on the map. The flight software knows
// nothing of points; this is the ground's reading of its output, so a mission
// that misbehaves shows a point missing or out of order.
//
// Every number and every decision comes from an event's id, order, time and
// numbers (FlightEvent::read), never from its text: the text is only quoted to
// people (a point's "what", the decisions list), so rewording an event changes
// no point. An event whose numbers were lost on the way is taken as one that
// does not show its point (as a missing event would). onEvent looks the
// event's id up in a table of handlers, one small member function each;
// mission_points.cpp holds them and points 1-4 and 6-10, mission_hidden_obstacle.cpp
// the hidden obstacle's (point 5) and the hazards.
//
//   1 operator      the goal list the flight software took from an authenticated GOTO (event 208, >= 1 goal)
//   2 deliberative  the first plan (902) and its first leg with length, energy and power bounds (905)
//   3 habitual      the first local plan within the leg's bounds, sent to the follower (803)
//   4 deliberative  a leg reached (906) and the next one issued (905)
//   5 habitual      a hidden obstacle (a hazard disc that meets no coarse-map polygon) on the
//                   path (804), the leg replanned within its bounds (805) and then achieved (808)
//                   with no fail-up and no new leg between; or first seen (816) while the leg was
//                   being planned, on its way (the disc within the footprint of the straight line
//                   from where the leg was sent to its end), the leg's plan (803) going round it
//                   and then achieved the same way; seen before the leg was sent counts as while
//                   planning; a leg merged into the next (919: its end inside the rock) carries the
//                   detour on; a worn motor's power fail-up on the detour leg ends it as achieved
//   6 habitual      a power fail-up (807, "power") while no drive is declared failed: a worn
//                   motor's extra draw broke the leg's power bound
//   7 deliberative  that power bound relaxed (910) and the leg re-sent; driving resumed (803)
//   8 habitual      a fail-up (807) while a drive is declared failed (762)
//   9 deliberative  plans made with the failed drive in the model (990): the motor loss seen in
//                   the drive-mode estimate
//  10 deliberative  call home (912) with reason "no plan within the risk limit" (PLAN call_home 1),
//                   then the rover safed (215: mode SAFE)
//
// Each point is taken the first time its evidence is complete; the criteria do
// not depend on each other, so the order they come in is the mission's.
// Host only.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "ground/mission_record.hpp"

namespace rse::ground {

// The call home in the flight software's words (event 912's text): from
// after "CALL HOME: " to before the goal counts that follow the reason, also
// when the event's 95 characters cut those short. Words for people (POINT 10's
// text, rse-demo's outcome line): nothing decides on them.
std::string callHomeWords(const std::string& eventText);

class TenPointTracker {
public:
    // footprintRadiusM: the rover's clearance radius (ROVER_GEOMETRY), to
    // tell a hidden obstacle on a leg's way from one beside it.
    explicit TenPointTracker(const tables::CoarseMapTable& map, double footprintRadiusM = 0.6);

    // The coarse map in force (an operator may upload another): what tells a
    // hidden obstacle from a known rock.
    void setMap(const tables::CoarseMapTable& map) { map_ = map; }
    // Flight events, in the order the flight software reported them.
    void onEvent(const FlightEvent& event);
    // The estimated position (to place the points; a point seen before the
    // first one is placed at it).
    void onPose(double timeS, double xM, double yM);
    // PLAN's call-home reason (msg::CallHomeReason; 0 none) as published.
    void onCallHomeReason(std::uint8_t reason);

    // The points seen since the last call, in the order they were seen.
    std::vector<MissionPoint> takeNew();
    const std::array<MissionPoint, kMissionPointCount>& points() const { return points_; }
    // Every point seen, each no earlier than the one before.
    bool allInOrder() const;
    // "ten points: all in order", or which are missing and which out of order.
    std::string verdict() const;
    // The points, the verdict, the hazards, legs and decisions seen.
    void fill(MissionRecord* record) const;

    // "[  12.340] POINT 5 habitual: ..." (no newline).
    static std::string formatPoint(const MissionPoint& point);
    // A named figure of a point ("power bound before W", ...): NAN when absent.
    double fact(int number, const std::string& name) const;

private:
    // One event id's reading (the handler table, mission_points.cpp).
    using Handler = void (TenPointTracker::*)(const FlightEvent&);
    struct Route {
        std::uint16_t firstId;
        std::uint16_t lastId;
        Handler handler;
    };
    static const Route kRoutes[];

    void see(int number, double timeS, const std::string& layer, const std::string& what, bool atPose = true);
    void setFact(int number, const std::string& name, double value);
    void decide(const FlightEvent& e, const char* kind);  // the event's words in the decisions list
    LegRecord* leg(std::uint32_t id);
    void seePointTen();

    // Handlers, one per event id (or id range); each reads the event's numbers.
    void onGoalsCommanded(const FlightEvent& e);     // 208: point 1
    void onPlanFound(const FlightEvent& e);          // 902
    void onLegSent(const FlightEvent& e);            // 905: points 2 and 4, the leg's record
    void onPlanSent(const FlightEvent& e);           // 803: points 3 and 7
    void onHabitualFailUp(const FlightEvent& e);     // 807: points 6 and 8
    void onHabitualLegAchieved(const FlightEvent& e);  // 808
    void onLegReached(const FlightEvent& e);         // 906
    void onBoundRelaxed(const FlightEvent& e);       // 910: point 7's relaxation
    void onRiskRelaxed(const FlightEvent& e);        // 904
    void onReplan(const FlightEvent& e);             // 911
    void onLegEndSkipped(const FlightEvent& e);      // 919
    void onNoPlan(const FlightEvent& e);             // 903
    void onFailedDriveModel(const FlightEvent& e);   // 990: point 9
    void onCallHome(const FlightEvent& e);           // 912: point 10
    void onSafed(const FlightEvent& e);              // 215: point 10
    void onGaveUp(const FlightEvent& e);             // 933
    void onDriveMode(const FlightEvent& e);          // 760-763
    // Point 5 and the hazards (mission_hidden_obstacle.cpp).
    void onPathBlocked(const FlightEvent& e);        // 804
    void onMinorAnomaly(const FlightEvent& e);       // 805
    void onHazardRemembered(const FlightEvent& e);   // 816
    // A new leg (905) before it is the current one: the hidden obstacle's leg
    // merged into it (919 in the same frame) or superseded by it.
    void hiddenObstacleLegReplaced(const FlightEvent& e, std::uint32_t newLegId);
    // ... and once it is: a hidden obstacle seen before it was sent, on its way.
    void hiddenObstacleBeforeLeg();
    // The leg's plan (803) with the obstacle seen while it was planned: round it.
    void hiddenObstaclePlanned(const FlightEvent& e);
    // A fail-up (807) of the hidden obstacle's leg: a power fail-up on the
    // detour ends it as point 5; any fail-up spoils it.
    void hiddenObstacleFailedUp(const FlightEvent& e, std::uint32_t legId, bool power);
    void startHiddenBlock(std::uint32_t legId, unsigned hazardId, double seenS, bool whilePlanning, bool beforeLeg);
    bool onLegWay(const HazardSeen& h) const;
    void completePointFive(double timeS, const std::string& ending);

    tables::CoarseMapTable map_;
    const double footprintRadiusM_;
    std::array<MissionPoint, kMissionPointCount> points_{};
    std::vector<int> fresh_;
    double poseTimeS_ = -1.0, poseX_ = 0.0, poseY_ = 0.0;
    std::uint8_t callHomeReason_ = 0;

    // What the points are built from.
    std::string firstPlan_;                // 902 text of the first plan
    bool planPending_ = false;             // 902 seen, its first leg not yet
    bool legReachedPending_ = false;       // 906 seen, the next leg not yet
    std::string legReachedText_;
    std::uint32_t currentLeg_ = 0;
    bool currentLegPlanned_ = false;       // a plan (803) of the current leg was sent
    double legFromX_ = 0.0, legFromY_ = 0.0, legToX_ = 0.0, legToY_ = 0.0;  // the current leg's way
    std::vector<LegRecord> legs_;
    std::vector<HazardSeen> hazards_;
    std::vector<MissionDecision> decisions_;
    // Point 5: a hidden obstacle on the path of a leg, until that leg ends.
    struct HiddenBlock {
        bool active = false;
        std::uint32_t legId = 0;
        unsigned hazardId = 0;
        double seenS = 0.0;
        double replannedS = -1.0;
        std::string plan;                  // the replanned trajectory (803 text)
        double replanX = 0.0, replanY = 0.0;  // the estimated position then
        bool whilePlanning = false;        // first seen while the leg was being planned (no 804)
        bool beforeLeg = false;            // ... or before the leg was sent
        std::uint32_t mergedFromLeg = 0;   // replanned on this leg, then merged into legId (919)
        double firstReplanS = -1.0;        // that first local replan
        std::uint32_t failUps = 0;         // fail-ups of the leg since
    } hidden_;
    double legEndSkippedS_ = -1.0;         // the last 919 (a leg merged into the next)
    std::vector<unsigned> hiddenTried_;    // hazards point 5 was tried on (once each: a fail-up spoils it)
    std::string lastPlanSent_;             // last 803 text
    // Drives (bit per wheel) the drive mode estimator declares degraded / failed.
    unsigned degraded_ = 0, failed_ = 0;
    std::string degradedText_, failedText_;
    double failedS_ = -1.0;
    std::string gaveUpText_;               // fault protection's 933
    // Point 6 -> 7: the power fail-up and the relaxation, until driving resumes.
    double powerBoundBeforeW_ = 0.0;
    bool powerFailUpSeen_ = false;
    bool relaxPending_ = false;
    std::string relaxText_;
    double relaxedPowerW_ = 0.0;
    std::string replanText_;               // last 911
    std::string riskRelaxText_;            // last 904
    // Point 10: the last call home (912) and the safing (215) after it.
    bool callHomeSeen_ = false;            // a 912 came
    std::string callHomeEventText_;        // its text, quoted
    std::string callHomeRiskRelaxText_;    // the risk relaxation before it
    double safedS_ = -1.0;                 // the 215 after it (-1 not yet)
    std::string safedText_;
};

}  // namespace rse::ground
