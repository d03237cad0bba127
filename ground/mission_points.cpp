#include "ground/mission_points.hpp"

#include <cmath>
#include <cstdio>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/estimator/drive_mode_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/mission_text.hpp"

namespace rse::ground {

namespace {

namespace dev = deliberative::events;
namespace hev = habitual::events;
namespace pev = plan_executive::events;
namespace evd = cmdtlm::event_data;

// An id or a count as the event's numbers carry it (a double holding an integer).
std::uint32_t whole(double value) { return value >= 0.0 ? static_cast<std::uint32_t>(value) : 0U; }

}  // namespace

// The table onEvent looks ids up in: every event the ten points, the legs,
// the hazards or the decisions list read.
const TenPointTracker::Route TenPointTracker::kRoutes[] = {
    {pev::kGoalsCommanded, pev::kGoalsCommanded, &TenPointTracker::onGoalsCommanded},
    {dev::kPlanFound, dev::kPlanFound, &TenPointTracker::onPlanFound},
    {dev::kLegSent, dev::kLegSent, &TenPointTracker::onLegSent},
    {hev::kPlanSent, hev::kPlanSent, &TenPointTracker::onPlanSent},
    {hev::kPathBlocked, hev::kPathBlocked, &TenPointTracker::onPathBlocked},
    {hev::kMinorAnomaly, hev::kMinorAnomaly, &TenPointTracker::onMinorAnomaly},
    {hev::kFailUp, hev::kFailUp, &TenPointTracker::onHabitualFailUp},
    {hev::kLegAchieved, hev::kLegAchieved, &TenPointTracker::onHabitualLegAchieved},
    {hev::kHazardRemembered, hev::kHazardRemembered, &TenPointTracker::onHazardRemembered},
    {dev::kLegAchieved, dev::kLegAchieved, &TenPointTracker::onLegReached},
    {dev::kBoundRelaxed, dev::kBoundRelaxed, &TenPointTracker::onBoundRelaxed},
    {dev::kRiskRelaxed, dev::kRiskRelaxed, &TenPointTracker::onRiskRelaxed},
    {dev::kReplan, dev::kReplan, &TenPointTracker::onReplan},
    {dev::kLegEndSkipped, dev::kLegEndSkipped, &TenPointTracker::onLegEndSkipped},
    {dev::kNoPlan, dev::kNoPlan, &TenPointTracker::onNoPlan},
    {dev::kFailedDriveModel, dev::kFailedDriveModel, &TenPointTracker::onFailedDriveModel},
    {dev::kCallHome, dev::kCallHome, &TenPointTracker::onCallHome},
    {cmdtlm::events::kSafedOnRequest, cmdtlm::events::kSafedOnRequest, &TenPointTracker::onSafed},
    {fault_protection::events::kGaveUp, fault_protection::events::kGaveUp, &TenPointTracker::onGaveUp},
    {estimator::events::kDriveModeDeclaredNominal, estimator::events::kDriveModeDeclaredUnknown,
     &TenPointTracker::onDriveMode},
};

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

void TenPointTracker::onEvent(const FlightEvent& e) {
    for (const Route& r : kRoutes) {
        if (e.id >= r.firstId && e.id <= r.lastId) {
            (this->*r.handler)(e);
            return;
        }
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
    if (!callHomeSeen_ || safedS_ < 0.0 || points_[9].seen) {
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

void TenPointTracker::decide(const FlightEvent& e, const char* kind) {
    decisions_.push_back(MissionDecision{e.timeS, kind, eventWords(e.text)});
}

double TenPointTracker::fact(int number, const std::string& name) const {
    if (number < 1 || number > kMissionPointCount) {
        return std::nan("");
    }
    const MissionPoint& p = points_[static_cast<std::size_t>(number - 1)];
    const auto f = p.facts.find(name);
    return f == p.facts.end() ? std::nan("") : f->second;
}

LegRecord* TenPointTracker::leg(std::uint32_t id) {
    for (LegRecord& l : legs_) {
        if (l.legId == id) {
            return &l;
        }
    }
    return nullptr;
}

void TenPointTracker::onGoalsCommanded(const FlightEvent& e) {
    evd::GOALS_COMMANDED goals;
    if (e.read(&goals) && goals.goal_count > 0.0) {
        setFact(1, "risk bound", goals.risk_bound);
        see(1, e.timeS, "operator",
            "authenticated GOTO taken by the flight software: " + eventWords(e.text) + " (its only source of goals is an "
            "accepted command)");
    }
}

void TenPointTracker::onPlanFound(const FlightEvent& e) {
    if (firstPlan_.empty()) {
        firstPlan_ = eventWords(e.text);
    }
    planPending_ = true;
    decide(e, "plan");
}

void TenPointTracker::onLegSent(const FlightEvent& e) {
    evd::LEG_SENT sent;
    if (!e.read(&sent)) {
        // A leg whose numbers were lost: it is the leg points 2 and 4 waited
        // for, so they cannot be shown from it (nor from a later one).
        planPending_ = false;
        legReachedPending_ = false;
        return;
    }
    LegRecord l;
    l.sentS = e.timeS;
    l.legId = whole(sent.leg_id);
    l.xM = sent.x;
    l.yM = sent.y;
    l.lengthBoundM = sent.length_bound;
    l.energyBoundJ = sent.energy_bound;
    l.powerBoundW = sent.power_bound;
    if (LegRecord* previous = leg(currentLeg_); previous != nullptr && previous->outcome.empty()) {
        previous->outcome = "superseded";
    }
    hiddenObstacleLegReplaced(e, l.legId);
    currentLeg_ = l.legId;
    currentLegPlanned_ = false;
    legFromX_ = poseX_;
    legFromY_ = poseY_;
    legToX_ = l.xM;
    legToY_ = l.yM;
    legs_.push_back(l);
    hiddenObstacleBeforeLeg();
    if (planPending_) {
        planPending_ = false;
        setFact(2, "power bound W", l.powerBoundW);
        setFact(2, "energy bound J", l.energyBoundJ);
        char bounds[160];
        std::snprintf(bounds, sizeof bounds, "; leg %u of %u to (%.2f, %.2f) within <= %.2f m, <= %.0f J, <= %.0f W",
                      static_cast<unsigned>(whole(sent.index)), static_cast<unsigned>(whole(sent.count)), l.xM, l.yM,
                      l.lengthBoundM, l.energyBoundJ, l.powerBoundW);
        see(2, e.timeS, "deliberative", "plan on the coarse map: " + firstPlan_ + bounds);
    }
    if (legReachedPending_) {
        legReachedPending_ = false;
        char next[96];
        std::snprintf(next, sizeof next, "; next issued: leg %u to (%.2f, %.2f)", static_cast<unsigned>(l.legId), l.xM,
                      l.yM);
        see(4, e.timeS, "habitual + deliberative", legReachedText_ + next);
    }
    if (relaxPending_ && relaxedPowerW_ <= 0.0) {
        relaxedPowerW_ = l.powerBoundW;
    }
}

void TenPointTracker::onPlanSent(const FlightEvent& e) {
    lastPlanSent_ = eventWords(e.text);
    hiddenObstaclePlanned(e);
    currentLegPlanned_ = true;
    if (!points_[2].seen) {
        see(3, e.timeS, "habitual", "local plan on the fine map within the leg's bounds, driving: " + eventWords(e.text));
    }
    if (relaxPending_) {
        relaxPending_ = false;
        setFact(7, "power bound before W", powerBoundBeforeW_);
        setFact(7, "power bound after W", relaxedPowerW_);
        see(7, e.timeS, "deliberative + habitual", relaxText_ + "; driving resumed: " + eventWords(e.text));
    }
}

void TenPointTracker::onHabitualFailUp(const FlightEvent& e) {
    evd::HABITUAL_FAIL_UP failUp;
    const bool known = e.read(&failUp);
    const std::uint32_t legId = known ? whole(failUp.leg_id) : 0U;
    const auto constraint = static_cast<msg::LegConstraint>(known ? whole(failUp.constraint) : 0U);
    if (LegRecord* l = leg(legId)) {
        l->outcome = std::string("failed up: ") + habitual::constraintName(constraint);
    }
    decide(e, "fail-up");
    const bool power = known && constraint == msg::LegConstraint::kPower;
    hiddenObstacleFailedUp(e, legId, power);
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
        what += "leg " + std::to_string(legId) + "'s power bound no longer met: " + eventWords(e.text);
        see(6, e.timeS, "estimator + habitual", what);
    } else if (failed_ != 0U) {
        // 8: the motor failed; the habitual layer fails up again.
        std::string what = "drive " + failedText_ + " at " + secondsText(failedS_);
        if (!gaveUpText_.empty()) {
            what += " (" + gaveUpText_ + ")";
        }
        what += "; " + eventWords(e.text);
        see(8, e.timeS, "estimator + habitual", what);
    }
}

void TenPointTracker::onHabitualLegAchieved(const FlightEvent& e) {
    evd::LEG_ACHIEVED achieved;
    if (!e.read(&achieved)) {
        return;
    }
    const std::uint32_t legId = whole(achieved.leg_id);
    if (LegRecord* l = leg(legId)) {
        l->outcome = "achieved";
        l->drivenM = achieved.driven_length;
        l->drivenJ = achieved.driven_energy;
    }
    if (hidden_.active && hidden_.legId == legId) {
        completePointFive(e.timeS, "leg achieved, no fail-up");
    }
}

void TenPointTracker::onLegReached(const FlightEvent& e) {
    legReachedPending_ = true;
    legReachedText_ = eventWords(e.text);
}

void TenPointTracker::onBoundRelaxed(const FlightEvent& e) {
    decide(e, "bound relaxed");
    evd::BOUND_RELAXED relaxed;
    const bool power =
        e.read(&relaxed) && whole(relaxed.bound) == static_cast<std::uint32_t>(msg::LegConstraint::kPower);
    if (powerFailUpSeen_ && power && !points_[6].seen) {
        relaxedPowerW_ = relaxed.to;
        relaxPending_ = true;
        char text[160];
        std::snprintf(text, sizeof text, "power bound relaxed from %.0f W to %.0f W (x%.3f), leg re-sent",
                      powerBoundBeforeW_, relaxedPowerW_, relaxed.factor);
        relaxText_ = text;
    }
}

void TenPointTracker::onRiskRelaxed(const FlightEvent& e) {
    riskRelaxText_ = eventWords(e.text);
    decide(e, "risk relaxed");
}

void TenPointTracker::onReplan(const FlightEvent& e) {
    replanText_ = eventWords(e.text);
    decide(e, "replan");
}

void TenPointTracker::onLegEndSkipped(const FlightEvent& e) {
    legEndSkippedS_ = e.timeS;
    decide(e, "leg end merged");
}

void TenPointTracker::onNoPlan(const FlightEvent& e) { decide(e, "no plan"); }

void TenPointTracker::onFailedDriveModel(const FlightEvent& e) {
    decide(e, "drive model");
    evd::FAILED_DRIVE_MODEL model;
    if (e.read(&model) && whole(model.failed_drives) != 0U) {
        std::string what = eventWords(e.text);
        if (!replanText_.empty()) {
            what = replanText_ + "; " + what;
        }
        see(9, e.timeS, "deliberative", what);
    }
}

void TenPointTracker::onCallHome(const FlightEvent& e) {
    decide(e, "call home");
    callHomeSeen_ = true;
    callHomeEventText_ = e.text;
    callHomeRiskRelaxText_ = riskRelaxText_;
    safedS_ = -1.0;  // the rover safed after this call home
    seePointTen();
}

void TenPointTracker::onSafed(const FlightEvent& e) {
    decide(e, "safed");
    if (callHomeSeen_ && safedS_ < 0.0) {
        safedS_ = e.timeS;
        safedText_ = eventWords(e.text);
        seePointTen();
    }
}

void TenPointTracker::onGaveUp(const FlightEvent& e) {
    gaveUpText_ = "fault protection gave it up at " + secondsText(e.timeS);
    decide(e, "fault protection");
}

void TenPointTracker::onDriveMode(const FlightEvent& e) {
    evd::DRIVE_MODE_DECLARED declared;
    if (!e.read(&declared) || declared.wheel < 0.0 || declared.wheel >= static_cast<double>(msg::kWheelCount)) {
        return;
    }
    const unsigned bit = 1U << whole(declared.wheel);
    const auto to = static_cast<msg::DriveMode>(whole(declared.to));
    degraded_ &= ~bit;
    failed_ &= ~bit;
    if (to == msg::DriveMode::kDegraded) {
        degraded_ |= bit;
        degradedText_ = eventWords(e.text) + " at " + secondsText(e.timeS);
    } else if (to == msg::DriveMode::kFailed || to == msg::DriveMode::kUnknown) {
        failed_ |= bit;
        failedText_ = eventWords(e.text);
        failedS_ = e.timeS;
    }
    decide(e, "drive mode");
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
