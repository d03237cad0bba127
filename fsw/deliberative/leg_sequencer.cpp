#include "fsw/deliberative/leg_sequencer.hpp"

#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

std::uint32_t LegSequencer::takeLegId() {
    const std::uint32_t id = nextLegId_;
    nextLegId_ = nextLegId_ == UINT32_MAX ? 1 : nextLegId_ + 1;
    return id;
}

void LegSequencer::newGoals() {
    goalUnconfirmed_ = false;
    powerGrowth_ = 1.0;
    legs_ = LegPlan{};
    index_ = 0;
}

bool LegSequencer::split(const CcPlan& plan, const LegParams& params) {
    return core::isOk(splitPlanIntoLegs(plan, params, &legs_)) && legs_.count > 0;
}

void LegSequencer::begin() {
    index_ = 0;
    legGrowth_ = energyGrowth_ = lengthGrowth_ = 1.0;
    powerGrowth_ = 1.0;  // the new legs are bounded at the power factors of the moment
}

void LegSequencer::widenFirstLeg(const msg::PoseEstimateMsg& pose, const LegParams& params) {
    msg::PlanLeg& first = legs_.legs[0];
    msg::PlanLeg fromRover = first;
    if (core::isOk(legBoundsFrom(pose.xM, pose.yM, pose.headingRad, params, &fromRover))) {
        first.lengthM = fromRover.lengthM > first.lengthM ? fromRover.lengthM : first.lengthM;
        first.energyJ = fromRover.energyJ > first.energyJ ? fromRover.energyJ : first.energyJ;
    }
}

void LegSequencer::send(core::TimeNs now, bool held, double goalRadiusM, const LegEndClearance& clear) {
    (void)mergeLegEnds(clear);
    if (held) {
        // Sent from the pose of the moment when the hold is released.
        leg_ = msg::LegCommandMsg{};
        return;
    }
    const msg::PlanLeg& leg = legs_.legs[index_];
    leg_ = msg::LegCommandMsg{};
    leg_.timeNs = now;
    leg_.legId = takeLegId();
    leg_.finalLeg = index_ + 1 == legs_.count ? 1 : 0;
    leg_.goalXM = leg.xM;
    leg_.goalYM = leg.yM;
    leg_.maxPathLengthM = leg.lengthM;
    leg_.maxEnergyJ = leg.energyJ;
    leg_.maxPowerW = leg.powerW * powerGrowth_;
    // The goal's last leg ends at the goal: the habitual layer may stop
    // anywhere in its region. Earlier legs end at waypoints, reached as points.
    leg_.arriveWithinM = leg_.finalLeg != 0 ? goalRadiusM : 0.0;
    out_.publish(leg_, "leg");
    ++counters_.legsSent;
    cmdtlm::event_data::LEG_SENT data;
    data.leg_id = leg_.legId;
    data.index = static_cast<double>(index_ + 1);
    data.count = static_cast<double>(legs_.count);
    data.x = leg.xM;
    data.y = leg.yM;
    data.length_bound = leg.lengthM;
    data.energy_bound = leg.energyJ;
    data.power_bound = leg_.maxPowerW;
    events_.report(events::kLegSent, core::Severity::kInfo, data.pack(),
                   "deliberative: leg %u (%u of %u) to (%.2f, %.2f): <= %.2f m, <= %.0f J, <= %.0f W, risk %.3g",
                   static_cast<unsigned>(leg_.legId), static_cast<unsigned>(index_ + 1),
                   static_cast<unsigned>(legs_.count), leg.xM, leg.yM, leg.lengthM, leg.energyJ, leg_.maxPowerW,
                   leg.risk);
}

bool LegSequencer::resendFromPose(core::TimeNs now, bool held, double goalRadiusM, const LegEndClearance& clear,
                                  const msg::PoseEstimateMsg& pose, const LegParams& params) {
    if (index_ >= legs_.count) {
        return false;
    }
    msg::PlanLeg& leg = legs_.legs[index_];
    (void)legBoundsFrom(pose.xM, pose.yM, pose.headingRad, params, &leg);
    // The bounds are new (from here), the relaxation the leg earned is not:
    // losing it fails the re-sent leg up again at once.
    leg.energyJ *= energyGrowth_;
    leg.lengthM *= lengthGrowth_;
    leg_.legId = 0;
    send(now, held, goalRadiusM, clear);
    return true;
}

void LegSequencer::sendBackUp(core::TimeNs now, bool held, msg::PlanLeg* target, const msg::PoseEstimateMsg& pose,
                              const LegParams& params) {
    if (held) {
        leg_ = msg::LegCommandMsg{};
        return;
    }
    (void)legBoundsFrom(pose.xM, pose.yM, pose.headingRad, params, target);
    leg_ = msg::LegCommandMsg{};
    leg_.timeNs = now;
    leg_.legId = takeLegId();
    leg_.finalLeg = 0;
    leg_.goalXM = target->xM;
    leg_.goalYM = target->yM;
    leg_.maxPathLengthM = target->lengthM;
    leg_.maxEnergyJ = target->energyJ;
    // The drives' power is the same on every leg: the plan's power bound.
    leg_.maxPowerW = legs_.count > 0 ? legs_.legs[index_ < legs_.count ? index_ : 0].powerW * powerGrowth_ : 0.0;
    out_.publish(leg_, "back-up leg");
    ++counters_.legsSent;
    cmdtlm::event_data::LEG_SENT data;  // index and count 0: a back-up leg, no leg of the plan
    data.leg_id = leg_.legId;
    data.x = target->xM;
    data.y = target->yM;
    data.length_bound = target->lengthM;
    data.energy_bound = target->energyJ;
    data.power_bound = leg_.maxPowerW;
    events_.report(events::kLegSent, core::Severity::kInfo, data.pack(),
                   "deliberative: leg %u (back-up) to (%.2f, %.2f): <= %.2f m, <= %.0f J",
                   static_cast<unsigned>(leg_.legId), target->xM, target->yM, target->lengthM, target->energyJ);
}

bool LegSequencer::achieved() {
    ++counters_.legsAchieved;
    cmdtlm::event_data::LEG_REACHED data;
    data.leg_id = leg_.legId;
    data.index = static_cast<double>(index_ + 1);
    data.count = static_cast<double>(legs_.count);
    events_.report(events::kLegAchieved, core::Severity::kInfo, data.pack(), "deliberative: leg %u reached (%u of %u)",
                   static_cast<unsigned>(leg_.legId), static_cast<unsigned>(index_ + 1),
                   static_cast<unsigned>(legs_.count));
    leg_.legId = 0;
    ++index_;
    legGrowth_ = energyGrowth_ = lengthGrowth_ = 1.0;
    return index_ < legs_.count;
}

void LegSequencer::cancel(core::TimeNs now) {
    msg::LegCommandMsg cancel{};
    cancel.timeNs = now;
    out_.publish(cancel, "leg cancel");
    leg_.legId = 0;
}

bool LegSequencer::legEndTooClose(const LegEndClearance& clear) const {
    return index_ + 1 < legs_.count && clear.tooClose(legs_.legs[index_].xM, legs_.legs[index_].yM);
}

bool LegSequencer::mergeLegEnds(const LegEndClearance& clear) {
    bool moved = false;
    // Bounded: index_ moves on every pass and stops before the last leg.
    while (legEndTooClose(clear)) {
        const msg::PlanLeg skipped = legs_.legs[index_];
        msg::PlanLeg& next = legs_.legs[index_ + 1];
        next.lengthM += skipped.lengthM;
        next.energyJ += skipped.energyJ;
        next.risk += skipped.risk;
        legs_.plannedLengthM[index_ + 1] += legs_.plannedLengthM[index_];
        ++index_;
        ++counters_.legEndsSkipped;
        moved = true;
        events_.report(events::kLegEndSkipped, core::Severity::kWarning,
                       "deliberative: leg end (%.2f, %.2f) too near a rock: merged into leg %u of %u (to (%.2f, %.2f))",
                       skipped.xM, skipped.yM, static_cast<unsigned>(index_ + 1), static_cast<unsigned>(legs_.count),
                       next.xM, next.yM);
    }
    return moved;
}

void LegSequencer::relax(const FailUpAnswer& answer, msg::LegConstraint which) {
    cmdtlm::event_data::BOUND_RELAXED data;
    data.leg_id = leg_.legId;
    data.bound = static_cast<double>(answer.action == FailUpAnswer::Action::kRelaxPower ? msg::LegConstraint::kPower
                                                                                         : which);
    data.factor = answer.needed;
    data.of_planned = answer.grown;
    data.limit = answer.limit;
    if (answer.action == FailUpAnswer::Action::kRelaxPower) {
        data.from = legs_.legs[index_].powerW * powerGrowth_;
        powerGrowth_ = answer.grown;
        data.to = legs_.legs[index_].powerW * powerGrowth_;
        events_.report(events::kBoundRelaxed, core::Severity::kWarning, data.pack(),
                       "deliberative: leg %u power bound relaxed x%.3f to %.0f W (x%.3f of planned, limit x%.2f): "
                       "resent",
                       static_cast<unsigned>(leg_.legId), answer.needed, legs_.legs[index_].powerW * powerGrowth_,
                       answer.grown, answer.limit);
        return;
    }
    if (answer.action != FailUpAnswer::Action::kRelaxBound) {
        return;
    }
    const bool energy = which == msg::LegConstraint::kEnergy;
    msg::PlanLeg& leg = legs_.legs[index_];
    data.from = energy ? leg.energyJ : leg.lengthM;
    (energy ? leg.energyJ : leg.lengthM) *= answer.needed;
    (energy ? energyGrowth_ : lengthGrowth_) *= answer.needed;
    legGrowth_ = answer.grown;
    data.to = energy ? leg.energyJ : leg.lengthM;
    events_.report(events::kBoundRelaxed, core::Severity::kWarning, data.pack(),
                   "deliberative: leg %u %s bound relaxed x%.3f (x%.3f of planned, limit x%.2f): resent",
                   static_cast<unsigned>(leg_.legId), constraintName(which), answer.needed, answer.grown,
                   answer.limit);
}

GoalClaim LegSequencer::claimGoal(const GoalArrival& a) {
    const msg::Goal& goal = *a.goal;
    const msg::PoseEstimateMsg& pose = *a.pose;
    if (a.poseUncertain) {
        if (!goalUnconfirmed_) {
            ++counters_.goalsUnconfirmed;
            events_.report(events::kGoalUnconfirmed, core::Severity::kWarning,
                           "deliberative: goal %u (%.2f, %.2f): last leg reached but the pose is uncertain (sigma "
                           "%.2f m%s): not claimed, waiting",
                           static_cast<unsigned>(a.number), goal.xM, goal.yM, pose.positionSigmaM,
                           a.poseFault ? ", fault 19" : "");
        }
        goalUnconfirmed_ = true;
        return GoalClaim::kUnconfirmed;
    }
    goalUnconfirmed_ = false;
    ++counters_.goalsReached;
    if (goal.radiusM > 0.0F) {
        events_.report(events::kGoalReached, core::Severity::kInfo,
                       "deliberative: goal %u (%.2f, %.2f) reached within %.2f m (%.2f m off)",
                       static_cast<unsigned>(a.number), goal.xM, goal.yM, a.arrivalM,
                       std::hypot(pose.xM - goal.xM, pose.yM - goal.yM));
    } else {
        events_.report(events::kGoalReached, core::Severity::kInfo, "deliberative: goal %u (%.2f, %.2f) reached",
                       static_cast<unsigned>(a.number), goal.xM, goal.yM);
    }
    return GoalClaim::kReached;
}

GoalClaim LegSequencer::reclaimGoal(const GoalArrival& a) {
    if (a.poseUncertain) {
        return GoalClaim::kWaiting;
    }
    const msg::Goal& goal = *a.goal;
    const msg::PoseEstimateMsg& pose = *a.pose;
    const double off = std::hypot(pose.xM - goal.xM, pose.yM - goal.yM);
    if (off <= a.arrivalM) {
        return claimGoal(a);
    }
    goalUnconfirmed_ = false;
    ++counters_.goalLegsResent;
    events_.report(events::kGoalLegResent, core::Severity::kWarning,
                   "deliberative: goal %u: pose certain again %.2f m from the goal: last leg re-sent from (%.2f, %.2f)",
                   static_cast<unsigned>(a.number), off, pose.xM, pose.yM);
    index_ = legs_.count > 0 ? legs_.count - 1 : 0;
    return GoalClaim::kResend;
}

}  // namespace rse::deliberative
