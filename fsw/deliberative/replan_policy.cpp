#include "fsw/deliberative/replan_policy.hpp"

#include <cmath>

#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

const char* constraintName(msg::LegConstraint c) {
    switch (c) {
        case msg::LegConstraint::kNone: return "none";
        case msg::LegConstraint::kPathLength: return "path length";
        case msg::LegConstraint::kEnergy: return "energy";
        case msg::LegConstraint::kNoPath: return "no path";
        case msg::LegConstraint::kCannotFollow: return "cannot follow";
        case msg::LegConstraint::kBadLeg: return "leg refused";
        case msg::LegConstraint::kPower: return "power";
    }
    return "?";
}

const char* callHomeReasonName(msg::CallHomeReason r) {
    switch (r) {
        case msg::CallHomeReason::kNone: return "none";
        case msg::CallHomeReason::kNoPlanWithinRisk: return "no plan within the risk limit";
        case msg::CallHomeReason::kGoalUnreachable: return "goal unreachable";
        case msg::CallHomeReason::kReplansExhausted: return "replans exhausted";
        case msg::CallHomeReason::kInsufficientPower: return "insufficient power";
        case msg::CallHomeReason::kMobilityLost: return "mobility lost";
        case msg::CallHomeReason::kFaultUnrecovered: return "fault unrecovered";
        case msg::CallHomeReason::kPlanNoMethod: return "no plan method remains";
    }
    return "?";
}

void ReplanPolicy::newGoals() {
    riskFactor_ = 1.0;
    goalReplans_ = 0;
    goalInformedReplans_ = 0;
    request_.pending = false;
}

void ReplanPolicy::nextGoal() {
    goalReplans_ = 0;
    goalInformedReplans_ = 0;
    riskFactor_ = 1.0;
}

double ReplanPolicy::riskInForce(double operatorBound) const {
    const double risk = operatorBound * riskFactor_;
    return risk < kMaxRiskInForce ? risk : kMaxRiskInForce;
}

FailUpAnswer ReplanPolicy::answerFailUp(const msg::LegReportMsg& report, double legGrowth, double powerGrowth,
                                        double boundRelaxLimit) {
    const bool power = report.violated == msg::LegConstraint::kPower;
    const bool energy = report.violated == msg::LegConstraint::kEnergy;
    const double predictedFigure =
        power ? report.predictedPowerW : (energy ? report.predictedEnergyJ : report.predictedLengthM);
    const double allowedFigure = power ? report.allowedPowerW : (energy ? report.allowedEnergyJ : report.allowedLengthM);
    events_.report(events::kFailUpReceived, core::Severity::kWarning,
                   "deliberative: leg %u failed up: %s (predicted %.1f, allowed %.1f, excess %.1f)",
                   static_cast<unsigned>(report.legId), constraintName(report.violated), predictedFigure,
                   allowedFigure, report.excess);
    FailUpAnswer answer;
    answer.limit = boundRelaxLimit;
    if (!power && !energy && report.violated != msg::LegConstraint::kPathLength) {
        return answer;  // no bound can make a path: replan
    }
    // Power: the drives' power is the same on every leg, so the bound grows
    // for the rest of the plan, within the same limit as a leg's other bounds.
    answer.needed = predictedFigure / allowedFigure * kBoundRelaxHeadroom;
    answer.grown = (power ? powerGrowth : legGrowth) * answer.needed;
    if (std::isfinite(answer.needed) && allowedFigure > 0.0 && answer.needed > 1.0 && answer.grown <= boundRelaxLimit) {
        answer.action = power ? FailUpAnswer::Action::kRelaxPower : FailUpAnswer::Action::kRelaxBound;
        ++boundRelaxations_;
        powerRelaxations_ += power ? 1U : 0U;
    }
    return answer;
}

void ReplanPolicy::capture(msg::LegConstraint why, const ReplanFrom& from) {
    const msg::PoseEstimateMsg& pose = *from.pose;
    ReplanRequest& rr = request_;
    rr.timeNs = from.now;
    rr.poseTimeNs = pose.timeNs;
    rr.xM = pose.xM;
    rr.yM = pose.yM;
    rr.headingRad = pose.headingRad;
    rr.cov[0] = pose.covariance[0];
    rr.cov[1] = pose.covariance[1];
    rr.cov[2] = pose.covariance[3];
    rr.cov[3] = pose.covariance[4];
    rr.firstGoal = from.goalIndex;
    rr.unfinished = static_cast<std::uint8_t>(from.goalCount > from.goalIndex ? from.goalCount - from.goalIndex : 0);
    rr.why = why;
    rr.pending = true;
}

bool ReplanPolicy::replan(msg::LegConstraint why, const ReplanFrom& from, std::uint32_t replanLimit) {
    const bool informed = from.informed && goalInformedReplans_ < kMaxInformedReplans;
    if (!informed && goalReplans_ >= replanLimit) {
        return false;
    }
    goalReplans_ += informed ? 0U : 1U;
    goalInformedReplans_ += informed ? 1U : 0U;
    ++replans_;
    capture(why, from);
    const ReplanRequest& rr = request_;
    events_.report(events::kReplan, core::Severity::kWarning,
                   "deliberative: replan %u/%u%s (%s) t=%.2f s from (%.2f, %.2f): goals %u..%u left, %u hazards",
                   static_cast<unsigned>(goalReplans_), static_cast<unsigned>(replanLimit),
                   informed ? " (new sightings: not counted)" : "", constraintName(why),
                   static_cast<double>(from.now) / static_cast<double>(core::kNsPerSec), rr.xM, rr.yM,
                   static_cast<unsigned>(rr.firstGoal), static_cast<unsigned>(rr.firstGoal + rr.unfinished - 1),
                   static_cast<unsigned>(from.seenHazards));
    return true;
}

StartPoint ReplanPolicy::takeStart(core::TimeNs now, const msg::PoseEstimateMsg& pose) {
    ReplanRequest& rr = request_;
    const bool replanning = rr.pending;
    if (replanning && now - rr.poseTimeNs > kReplanMaxAgeNs) {
        // Too old to start from: the rover may stand elsewhere now.
        rr.poseTimeNs = pose.timeNs;
        rr.xM = pose.xM;
        rr.yM = pose.yM;
        rr.headingRad = pose.headingRad;
        rr.cov[0] = pose.covariance[0];
        rr.cov[1] = pose.covariance[1];
        rr.cov[2] = pose.covariance[3];
        rr.cov[3] = pose.covariance[4];
    }
    rr.pending = false;
    StartPoint start;
    start.xM = replanning ? rr.xM : pose.xM;
    start.yM = replanning ? rr.yM : pose.yM;
    start.cov[0] = replanning ? rr.cov[0] : pose.covariance[0];
    start.cov[1] = replanning ? rr.cov[1] : pose.covariance[1];
    start.cov[2] = replanning ? rr.cov[2] : pose.covariance[3];
    start.cov[3] = replanning ? rr.cov[3] : pose.covariance[4];
    return start;
}

bool ReplanPolicy::relaxRisk(double plannedRisk, double operatorBound, double riskRelaxLimit) {
    if (!(riskFactor_ < riskRelaxLimit && plannedRisk < kMaxRiskInForce)) {
        return false;
    }
    const double next = riskFactor_ * kRiskRelaxStep;
    riskFactor_ = next < riskRelaxLimit ? next : riskRelaxLimit;
    ++riskRelaxations_;
    // The value the next plan uses, cap included (it said "relaxed to 1"
    // for an operator's 0.1 while 0.49 was planned to).
    const double relaxed = riskInForce(operatorBound);
    const bool capped = operatorBound * riskFactor_ > relaxed;
    events_.report(events::kRiskRelaxed, core::Severity::kWarning,
                   "deliberative: risk bound relaxed to %.3g (the operator's %.3g x%.3g%s, limit x%.3g)", relaxed,
                   operatorBound, relaxed / operatorBound, capped ? ", capped below 0.5" : "", riskRelaxLimit);
    return true;
}

msg::CallHomeReason ReplanPolicy::exhaustedReason(msg::LegConstraint why) {
    return why == msg::LegConstraint::kEnergy || why == msg::LegConstraint::kPower
               ? msg::CallHomeReason::kInsufficientPower
               : msg::CallHomeReason::kReplansExhausted;
}

}  // namespace rse::deliberative
