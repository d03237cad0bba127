#include "fsw/habitual/input_checks.hpp"

#include <cmath>

#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/goal_msgs.hpp"

namespace rse::habitual {

bool poseFinite(const msg::PoseEstimateMsg& pose) {
    return std::isfinite(pose.xM) && std::isfinite(pose.yM) && std::isfinite(pose.headingRad) &&
           std::isfinite(pose.speedMS) && std::isfinite(pose.yawRateRadS);
}

bool modeUsable(const msg::ModeMsg& mode) { return mode.mode < msg::mode::kCount; }

bool hazardsUsable(const msg::HazardMsg& hazards) { return hazards.count <= msg::kMaxHazardsInMsg; }

bool driveModesUsable(const msg::DriveModesMsg& modes) {
    for (const msg::DriveModeBelief& drive : modes.drives) {
        if (!std::isfinite(drive.powerFactor) || drive.powerFactor < 0.0F || drive.powerFactor > kLargestPowerFactor ||
            static_cast<std::uint8_t>(drive.declared) >= msg::kDriveModeCount) {
            return false;
        }
    }
    return true;
}

bool followerStatusUsable(const msg::FollowerStatusMsg& status) {
    return static_cast<std::uint8_t>(status.state) <= static_cast<std::uint8_t>(msg::FollowerState::kBackingOff) &&
           static_cast<std::uint8_t>(status.reason) <= static_cast<std::uint8_t>(msg::FollowReason::kContact);
}

bool contactUsable(const msg::ContactMsg& contact) {
    return std::isfinite(contact.xM) && std::isfinite(contact.yM) && std::isfinite(contact.headingRad) &&
           (contact.directionSign == 1.0 || contact.directionSign == -1.0) && std::fabs(contact.xM) <= 1.0e6 &&
           std::fabs(contact.yM) <= 1.0e6;
}

const char* legRefusal(const msg::LegCommandMsg& leg, bool autonomous, std::uint32_t currentLegId,
                       const tables::CoarseMapTable& coarse) {
    if (!autonomous) {
        return "not in AUTONOMOUS mode";
    }
    if (leg.legId == currentLegId) {
        return "leg id not new";
    }
    if (!std::isfinite(leg.goalXM) || !std::isfinite(leg.goalYM)) {
        return "goal not finite";
    }
    if (geometry::outsideBy(geometry::siteBox(coarse, 0.0), leg.goalXM, leg.goalYM) > 0.0) {
        return "goal off the coarse map";
    }
    if (!std::isfinite(leg.maxPathLengthM) || leg.maxPathLengthM <= 0.0) {
        return "path length bound not positive and finite";
    }
    if (!std::isfinite(leg.maxEnergyJ) || leg.maxEnergyJ <= 0.0) {
        return "energy bound not positive and finite";
    }
    if (!std::isfinite(leg.maxPowerW) || leg.maxPowerW < 0.0) {
        return "power bound negative or not finite";
    }
    if (!(leg.arriveWithinM >= 0.0 && leg.arriveWithinM <= static_cast<double>(msg::kMaxGoalRadiusM))) {
        return "arrival radius negative, too large or not finite";
    }
    return nullptr;
}

}  // namespace rse::habitual
