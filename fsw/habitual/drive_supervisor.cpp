#include "fsw/habitual/drive_supervisor.hpp"

#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::habitual {

using geometry::Point2;
using geometry::wrapAngleRad;
using rover_model::motionEnergyJ;
using rover_model::PowerModel;
using rover_model::powerModelFrom;

namespace {

const char* followReasonName(msg::FollowReason reason) {
    switch (reason) {
        case msg::FollowReason::kNone:
            return "no reason";
        case msg::FollowReason::kCrossTrackError:
            return "cross-track error";
        case msg::FollowReason::kPoseStale:
            return "pose stale";
        case msg::FollowReason::kDrivesHeld:
            return "drives held";
        case msg::FollowReason::kNotAutonomous:
            return "not autonomous";
        case msg::FollowReason::kBadTrajectory:
            return "bad trajectory";
        case msg::FollowReason::kContact:
            return "contact";
    }
    return "?";
}

}  // namespace

void DriveSupervisor::beginLeg() {
    drivenLengthM_ = 0.0;
    drivenEnergyJ_ = 0.0;
    anchorSet_ = false;
    cannotFollowReplans_ = 0;
}

void DriveSupervisor::updateOdometry(const msg::PoseEstimateMsg& pose, double powerFactor) {
    if (pose.initialised == 0) {
        return;
    }
    const Point2 here{pose.xM, pose.yM};
    if (!anchorSet_) {
        anchor_ = here;
        anchorHeading_ = pose.headingRad;
        anchorSet_ = true;
        return;
    }
    const PowerModel model = powerModelFrom(habitual_);
    const double moved = distance(here, anchor_);
    if (moved >= kOdometryStepM) {
        drivenLengthM_ += moved;
        drivenEnergyJ_ += motionEnergyJ(model, moved, 0.0, powerFactor);
        anchor_ = here;
    }
    const double turned = std::fabs(wrapAngleRad(pose.headingRad - anchorHeading_));
    if (turned >= kOdometryStepRad) {
        drivenEnergyJ_ += motionEnergyJ(model, 0.0, turned, powerFactor);
        anchorHeading_ = pose.headingRad;
    }
}

void DriveSupervisor::followPlan(double powerFactor) {
    progressIndex_ = 0;
    predictedFactor_ = powerFactor;
}

std::size_t DriveSupervisor::remainingPath(const msg::TrajectoryMsg& t, Point2 here, Point2* out) {
    const std::size_t count = t.count < msg::kMaxTrajectoryPoints ? t.count : msg::kMaxTrajectoryPoints;
    if (count < 2) {
        return 0;
    }
    std::size_t best = progressIndex_ < count - 1 ? progressIndex_ : count - 2;
    Point2 bestPoint{0.0, 0.0};
    double bestD2 = INFINITY;
    for (std::size_t i = best; i + 1 < count; ++i) {
        const Point2 a{t.points[i].xM, t.points[i].yM};
        const Point2 b{t.points[i + 1].xM, t.points[i + 1].yM};
        const Point2 q = closestOnSegment(here, a, b);
        const double d2 = distanceSquared(here, q);
        if (d2 < bestD2) {
            bestD2 = d2;
            bestPoint = q;
            best = i;
        }
    }
    progressIndex_ = best;
    std::size_t n = 0;
    out[n++] = bestPoint;
    for (std::size_t i = best + 1; i < count; ++i) {
        out[n++] = Point2{t.points[i].xM, t.points[i].yM};
    }
    return n;
}

bool DriveSupervisor::pathBlocked(const msg::TrajectoryMsg& t, Point2 here, const HazardMemory& memory,
                                  std::uint32_t legId) {
    const LocalMap& checkMap = memory.checkMap();
    const std::size_t n = remainingPath(t, here, remaining_);
    remainingCount_ = n;
    for (std::size_t i = 0; i + 1 < n; ++i) {
        if (checkMap.segmentFree(remaining_[i], remaining_[i + 1])) {
            continue;
        }
        ++counters_.pathBlocked;
        // Name the remembered disc that blocks it (the coarse map did not change).
        const double clearance = checkMap.clearance();
        const RememberedHazard* blocker = nullptr;
        for (std::size_t k = 0; k < kMaxMapDiscs && blocker == nullptr; ++k) {
            const RememberedHazard& h = memory.builder().slot(k);
            const double reach = h.radiusM + clearance;
            if (h.used && pointSegmentDistanceSquared(h.centre, remaining_[i], remaining_[i + 1]) <= reach * reach) {
                blocker = &h;
            }
        }
        cmdtlm::event_data::PATH_BLOCKED data;
        data.leg_id = legId;
        if (blocker != nullptr) {
            data.hazard = blocker->obstacleId;
            data.x = blocker->centre.x;
            data.y = blocker->centre.y;
            data.radius = blocker->radiusM;
            events_.report(events::kPathBlocked, core::Severity::kWarning, data.pack(),
                           "habitual: leg %u: hazard %u at (%.2f, %.2f) r %.2f m on the path: stop, replan",
                           static_cast<unsigned>(legId), static_cast<unsigned>(blocker->obstacleId),
                           blocker->centre.x, blocker->centre.y, blocker->radiusM);
        } else {
            data.x = remaining_[i + 1].x;  // no disc named (hazard 0): the point it cannot reach
            data.y = remaining_[i + 1].y;
            events_.report(events::kPathBlocked, core::Severity::kWarning, data.pack(),
                           "habitual: leg %u: path to (%.2f, %.2f) blocked: stop and replan",
                           static_cast<unsigned>(legId), remaining_[i + 1].x, remaining_[i + 1].y);
        }
        return true;
    }
    return false;
}

FactorCheck DriveSupervisor::checkPowerFactors(const msg::TrajectoryMsg& t, const msg::PoseEstimateMsg& pose,
                                               const CandidateEvaluator& evaluator, const LegProgress& progress,
                                               std::uint32_t legId) {
    FactorCheck check{FactorVerdict::kUnchanged, Evaluation{}, Evaluation{}};
    const double factor = progress.powerFactor;
    if (factor == predictedFactor_) {
        return check;
    }
    predictedFactor_ = factor;
    remainingCount_ = remainingPath(t, Point2{pose.xM, pose.yM}, remaining_);
    const Evaluation e = evaluator.evaluate(remaining_, remainingCount_, pose.headingRad, progress);
    check.evaluation = e;
    if (e.violated == msg::LegConstraint::kPower) {
        check.verdict = FactorVerdict::kPower;  // no path mends it
        return check;
    }
    if (e.energyJ <= e.allowedEnergyJ) {
        check.verdict = FactorVerdict::kHolds;
        return check;
    }
    ++counters_.energyViolations;
    events_.report(events::kEnergyViolated, core::Severity::kWarning,
                   "habitual: leg %u power factor %.2f: %.0f J left > allowed %.0f J: repair",
                   static_cast<unsigned>(legId), factor, e.energyJ, e.allowedEnergyJ);
    check.asEnergy = e;
    if (check.asEnergy.violated != msg::LegConstraint::kEnergy) {
        check.asEnergy.violated = msg::LegConstraint::kEnergy;
        check.asEnergy.excess = e.energyJ - e.allowedEnergyJ;
    }
    check.verdict = FactorVerdict::kEnergy;
    return check;
}

FollowerVerdict DriveSupervisor::judgeFollower(const msg::FollowerStatusMsg& status, const msg::TrajectoryMsg& t,
                                               bool escaping, std::uint32_t legId) {
    if (t.count == 0 || status.trajectoryId != t.trajectoryId) {
        return FollowerVerdict::kNothing;  // about a trajectory no longer in force
    }
    if (status.state == msg::FollowerState::kReached) {
        return escaping ? FollowerVerdict::kEscapeDone : FollowerVerdict::kReached;
    }
    if (status.state != msg::FollowerState::kCannotFollow) {
        return FollowerVerdict::kNothing;
    }
    ++counters_.cannotFollow;
    const bool hopeless = status.reason == msg::FollowReason::kDrivesHeld ||
                          status.reason == msg::FollowReason::kNotAutonomous || cannotFollowReplans_ > 0;
    events_.report(events::kCannotFollow, core::Severity::kWarning, "habitual: leg %u: follower gave up (%s): %s",
                   static_cast<unsigned>(legId), followReasonName(status.reason),
                   hopeless ? "fail-up" : "replanning once");
    if (hopeless) {
        return FollowerVerdict::kFailUp;
    }
    ++cannotFollowReplans_;
    return FollowerVerdict::kReplan;
}

}  // namespace rse::habitual
