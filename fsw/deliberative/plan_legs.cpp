#include "fsw/deliberative/plan_legs.hpp"

#include <cmath>

#include "fsw/geometry/geometry2d.hpp"

namespace rse::deliberative {

namespace {

using geometry::Point2;

bool paramsUsable(const LegParams& p) {
    return std::isfinite(p.spacingM) && p.spacingM > 0.0 && std::isfinite(p.slackFrac) && p.slackFrac >= 0.0 &&
           std::isfinite(p.distanceMarginFrac) && p.distanceMarginFrac >= 0.0 && p.distanceMarginFrac < 1.0 &&
           std::isfinite(p.powerMarginFrac) && p.powerMarginFrac >= 0.0 && p.powerMarginFrac < 1.0 &&
           std::isfinite(p.powerSlackFrac) && p.powerSlackFrac >= 0.0 && std::isfinite(p.cruiseSpeedMS) &&
           p.cruiseSpeedMS > 0.0 && std::isfinite(p.meanPowerFactor) && p.meanPowerFactor >= 1.0 &&
           std::isfinite(p.headingRad);
}

double headingOf(Point2 from, Point2 to) { return std::atan2(to.y - from.y, to.x - from.x); }

}  // namespace

core::Status splitPlanIntoLegs(const CcPlan& plan, const LegParams& params, LegPlan* out) {
    *out = LegPlan{};
    const bool hasPath = plan.status == CcStatus::kOptimal || plan.status == CcStatus::kFeasible;
    if (!hasPath || plan.steps == 0 || plan.steps > kMaxPlanSteps || !paramsUsable(params)) {
        return core::Status::kInvalidArgument;
    }
    // Corners: the distinct means where the path turns, with the risk of the
    // plan segments that reach each one.
    Point2 corner[kMaxPlanSteps + 1];
    double risk[kMaxPlanSteps + 1] = {};
    std::size_t corners = 1;
    corner[0] = Point2{plan.meanX[0], plan.meanY[0]};
    double pendingRisk = 0.0;
    for (std::size_t t = 1; t <= plan.steps; ++t) {
        const Point2 p{plan.meanX[t], plan.meanY[t]};
        if (!geometry::isFinite(p)) {
            return core::Status::kInvalidArgument;
        }
        pendingRisk += plan.segmentRisk[t - 1];
        const bool last = t == plan.steps;
        if (geometry::distance(p, corner[corners - 1]) < kMinLegM && !last) {
            continue;  // coincident or too close: merged into the next corner
        }
        if (corners >= 2 && !last) {
            // Straight on through the previous corner? Drop it (its risk moves on).
            const double turn = geometry::wrapAngleRad(headingOf(corner[corners - 1], p) -
                                                       headingOf(corner[corners - 2], corner[corners - 1]));
            if (std::fabs(turn) < kCornerRad) {
                pendingRisk += risk[corners - 1];
                --corners;
            }
        }
        if (last && corners >= 2 && geometry::distance(p, corner[corners - 1]) < kMinLegM) {
            pendingRisk += risk[corners - 1];
            --corners;  // the goal replaces a corner just before it
        }
        corner[corners] = p;
        risk[corners] = pendingRisk;
        pendingRisk = 0.0;
        ++corners;
    }
    // Runs between corners, cut into pieces of at most spacingM.
    const std::size_t runs = corners - 1;
    const double powerW = rover_model::cruisePowerW(params.power, params.cruiseSpeedMS, params.meanPowerFactor) *
                          (1.0 + params.powerSlackFrac) / (1.0 - params.powerMarginFrac);
    double heading = params.headingRad;
    for (std::size_t k = 1; k <= runs; ++k) {
        const Point2 a = corner[k - 1];
        const Point2 b = corner[k];
        const double length = geometry::distance(a, b);
        const std::size_t capacity = kMaxPlanLegs - out->count - (runs - k);  // one per later run kept
        double wanted = std::ceil(length / params.spacingM);
        wanted = wanted < 1.0 ? 1.0 : wanted;
        const std::size_t pieces = wanted < static_cast<double>(capacity) ? static_cast<std::size_t>(wanted) : capacity;
        const double runHeading = length > 0.0 ? headingOf(a, b) : heading;
        for (std::size_t j = 1; j <= pieces; ++j) {
            const double f = static_cast<double>(j) / static_cast<double>(pieces);
            const double legLength = length / static_cast<double>(pieces);
            const double turn = j == 1 ? std::fabs(geometry::wrapAngleRad(runHeading - heading)) : 0.0;
            msg::PlanLeg& leg = out->legs[out->count];
            leg.xM = j == pieces ? b.x : a.x + f * (b.x - a.x);
            leg.yM = j == pieces ? b.y : a.y + f * (b.y - a.y);
            leg.risk = risk[k] / static_cast<double>(pieces);
            const double slack = 1.0 + params.slackFrac;
            leg.lengthM = (legLength + kLengthAllowanceM) * slack / (1.0 - params.distanceMarginFrac);
            leg.energyJ = rover_model::motionEnergyJ(params.power, legLength + kLengthAllowanceM,
                                                     turn + kTurnAllowanceRad, params.meanPowerFactor) *
                          slack / (1.0 - params.powerMarginFrac);
            leg.powerW = powerW;
            out->plannedLengthM[out->count] = legLength;
            ++out->count;
        }
        heading = runHeading;
    }
    return core::Status::kOk;
}

core::Status legBoundsFrom(double fromX, double fromY, double headingRad, const LegParams& params,
                           msg::PlanLeg* leg) {
    const Point2 from{fromX, fromY};
    const Point2 to{leg->xM, leg->yM};
    if (!paramsUsable(params) || !geometry::isFinite(from) || !geometry::isFinite(to) || !std::isfinite(headingRad)) {
        return core::Status::kInvalidArgument;
    }
    const double length = geometry::distance(from, to);
    const double turn = length > 0.0 ? std::fabs(geometry::wrapAngleRad(headingOf(from, to) - headingRad)) : 0.0;
    const double slack = 1.0 + params.slackFrac;
    leg->lengthM = (length + kLengthAllowanceM) * slack / (1.0 - params.distanceMarginFrac);
    leg->energyJ = rover_model::motionEnergyJ(params.power, length + kLengthAllowanceM, turn + kTurnAllowanceRad,
                                              params.meanPowerFactor) *
                   slack / (1.0 - params.powerMarginFrac);
    return core::Status::kOk;
}

}  // namespace rse::deliberative
