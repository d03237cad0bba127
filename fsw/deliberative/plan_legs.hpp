// A chance-constrained plan cut into legs for the habitual layer: where each leg
// ends, the risk the plan spent on it, and its not-to-exceed length and energy.
//
// Leg ends are the corners of the plan's mean path (points where it turns by
// more than kCornerRad; coincident means, e.g. steps parked at the goal, are
// merged), plus cuts that keep every leg at most PLANNER.waypoint_spacing_m.
// A straight run is cut into equal pieces. Legs shorter than kMinLegM are
// merged into the next one (the habitual layer stops at every leg end, and its
// goal tolerance is 0.5 m).
//
// Bounds, for a leg of planned length L turning Theta (from the previous leg's
// direction; the first leg from the rover's heading):
//   maxPathLengthM = (L + kLengthAllowanceM) (1 + slack) / (1 - HABITUAL.distance_margin_frac)
//   maxEnergyJ     = E(L + kLengthAllowanceM, Theta + kTurnAllowanceRad) (1 + slack) / (1 - HABITUAL.power_margin_frac)
//   powerW         = P(fbar) (1 + power slack) / (1 - HABITUAL.power_margin_frac)
// with E and P the rover's power model (fsw/rover_model/power_model.hpp, the one the
// habitual layer checks its plans with) at the drives'
// present mean power factor fbar, slack = PLANNER.leg_slack_frac and power
// slack = PLANNER.leg_power_slack_frac: the habitual layer holds its own margin
// back from what it is given, so the division hands it the planned figure plus
// the slack after its reserve. The allowances cover
// starting a leg where the last one was reached (within the goal tolerance) in
// a heading of the follower's choosing. P is the drives' power at the cruise
// speed: it depends on their health only, so it is the same for every leg of
// a plan, and what a worn motor breaks first.
//
// Pure: no bus, no events, no state.
#pragma once

#include <cstddef>

#include "fsw/core/status.hpp"
#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::deliberative {

constexpr std::size_t kMaxPlanLegs = 48;
constexpr double kCornerRad = 0.02;          // smaller turns are straight on
constexpr double kMinLegM = 0.3;
constexpr double kLengthAllowanceM = 1.0;    // about twice the habitual goal tolerance
constexpr double kTurnAllowanceRad = 0.5;

struct LegParams {
    double spacingM = 6.0;            // PLANNER.waypoint_spacing_m
    double slackFrac = 0.3;           // PLANNER.leg_slack_frac
    double distanceMarginFrac = 0.1;  // HABITUAL.distance_margin_frac
    double powerMarginFrac = 0.2;     // HABITUAL.power_margin_frac
    double powerSlackFrac = 0.05;     // PLANNER.leg_power_slack_frac
    double cruiseSpeedMS = 0.25;      // HABITUAL.cruise_speed_m_s
    rover_model::PowerModel power{};
    double meanPowerFactor = 1.0;     // the drives' present mean factor (>= 1)
    double headingRad = 0.0;          // the rover's heading at the plan's start
};

struct LegPlan {
    std::size_t count = 0;
    msg::PlanLeg legs[kMaxPlanLegs] = {};
    double plannedLengthM[kMaxPlanLegs] = {};  // L of each leg (before allowances)
};

// kInvalidArgument for a plan without a path (status not kOptimal or
// kFeasible, no steps), non-finite or out-of-range parameters; kOk otherwise
// (a plan whose start is its goal gives one leg to the goal). When the cuts
// would pass kMaxPlanLegs, the pieces of the last runs get longer (never fewer
// legs than corners: a plan has at most kMaxPlanSteps corners).
core::Status splitPlanIntoLegs(const CcPlan& plan, const LegParams& params, LegPlan* out);

// The length and energy bounds of *leg (its end and power bound kept) for a
// rover at (fromX, fromY) heading
// headingRad: the formulas above with L the straight distance to the leg's end
// and Theta the turn towards it. Used when a leg is re-sent from where the
// rover stands (after a mission hold, or to confirm a goal). kInvalidArgument
// (leg unchanged) for non-finite input or unusable params.
core::Status legBoundsFrom(double fromX, double fromY, double headingRad, const LegParams& params,
                           msg::PlanLeg* leg);

}  // namespace rse::deliberative
