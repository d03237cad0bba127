#include "ground/mission_points.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/goal_commands.hpp"
#include "fsw/estimator/drive_mode_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/geometry/coarse_map.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"

namespace rse::ground {

namespace {

namespace dev = deliberative::events;
namespace hev = habitual::events;

// The text after "layer: " (the flight event's own words, without its prefix).
std::string body(const std::string& text) {
    const std::size_t colon = text.find(": ");
    return colon == std::string::npos ? text : text.substr(colon + 2);
}

// Where `marker` starts in text, or nullptr.
const char* after(const std::string& text, const char* marker) {
    const std::size_t at = text.find(marker);
    return at == std::string::npos ? nullptr : text.c_str() + at;
}

// The wheel index of a drive name at the start of s ("ML ..."), or -1.
int wheelNamed(const char* s) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const char* name = msg::wheelName(w);
        const std::size_t n = std::strlen(name);
        if (std::strncmp(s, name, n) == 0 && s[n] == ' ') {
            return static_cast<int>(w);
        }
    }
    return -1;
}

std::string seconds(double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f s", t);
    return text;
}

}  // namespace

std::string callHomeWords(const std::string& eventText) {
    std::string t = eventText;
    const std::string marker = "CALL HOME: ";
    const std::size_t at = t.find(marker);
    if (at != std::string::npos) {
        t.erase(0, at + marker.size());
    }
    const std::string tail = ", goal ";
    for (std::size_t comma = t.rfind(", "); comma != std::string::npos; comma = comma == 0 ? std::string::npos : t.rfind(", ", comma - 1)) {
        const std::string rest = t.substr(comma);
        if (tail.compare(0, rest.size() < tail.size() ? rest.size() : tail.size(), rest, 0,
                         rest.size() < tail.size() ? rest.size() : tail.size()) == 0) {
            return t.substr(0, comma);  // ", goal 0, risk ..." or what the 95 characters left of it
        }
    }
    return t;
}

TenPointTracker::TenPointTracker(const tables::CoarseMapTable& map, double footprintRadiusM)
    : map_(map), footprintRadiusM_(footprintRadiusM) {
    for (int i = 0; i < kMissionPointCount; ++i) {
        points_[static_cast<std::size_t>(i)].number = i + 1;
    }
}

void TenPointTracker::onPose(double timeS, double xM, double yM) {
    poseTimeS_ = timeS;
    poseX_ = xM;
    poseY_ = yM;
    // A point seen before the estimate was initialised (the GOTO sent while
    // the rover waits for its first fix) is placed at its first estimate: it
    // has not moved yet.
    for (MissionPoint& p : points_) {
        if (p.seen && !p.hasPlace) {
            p.hasPlace = true;
            p.xM = xM;
            p.yM = yM;
        }
    }
}

void TenPointTracker::onCallHomeReason(std::uint8_t reason) {
    callHomeReason_ = reason;
    seePointTen();
}

// Point 10 needs the call home (912), PLAN's reason and the rover safed (215).
// On the bus the reason comes before the event; on a downlink PLAN is routine
// telemetry and may come after both events, so whichever comes last decides.
void TenPointTracker::seePointTen() {
    if (callHomeEventText_.empty() || safedS_ < 0.0 || points_[9].seen) {
        return;
    }
    setFact(10, "call home reason", callHomeReason_);
    if (callHomeReason_ != static_cast<std::uint8_t>(msg::CallHomeReason::kNoPlanWithinRisk)) {
        return;
    }
    std::string text = "CALL HOME, operator called: " + callHomeWords(callHomeEventText_);
    if (!callHomeRiskRelaxText_.empty()) {
        text = "no plan within the bound even after " + callHomeRiskRelaxText_ + "; " + text;
    }
    see(10, safedS_, "deliberative + mode owner", text + "; rover safed: " + safedText_);
}

void TenPointTracker::see(int number, double timeS, const std::string& layer, const std::string& what, bool atPose) {
    MissionPoint& p = points_[static_cast<std::size_t>(number - 1)];
    if (p.seen) {
        return;  // each point once: the first time its evidence was complete
    }
    p.seen = true;
    p.timeS = timeS;
    p.layer = layer;
    p.what = what;
    p.hasPlace = atPose && poseTimeS_ >= 0.0;
    p.xM = poseX_;
    p.yM = poseY_;
    fresh_.push_back(number);
}

void TenPointTracker::setFact(int number, const std::string& name, double value) {
    points_[static_cast<std::size_t>(number - 1)].facts[name] = value;
}

double TenPointTracker::fact(int number, const std::string& name) const {
    if (number < 1 || number > kMissionPointCount) {
        return std::nan("");
    }
    const MissionPoint& p = points_[static_cast<std::size_t>(number - 1)];
    const auto f = p.facts.find(name);
    return f == p.facts.end() ? std::nan("") : f->second;
}

// Within the rover's footprint of the straight line from where the current
// leg was sent to its end.
bool TenPointTracker::onLegWay(const HazardSeen& h) const {
    const double reach = h.radiusM + footprintRadiusM_;
    return geometry::pointSegmentDistanceSquared(geometry::Point2{h.xM, h.yM}, geometry::Point2{legFromX_, legFromY_},
                                                 geometry::Point2{legToX_, legToY_}) < reach * reach;
}

LegRecord* TenPointTracker::leg(std::uint32_t id) {
    for (LegRecord& l : legs_) {
        if (l.legId == id) {
            return &l;
        }
    }
    return nullptr;
}

void TenPointTracker::onHazardBlocked(const FlightEvent& e) {
    unsigned legId = 0, hazard = 0;
    double x = 0.0, y = 0.0, r = 0.0;
    const char* s = after(e.text, "leg ");
    if (s == nullptr || std::sscanf(s, "leg %u: hazard %u at (%lf, %lf) r %lf m", &legId, &hazard, &x, &y, &r) != 5) {
        return;  // "path ... blocked": no disc named
    }
    // Hidden: the disc meets no polygon of the coarse map (a known rock seen
    // by the detector is the map's, not a surprise).
    const bool hidden = geometry::distanceToCoarseMap(map_, geometry::Point2{x, y}) > r;
    if (hidden && !hidden_.active) {
        hidden_ = HiddenBlock{};
        hidden_.active = true;
        hidden_.legId = legId;
        hidden_.hazardId = hazard;
        hidden_.seenS = e.timeS;
        hiddenTried_.push_back(hazard);
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
            ? " seen on the path at " + seconds(hidden_.seenS) + ", leg " + std::to_string(hidden_.mergedFromLeg) +
                  " replanned locally within its bounds at " + seconds(hidden_.firstReplanS) +
                  ", logged as a minor anomaly; the leg's end inside it, merged into leg " + legId +
                  ", planned round it at " + seconds(hidden_.replannedS) + " (" + hidden_.plan + ")"
        : hidden_.whilePlanning
            ? " seen on the leg's way at " + seconds(hidden_.seenS) + (hidden_.beforeLeg ? " before leg " : " while leg ") +
                  legId + (hidden_.beforeLeg ? " was sent" : " was being planned") +
                  "; planned round it locally within its bounds at " + seconds(hidden_.replannedS) + " (" +
                  hidden_.plan + ")"
            : " seen on the path at " + seconds(hidden_.seenS) + ", leg " + legId +
                  " replanned locally within its bounds at " + seconds(hidden_.replannedS) + " (" + hidden_.plan +
                  "), logged as a minor anomaly";
    see(5, timeS, "habitual", "hidden obstacle " + std::to_string(hidden_.hazardId) + how + "; " + ending);
    // Placed where it happened: where the rover replanned.
    points_[4].xM = hidden_.replanX;
    points_[4].yM = hidden_.replanY;
}

void TenPointTracker::onHabitualFailUp(const FlightEvent& e) {
    unsigned legId = 0;
    const char* s = after(e.text, "leg ");
    if (s != nullptr) {
        (void)std::sscanf(s, "leg %u", &legId);
    }
    if (LegRecord* l = leg(legId)) {
        const char* what = after(e.text, "fail-up: ");
        l->outcome = std::string("failed up: ") + (what != nullptr ? what + 9 : "?");
    }
    decisions_.push_back(MissionDecision{e.timeS, "fail-up", body(e.text)});
    const bool power = e.text.find("fail-up: power") != std::string::npos;
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
                                                 seconds(hidden_.seenS) + " on leg " + std::to_string(legId) +
                                                 ": the leg failed up (no local replan within its bounds)"});
        hidden_.active = false;
    }
    if (power && failed_ == 0U) {
        // 6: a worn motor's extra draw broke the leg's power bound.
        const LegRecord* l = leg(legId);
        powerBoundBeforeW_ = l != nullptr ? l->powerBoundW : 0.0;
        powerFailUpSeen_ = true;
        setFact(6, "power bound W", powerBoundBeforeW_);
        std::string what;
        if (degraded_ != 0U) {
            what = "drive " + degradedText_ + "; ";
        }
        what += "leg " + std::to_string(legId) + "'s power bound no longer met: " + body(e.text);
        see(6, e.timeS, "estimator + habitual", what);
    } else if (failed_ != 0U) {
        // 8: the motor failed; the habitual layer fails up again.
        std::string what = "drive " + failedText_ + " at " + seconds(failedS_);
        if (!gaveUpText_.empty()) {
            what += " (" + gaveUpText_ + ")";
        }
        what += "; " + body(e.text);
        see(8, e.timeS, "estimator + habitual", what);
    }
}

void TenPointTracker::onEvent(const FlightEvent& e) {
    const std::string& t = e.text;
    switch (e.id) {
        case deliberative::events::kGoalsCommanded: {
            unsigned goals = 0;
            double risk = 0.0;
            const char* s = after(t, "app: ");
            if (s != nullptr && std::sscanf(s, "app: %u goal(s), risk bound %lf", &goals, &risk) == 2 && goals > 0) {
                setFact(1, "risk bound", risk);
                see(1, e.timeS, "operator",
                    "authenticated GOTO taken by the flight software: " + body(t) + " (its only source of goals is an "
                    "accepted command)");
            }
            break;
        }
        case dev::kPlanFound:
            if (firstPlan_.empty()) {
                firstPlan_ = body(t);
            }
            planPending_ = true;
            decisions_.push_back(MissionDecision{e.timeS, "plan", body(t)});
            break;
        case dev::kLegSent: {
            LegRecord l;
            l.sentS = e.timeS;
            unsigned id = 0, k = 0, n = 0;
            const char* s = after(t, "leg ");
            if (s != nullptr && std::sscanf(s, "leg %u (%u of %u) to (%lf, %lf): <= %lf m, <= %lf J, <= %lf W", &id, &k,
                                            &n, &l.xM, &l.yM, &l.lengthBoundM, &l.energyBoundJ, &l.powerBoundW) == 8) {
                l.legId = id;
            } else if (s != nullptr && std::sscanf(s, "leg %u (back-up) to (%lf, %lf): <= %lf m, <= %lf J", &id, &l.xM,
                                                   &l.yM, &l.lengthBoundM, &l.energyBoundJ) == 5) {
                l.legId = id;
            } else {
                break;
            }
            if (LegRecord* previous = leg(currentLeg_); previous != nullptr && previous->outcome.empty()) {
                previous->outcome = "superseded";
            }
            if (hidden_.active && hidden_.legId == currentLeg_ && legEndSkippedS_ == e.timeS &&
                hidden_.replannedS >= 0.0 && hidden_.failUps == 0) {
                // The leg's end lay inside the obstacle as it grew: the
                // deliberative layer merged the leg into the next (919) and
                // re-sent it; the local detour goes on as that leg's.
                decisions_.push_back(MissionDecision{e.timeS, "hidden obstacle",
                                                     "hazard " + std::to_string(hidden_.hazardId) + ": leg " +
                                                         std::to_string(currentLeg_) + "'s end inside it, merged into leg " +
                                                         std::to_string(l.legId)});
                hidden_.mergedFromLeg = hidden_.legId;
                hidden_.firstReplanS = hidden_.replannedS;
                hidden_.legId = l.legId;
                hidden_.replannedS = -1.0;  // the merged leg's own plan must go round it too
                hidden_.whilePlanning = true;
            } else if (hidden_.active && hidden_.legId == currentLeg_) {
                // A new leg before the hidden obstacle's leg was achieved: the
                // deliberative layer stepped in (merged, re-sent or replanned).
                decisions_.push_back(MissionDecision{e.timeS, "hidden obstacle",
                                                     "hazard " + std::to_string(hidden_.hazardId) + " seen at " +
                                                         seconds(hidden_.seenS) + ": leg " +
                                                         std::to_string(currentLeg_) + " superseded by leg " +
                                                         std::to_string(l.legId)});
                hidden_.active = false;
            }
            currentLeg_ = l.legId;
            currentLegPlanned_ = false;
            legFromX_ = poseX_;
            legFromY_ = poseY_;
            legToX_ = l.xM;
            legToY_ = l.yM;
            legs_.push_back(l);
            // A hidden obstacle seen before this leg was sent, on its way: the
            // deliberative layer's leg (coarse map) runs through it, so the
            // leg's plan must go round it (as when it is seen while planning).
            if (!hidden_.active && !points_[4].seen) {
                for (const HazardSeen& h : hazards_) {
                    const bool tried = std::find(hiddenTried_.begin(), hiddenTried_.end(), h.id) != hiddenTried_.end();
                    if (h.hidden && !tried && onLegWay(h)) {
                        hidden_ = HiddenBlock{};
                        hidden_.active = true;
                        hidden_.legId = currentLeg_;
                        hidden_.hazardId = h.id;
                        hidden_.seenS = h.timeS;
                        hiddenTried_.push_back(h.id);
                        hidden_.whilePlanning = true;
                        hidden_.beforeLeg = true;
                        break;
                    }
                }
            }
            if (planPending_) {
                planPending_ = false;
                setFact(2, "power bound W", l.powerBoundW);
                setFact(2, "energy bound J", l.energyBoundJ);
                char bounds[160];
                std::snprintf(bounds, sizeof bounds, "; leg %u of %u to (%.2f, %.2f) within <= %.2f m, <= %.0f J, "
                              "<= %.0f W", k, n, l.xM, l.yM, l.lengthBoundM, l.energyBoundJ, l.powerBoundW);
                see(2, e.timeS, "deliberative", "plan on the coarse map: " + firstPlan_ + bounds);
            }
            if (legReachedPending_) {
                legReachedPending_ = false;
                char next[96];
                std::snprintf(next, sizeof next, "; next issued: leg %u to (%.2f, %.2f)", l.legId, l.xM, l.yM);
                see(4, e.timeS, "habitual + deliberative", legReachedText_ + next);
            }
            if (relaxPending_ && relaxedPowerW_ <= 0.0) {
                relaxedPowerW_ = l.powerBoundW;
            }
            break;
        }
        case hev::kPlanSent:
            lastPlanSent_ = body(t);
            if (hidden_.active && hidden_.whilePlanning && hidden_.legId == currentLeg_ && hidden_.replannedS < 0.0) {
                // The leg's plan, made with the obstacle on the map: round it.
                hidden_.replannedS = e.timeS;
                hidden_.plan = body(t);
                hidden_.replanX = poseX_;
                hidden_.replanY = poseY_;
            }
            currentLegPlanned_ = true;
            if (!points_[2].seen) {
                see(3, e.timeS, "habitual", "local plan on the fine map within the leg's bounds, driving: " + body(t));
            }
            if (relaxPending_) {
                relaxPending_ = false;
                setFact(7, "power bound before W", powerBoundBeforeW_);
                setFact(7, "power bound after W", relaxedPowerW_);
                see(7, e.timeS, "deliberative + habitual", relaxText_ + "; driving resumed: " + body(t));
            }
            break;
        case hev::kPathBlocked:
            onHazardBlocked(e);
            break;
        case hev::kMinorAnomaly: {
            unsigned legId = 0;
            const char* s = after(t, "leg ");
            if (s != nullptr && std::sscanf(s, "leg %u", &legId) == 1 && hidden_.active && hidden_.legId == legId &&
                hidden_.replannedS < 0.0) {
                hidden_.replannedS = e.timeS;
                hidden_.plan = lastPlanSent_;
                hidden_.replanX = poseX_;
                hidden_.replanY = poseY_;
            }
            break;
        }
        case hev::kFailUp:
            onHabitualFailUp(e);
            break;
        case hev::kLegAchieved: {
            unsigned legId = 0;
            double x = 0.0, y = 0.0, m = 0.0, j = 0.0;
            const char* s = after(t, "leg ");
            if (s == nullptr || std::sscanf(s, "leg %u achieved at (%lf, %lf): %lf m, %lf J", &legId, &x, &y, &m, &j) < 1) {
                break;
            }
            if (LegRecord* l = leg(legId)) {
                l->outcome = "achieved";
                l->drivenM = m;
                l->drivenJ = j;
            }
            if (hidden_.active && hidden_.legId == legId) {
                completePointFive(e.timeS, "leg achieved, no fail-up");
            }
            break;
        }
        case hev::kHazardRemembered: {
            HazardSeen h;
            unsigned id = 0;
            const char* s = after(t, "hazard ");
            if (s != nullptr && std::sscanf(s, "hazard %u seen at (%lf, %lf), radius %lf m", &id, &h.xM, &h.yM,
                                            &h.radiusM) == 4) {
                h.id = static_cast<std::uint8_t>(id);
                h.timeS = e.timeS;
                h.hidden = geometry::distanceToCoarseMap(map_, geometry::Point2{h.xM, h.yM}) > h.radiusM;
                hazards_.push_back(h);
                // Seen while the leg in force was being planned, on its way:
                // its plan must go round it (else it is seen on the path, 804).
                if (h.hidden && !hidden_.active && currentLeg_ != 0 && !currentLegPlanned_ && onLegWay(h)) {
                    hidden_ = HiddenBlock{};
                    hidden_.active = true;
                    hidden_.legId = currentLeg_;
                    hidden_.hazardId = id;
                    hidden_.seenS = e.timeS;
                    hiddenTried_.push_back(id);
                    hidden_.whilePlanning = true;
                }
            }
            break;
        }
        case dev::kLegAchieved:
            legReachedPending_ = true;
            legReachedText_ = body(t);
            break;
        case dev::kBoundRelaxed:
            decisions_.push_back(MissionDecision{e.timeS, "bound relaxed", body(t)});
            if (powerFailUpSeen_ && t.find("power bound relaxed") != std::string::npos && !points_[6].seen) {
                double factor = 0.0, to = 0.0;
                const char* s = after(t, "relaxed x");
                if (s != nullptr && std::sscanf(s, "relaxed x%lf to %lf W", &factor, &to) == 2) {
                    relaxedPowerW_ = to;
                }
                relaxPending_ = true;
                char text[160];
                std::snprintf(text, sizeof text, "power bound relaxed from %.0f W to %.0f W (x%.3f), leg re-sent",
                              powerBoundBeforeW_, relaxedPowerW_, factor);
                relaxText_ = text;
            }
            break;
        case dev::kRiskRelaxed:
            riskRelaxText_ = body(t);
            decisions_.push_back(MissionDecision{e.timeS, "risk relaxed", body(t)});
            break;
        case dev::kReplan:
            replanText_ = body(t);
            decisions_.push_back(MissionDecision{e.timeS, "replan", body(t)});
            break;
        case dev::kLegEndSkipped:
            legEndSkippedS_ = e.timeS;
            decisions_.push_back(MissionDecision{e.timeS, "leg end merged", body(t)});
            break;
        case dev::kNoPlan:
            decisions_.push_back(MissionDecision{e.timeS, "no plan", body(t)});
            break;
        case dev::kFailedDriveModel:
            decisions_.push_back(MissionDecision{e.timeS, "drive model", body(t)});
            if (t.find(" failed:") != std::string::npos) {
                std::string what = body(t);
                if (!replanText_.empty()) {
                    what = replanText_ + "; " + what;
                }
                see(9, e.timeS, "deliberative", what);
            }
            break;
        case dev::kCallHome:
            decisions_.push_back(MissionDecision{e.timeS, "call home", body(t)});
            callHomeEventText_ = t;
            callHomeRiskRelaxText_ = riskRelaxText_;
            safedS_ = -1.0;  // the rover safed after this call home
            seePointTen();
            break;
        case cmdtlm::events::kSafedOnRequest:
            decisions_.push_back(MissionDecision{e.timeS, "safed", body(t)});
            if (!callHomeEventText_.empty() && safedS_ < 0.0) {
                safedS_ = e.timeS;
                safedText_ = body(t);
                seePointTen();
            }
            break;
        case fault_protection::events::kGaveUp:
            gaveUpText_ = "fault protection gave it up at " + seconds(e.timeS);
            decisions_.push_back(MissionDecision{e.timeS, "fault protection", body(t)});
            break;
        case estimator::events::kDriveModeDeclaredNominal:
        case estimator::events::kDriveModeDeclaredDegraded:
        case estimator::events::kDriveModeDeclaredFailed:
        case estimator::events::kDriveModeDeclaredUnknown: {
            const char* s = after(t, "drive_modes: ");
            const int w = s != nullptr ? wheelNamed(s + 13) : -1;
            if (w < 0) {
                break;
            }
            const unsigned bit = 1U << static_cast<unsigned>(w);
            degraded_ &= ~bit;
            failed_ &= ~bit;
            if (e.id == estimator::events::kDriveModeDeclaredDegraded) {
                degraded_ |= bit;
                degradedText_ = body(t) + " at " + seconds(e.timeS);
            } else if (e.id == estimator::events::kDriveModeDeclaredFailed ||
                       e.id == estimator::events::kDriveModeDeclaredUnknown) {
                failed_ |= bit;
                failedText_ = body(t);
                failedS_ = e.timeS;
            }
            decisions_.push_back(MissionDecision{e.timeS, "drive mode", body(t)});
            break;
        }
        default:
            break;
    }
}

std::vector<MissionPoint> TenPointTracker::takeNew() {
    std::vector<MissionPoint> out;
    for (int n : fresh_) {
        out.push_back(points_[static_cast<std::size_t>(n - 1)]);
    }
    fresh_.clear();
    return out;
}

bool TenPointTracker::allInOrder() const {
    for (std::size_t i = 0; i < points_.size(); ++i) {
        if (!points_[i].seen || (i > 0 && points_[i].timeS < points_[i - 1].timeS)) {
            return false;
        }
    }
    return true;
}

std::string TenPointTracker::verdict() const {
    if (allInOrder()) {
        return "ten points: all in order";
    }
    std::string missing;
    std::string disorder;
    double latest = -1.0;
    int latestNumber = 0;
    for (const MissionPoint& p : points_) {
        if (!p.seen) {
            missing += (missing.empty() ? "" : ", ") + std::to_string(p.number);
            continue;
        }
        if (p.timeS < latest) {
            char text[96];
            std::snprintf(text, sizeof text, "%d (%.2f s) before %d (%.2f s)", p.number, p.timeS, latestNumber, latest);
            disorder += (disorder.empty() ? "" : ", ") + std::string(text);
        } else {
            latest = p.timeS;
            latestNumber = p.number;
        }
    }
    std::string out = "ten points: NOT all in order";
    if (!missing.empty()) {
        out += "; missing " + missing;
    }
    if (!disorder.empty()) {
        out += "; out of order " + disorder;
    }
    return out;
}

void TenPointTracker::fill(MissionRecord* r) const {
    r->points = points_;
    r->allInOrder = allInOrder();
    r->verdict = verdict();
    r->hazards = hazards_;
    r->legs = legs_;
    r->decisions = decisions_;
}

std::string TenPointTracker::formatPoint(const MissionPoint& p) {
    char head[64];
    std::snprintf(head, sizeof head, "[%10.3f] POINT %d ", p.timeS, p.number);
    return head + p.layer + ": " + p.what;
}

}  // namespace rse::ground
