// TenPointTracker's reading of point 5 (ground/mission_points.hpp): a hidden
// obstacle (a hazard disc that meets no coarse-map polygon) on a leg's path or
// way, the leg's plan going round it within its bounds, and the leg achieved
// with no fail-up and no new leg between (or merged into the next, or ended by
// the worn motor's power fail-up); and the hazards the habitual layer reports.
// Every figure is the events' numbers (PATH_BLOCKED, MINOR_ANOMALY,
// HAZARD_REMEMBERED, ...); the texts are only quoted.
#include <algorithm>
#include <cstdio>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_text.hpp"

namespace rse::ground {

namespace {

namespace evd = cmdtlm::event_data;

// Hidden: the disc meets no polygon of the coarse map (a known rock seen by
// the detector is the map's, not a surprise).
bool hiddenDisc(const tables::CoarseMapTable& map, double xM, double yM, double radiusM) {
    return geometry::distanceToCoarseMap(map, geometry::Point2{xM, yM}) > radiusM;
}

}  // namespace

void TenPointTracker::startHiddenBlock(std::uint32_t legId, unsigned hazardId, double seenS, bool whilePlanning,
                                       bool beforeLeg) {
    hidden_ = HiddenBlock{};
    hidden_.active = true;
    hidden_.legId = legId;
    hidden_.hazardId = hazardId;
    hidden_.seenS = seenS;
    hiddenTried_.push_back(hazardId);
    hidden_.whilePlanning = whilePlanning;
    hidden_.beforeLeg = beforeLeg;
}

// Within the rover's footprint of the straight line from where the current
// leg was sent to its end.
bool TenPointTracker::onLegWay(const HazardSeen& h) const {
    const double reach = h.radiusM + footprintRadiusM_;
    return geometry::pointSegmentDistanceSquared(geometry::Point2{h.xM, h.yM}, geometry::Point2{legFromX_, legFromY_},
                                                 geometry::Point2{legToX_, legToY_}) < reach * reach;
}

void TenPointTracker::onPathBlocked(const FlightEvent& e) {
    evd::PATH_BLOCKED blocked;
    if (!e.read(&blocked) || blocked.hazard <= 0.0) {
        return;  // the path blocked with no disc named
    }
    if (hiddenDisc(map_, blocked.x, blocked.y, blocked.radius) && !hidden_.active) {
        startHiddenBlock(static_cast<std::uint32_t>(blocked.leg_id), static_cast<unsigned>(blocked.hazard), e.timeS,
                         false, false);
    }
}

void TenPointTracker::onMinorAnomaly(const FlightEvent& e) {
    evd::MINOR_ANOMALY replanned;
    if (e.read(&replanned) && hidden_.active && hidden_.legId == static_cast<std::uint32_t>(replanned.leg_id) &&
        hidden_.replannedS < 0.0) {
        hidden_.replannedS = e.timeS;
        hidden_.plan = lastPlanSent_;
        hidden_.replanX = poseX_;
        hidden_.replanY = poseY_;
    }
}

void TenPointTracker::onHazardRemembered(const FlightEvent& e) {
    evd::HAZARD_REMEMBERED seen;
    if (!e.read(&seen)) {
        return;
    }
    HazardSeen h;
    const auto id = static_cast<unsigned>(seen.hazard);
    h.id = static_cast<std::uint8_t>(id);
    h.timeS = e.timeS;
    h.xM = seen.x;
    h.yM = seen.y;
    h.radiusM = seen.radius;
    h.hidden = hiddenDisc(map_, h.xM, h.yM, h.radiusM);
    hazards_.push_back(h);
    // Seen while the leg in force was being planned, on its way: its plan
    // must go round it (else it is seen on the path, 804).
    if (h.hidden && !hidden_.active && currentLeg_ != 0 && !currentLegPlanned_ && onLegWay(h)) {
        startHiddenBlock(currentLeg_, id, e.timeS, true, false);
    }
}

void TenPointTracker::hiddenObstacleLegReplaced(const FlightEvent& e, std::uint32_t newLegId) {
    if (hidden_.active && hidden_.legId == currentLeg_ && legEndSkippedS_ == e.timeS && hidden_.replannedS >= 0.0 &&
        hidden_.failUps == 0) {
        // The leg's end lay inside the obstacle as it grew: the deliberative
        // layer merged the leg into the next (919) and re-sent it; the local
        // detour goes on as that leg's.
        decisions_.push_back(MissionDecision{e.timeS, "hidden obstacle",
                                             "hazard " + std::to_string(hidden_.hazardId) + ": leg " +
                                                 std::to_string(currentLeg_) + "'s end inside it, merged into leg " +
                                                 std::to_string(newLegId)});
        hidden_.mergedFromLeg = hidden_.legId;
        hidden_.firstReplanS = hidden_.replannedS;
        hidden_.legId = newLegId;
        hidden_.replannedS = -1.0;  // the merged leg's own plan must go round it too
        hidden_.whilePlanning = true;
    } else if (hidden_.active && hidden_.legId == currentLeg_) {
        // A new leg before the hidden obstacle's leg was achieved: the
        // deliberative layer stepped in (merged, re-sent or replanned).
        decisions_.push_back(MissionDecision{e.timeS, "hidden obstacle",
                                             "hazard " + std::to_string(hidden_.hazardId) + " seen at " +
                                                 secondsText(hidden_.seenS) + ": leg " + std::to_string(currentLeg_) +
                                                 " superseded by leg " + std::to_string(newLegId)});
        hidden_.active = false;
    }
}

// A hidden obstacle seen before this leg was sent, on its way: the
// deliberative layer's leg (coarse map) runs through it, so the leg's plan
// must go round it (as when it is seen while planning).
void TenPointTracker::hiddenObstacleBeforeLeg() {
    if (hidden_.active || points_[4].seen) {
        return;
    }
    for (const HazardSeen& h : hazards_) {
        const bool tried = std::find(hiddenTried_.begin(), hiddenTried_.end(), h.id) != hiddenTried_.end();
        if (h.hidden && !tried && onLegWay(h)) {
            startHiddenBlock(currentLeg_, h.id, h.timeS, true, true);
            return;
        }
    }
}

void TenPointTracker::hiddenObstaclePlanned(const FlightEvent& e) {
    if (hidden_.active && hidden_.whilePlanning && hidden_.legId == currentLeg_ && hidden_.replannedS < 0.0) {
        // The leg's plan, made with the obstacle on the map: round it.
        hidden_.replannedS = e.timeS;
        hidden_.plan = eventWords(e.text);
        hidden_.replanX = poseX_;
        hidden_.replanY = poseY_;
    }
}

void TenPointTracker::hiddenObstacleFailedUp(const FlightEvent& e, std::uint32_t legId, bool power) {
    if (hidden_.active && hidden_.legId == legId && power && degraded_ != 0U && failed_ == 0U &&
        hidden_.replannedS >= 0.0) {
        // The leg was driven on round the obstacle until a worn motor broke its
        // power bound (point 6's fail-up): the detour held; the leg ends here
        // for a reason of its own.
        completePointFive(e.timeS, "driven on round it with no fail-up until a worn motor broke the leg's power bound");
    }
    if (hidden_.active && hidden_.legId == legId) {
        ++hidden_.failUps;
        decisions_.push_back(MissionDecision{e.timeS, "hidden obstacle",
                                             "hazard " + std::to_string(hidden_.hazardId) + " seen at " +
                                                 secondsText(hidden_.seenS) + " on leg " + std::to_string(legId) +
                                                 ": the leg failed up (no local replan within its bounds)"});
        hidden_.active = false;
    }
}

// The hidden obstacle's leg ended: point 5 when the leg's plan went round the
// obstacle within its bounds and no fail-up came between.
void TenPointTracker::completePointFive(double timeS, const std::string& ending) {
    hidden_.active = false;
    if (hidden_.replannedS < 0.0 || hidden_.failUps != 0) {
        return;
    }
    const std::string legId = std::to_string(hidden_.legId);
    setFact(5, "fail-ups", 0.0);
    setFact(5, "hazard", hidden_.hazardId);
    setFact(5, "leg", hidden_.legId);
    setFact(5, "seen s", hidden_.seenS);
    setFact(5, "while planning", hidden_.whilePlanning ? 1.0 : 0.0);
    const std::string how =
        hidden_.mergedFromLeg != 0
            ? " seen on the path at " + secondsText(hidden_.seenS) + ", leg " + std::to_string(hidden_.mergedFromLeg) +
                  " replanned locally within its bounds at " + secondsText(hidden_.firstReplanS) +
                  ", logged as a minor anomaly; the leg's end inside it, merged into leg " + legId +
                  ", planned round it at " + secondsText(hidden_.replannedS) + " (" + hidden_.plan + ")"
        : hidden_.whilePlanning
            ? " seen on the leg's way at " + secondsText(hidden_.seenS) + (hidden_.beforeLeg ? " before leg " : " while leg ") +
                  legId + (hidden_.beforeLeg ? " was sent" : " was being planned") +
                  "; planned round it locally within its bounds at " + secondsText(hidden_.replannedS) + " (" +
                  hidden_.plan + ")"
            : " seen on the path at " + secondsText(hidden_.seenS) + ", leg " + legId +
                  " replanned locally within its bounds at " + secondsText(hidden_.replannedS) + " (" + hidden_.plan +
                  "), logged as a minor anomaly";
    see(5, timeS, "habitual", "hidden obstacle " + std::to_string(hidden_.hazardId) + how + "; " + ending);
    // Placed where it happened: where the rover replanned.
    points_[4].xM = hidden_.replanX;
    points_[4].yM = hidden_.replanY;
}

}  // namespace rse::ground
