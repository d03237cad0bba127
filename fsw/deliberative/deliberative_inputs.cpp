#include "fsw/deliberative/deliberative_inputs.hpp"

#include <cmath>
#include <cstddef>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/msg/goal_msgs.hpp"

namespace rse::deliberative {

namespace {

constexpr std::uint8_t kLargestHabitualState = static_cast<std::uint8_t>(msg::HabitualState::kAchieved);
constexpr std::uint8_t kLargestConstraint = static_cast<std::uint8_t>(msg::LegConstraint::kPower);

constexpr core::InputPipeConfig kFastPipe{"delib_fast", kFastPipeDepth, events::kMalformedInput, "deliberative"};
constexpr core::InputPipeConfig kInputPipe{"deliberative", kInputPipeDepth, events::kMalformedInput, "deliberative"};

core::Status usableIf(bool usable) { return usable ? core::Status::kOk : core::Status::kInvalidArgument; }

}  // namespace

core::Status checkPose(const msg::PoseEstimateMsg& pose) {
    bool ok = std::isfinite(pose.xM) && std::isfinite(pose.yM) && std::isfinite(pose.headingRad);
    for (double c : pose.covariance) {
        ok = ok && std::isfinite(c);
    }
    return usableIf(ok);
}

core::Status checkGoals(const msg::PlanGoalMsg& goal) {
    return usableIf(msg::goalListUsable(goal.goals) && goal.listIndex < msg::kMaxGoals);
}

core::Status checkLegReport(const msg::LegReportMsg& report) {
    return usableIf(static_cast<std::uint8_t>(report.state) <= kLargestHabitualState &&
                    static_cast<std::uint8_t>(report.violated) <= kLargestConstraint);
}

core::Status checkMode(const msg::ModeMsg& mode) { return usableIf(mode.mode < msg::mode::kCount); }

core::Status checkHazards(const msg::KnownHazardsMsg& h) {
    if (h.count > msg::kMaxKnownHazards) {
        return core::Status::kInvalidArgument;
    }
    for (std::size_t i = 0; i < h.count; ++i) {
        const msg::KnownHazard& k = h.hazards[i];
        if (!std::isfinite(k.xM) || !std::isfinite(k.yM) || !std::isfinite(k.radiusM) || !(k.radiusM > 0.0F) ||
            k.radiusM > kMaxHazardRadiusM) {  // obstacleId 0: a contact's disc (habitual map_builder.hpp)
            return core::Status::kInvalidArgument;
        }
    }
    return core::Status::kOk;
}

core::Status checkHold(const msg::MissionHoldMsg& hold) { return usableIf(msg::holdUsable(hold)); }

core::Status checkReplanRequest(const msg::ReplanRequestMsg& request) {
    return usableIf(request.faultId == msg::fault::kOffMap && request.attempt >= 1);
}

DeliberativeInputs::DeliberativeInputs(core::SoftwareBus& bus, core::EventLog& events, Receiver& receiver)
    : receiver_(receiver), fast_(bus, events, kFastPipe), inputs_(bus, events, kInputPipe) {}

core::Status DeliberativeInputs::init() {
    core::Status status = fast_.create();
    if (core::isOk(status)) {
        status = fast_.route<&DeliberativeInputs::pose>(this);
    }
    if (core::isOk(status)) {
        status = fast_.route<&DeliberativeInputs::driveStatus>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.create();
    }
    // Goals come only from the plan executive (PlanGoalMsg): GOTO and the goal
    // list are plans of drive activities it runs (docs/plan_executive.md).
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::goals>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::legReport>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::driveModes>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::mode>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::hazards>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::hold>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::faults>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&DeliberativeInputs::replanRequest>(this);
    }
    return status;
}

core::Status DeliberativeInputs::pose(const msg::PoseEstimateMsg& m) {
    const core::Status status = checkPose(m);
    if (core::isOk(status)) {
        receiver_.takePose(m);
    }
    return status;
}

core::Status DeliberativeInputs::goals(const msg::PlanGoalMsg& m) {
    // The plan executive's drive activity: the goal list in force
    // (docs/plan_executive.md "Dispatch to the devices").
    const core::Status status = checkGoals(m);
    if (core::isOk(status)) {
        receiver_.takeGoals(m);
    }
    return status;
}

core::Status DeliberativeInputs::legReport(const msg::LegReportMsg& m) {
    const core::Status status = checkLegReport(m);
    if (core::isOk(status)) {
        receiver_.takeLegReport(m);
    }
    return status;
}

core::Status DeliberativeInputs::mode(const msg::ModeMsg& m) {
    const core::Status status = checkMode(m);
    if (core::isOk(status)) {
        receiver_.takeMode(m);
    }
    return status;
}

core::Status DeliberativeInputs::hazards(const msg::KnownHazardsMsg& m) {
    const core::Status status = checkHazards(m);
    if (core::isOk(status)) {
        receiver_.takeHazards(m);
    }
    return status;
}

core::Status DeliberativeInputs::hold(const msg::MissionHoldMsg& m) {
    const core::Status status = checkHold(m);
    if (core::isOk(status)) {
        receiver_.takeHold(m);
    }
    return status;
}

core::Status DeliberativeInputs::replanRequest(const msg::ReplanRequestMsg& m) {
    const core::Status status = checkReplanRequest(m);
    if (core::isOk(status)) {
        receiver_.takeReplanRequest(m);
    }
    return status;
}

}  // namespace rse::deliberative
