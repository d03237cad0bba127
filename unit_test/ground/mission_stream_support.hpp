// Test support for the ground's reading of a mission: a small coarse map and
// the demo's ten points as the flight software's events say them (abridged
// times), each with its numbers (the event data the flight attaches, built by
// name through fsw/cmdtlm/event_data.hpp), shared by the tracker's tests and
// the report-from-telemetry tests.
#pragma once

#include <cstdint>
#include <vector>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::test {

// One square rock, x 5..6.5, y 1.8..3.2, on a 35 m x 20 m site.
inline tables::CoarseMapTable oneRock() {
    tables::CoarseMapTable m{};
    m.x_min_m = -5.0F;
    m.x_max_m = 30.0F;
    m.y_min_m = -10.0F;
    m.y_max_m = 10.0F;
    m.obstacle_count = 1;
    m.vertex_count[0] = 4;
    const float xs[4] = {5.0F, 6.5F, 6.5F, 5.0F};
    const float ys[4] = {1.8F, 1.8F, 3.2F, 3.2F};
    for (int i = 0; i < 4; ++i) {
        m.vertex_x_m[i] = xs[i];
        m.vertex_y_m[i] = ys[i];
    }
    return m;
}

// The numbers of each event the demo stream holds, by name.
namespace data {
namespace evd = cmdtlm::event_data;

inline core::EventData goals(double count, double riskBound) {
    evd::GOALS_COMMANDED d;
    d.goal_count = count;
    d.risk_bound = riskBound;
    return d.pack();
}
inline core::EventData legSent(double leg, double index, double count, double x, double y, double lengthM,
                               double energyJ, double powerW) {
    evd::LEG_SENT d;
    d.leg_id = leg;
    d.index = index;
    d.count = count;
    d.x = x;
    d.y = y;
    d.length_bound = lengthM;
    d.energy_bound = energyJ;
    d.power_bound = powerW;
    return d.pack();
}
inline core::EventData legAchieved(double leg, double x, double y, double drivenM, double drivenJ) {
    evd::LEG_ACHIEVED d;
    d.leg_id = leg;
    d.x = x;
    d.y = y;
    d.driven_length = drivenM;
    d.driven_energy = drivenJ;
    return d.pack();
}
inline core::EventData legReached(double leg, double index, double count) {
    evd::LEG_REACHED d;
    d.leg_id = leg;
    d.index = index;
    d.count = count;
    return d.pack();
}
inline core::EventData hazardSeen(double hazard, double x, double y, double radiusM) {
    evd::HAZARD_REMEMBERED d;
    d.hazard = hazard;
    d.x = x;
    d.y = y;
    d.radius = radiusM;
    return d.pack();
}
inline core::EventData pathBlocked(double leg, double hazard, double x, double y, double radiusM) {
    evd::PATH_BLOCKED d;
    d.leg_id = leg;
    d.hazard = hazard;
    d.x = x;
    d.y = y;
    d.radius = radiusM;
    return d.pack();
}
inline core::EventData minorAnomaly(double leg, double trigger, double run) {
    evd::MINOR_ANOMALY d;
    d.leg_id = leg;
    d.trigger = trigger;
    d.run = run;
    return d.pack();
}
inline core::EventData failUp(double leg, msg::LegConstraint constraint, double predicted = 0.0, double allowed = 0.0,
                              double powerFactor = 0.0) {
    evd::HABITUAL_FAIL_UP d;
    d.leg_id = leg;
    d.constraint = static_cast<double>(constraint);
    d.predicted = predicted;
    d.allowed = allowed;
    d.excess = predicted - allowed;
    d.power_factor = powerFactor;
    return d.pack();
}
inline core::EventData powerRelaxed(double leg, double factor, double fromW, double toW) {
    evd::BOUND_RELAXED d;
    d.leg_id = leg;
    d.bound = static_cast<double>(msg::LegConstraint::kPower);
    d.factor = factor;
    d.from = fromW;
    d.to = toW;
    d.of_planned = factor;
    d.limit = 1.5;
    return d.pack();
}
inline core::EventData driveMode(double wheel, double from, double to, double probability, double powerFactor) {
    evd::DRIVE_MODE_DECLARED d;
    d.wheel = wheel;
    d.from = from;
    d.to = to;
    d.probability = probability;
    d.power_factor = powerFactor;
    return d.pack();
}
inline core::EventData gaveUp(double faultClass, double faultId, double wheel, double attempts, double callHome) {
    evd::FAULT_GAVE_UP d;
    d.fault_class = faultClass;
    d.fault_id = faultId;
    d.wheel = wheel;
    d.attempts = attempts;
    d.call_home = callHome;
    return d.pack();
}
inline core::EventData failedDrives(double mask, double powerFactor, double noiseM) {
    evd::FAILED_DRIVE_MODEL d;
    d.failed_drives = mask;
    d.power_factor = powerFactor;
    d.noise = noiseM;
    return d.pack();
}
inline core::EventData callHome(msg::CallHomeReason reason, double goal, double riskBound) {
    evd::CALL_HOME d;
    d.reason = static_cast<double>(reason);
    d.goal = goal;
    d.risk_bound = riskBound;
    return d.pack();
}
inline core::EventData safed(msg::CallHomeReason reason, double modeBefore) {
    evd::SAFED_ON_REQUEST d;
    d.reason = static_cast<double>(reason);
    d.mode_before = modeBefore;
    return d.pack();
}
}  // namespace data

struct Step {
    double t;
    std::uint16_t id;
    const char* text;
    core::EventData data;  // the event's numbers (count 0: it carries none)
};

// The demo's ten points, in the flight software's words (abridged times).
inline const std::vector<Step> kDemo = {
    {0.39, 208, "app: 1 goal(s), risk bound 0.001", data::goals(1, 0.001)},
    {1.47, 902, "deliberative: optimal plan, gap 0.2%: 19.96 m, risk 9.17e-06/0.001, 6 legs, 1 nodes", {}},
    {1.47, 905, "deliberative: leg 1 (1 of 6) to (3.86, -0.28): <= 6.90 m, <= 8543 J, <= 308 W, risk 7.95e-43",
     data::legSent(1, 1, 6, 3.86, -0.28, 6.90, 8543, 308)},
    {1.55, 803, "habitual: leg 1 trajectory 2: 2 pts, 3.8/6.2 m, 3632/6834 J", {}},
    {17.25, 808, "habitual: leg 1 achieved at (3.73, -0.28): 3.6 m, 3473 J driven",
     data::legAchieved(1, 3.73, -0.28, 3.6, 3473)},
    {17.27, 906, "deliberative: leg 1 reached (1 of 6)", data::legReached(1, 1, 6)},
    {17.27, 905, "deliberative: leg 2 (2 of 6) to (14.33, -0.38): <= 12.83 m, <= 15856 J, <= 308 W, risk 4.59e-06",
     data::legSent(2, 2, 6, 14.33, -0.38, 12.83, 15856, 308)},
    {44.35, 816, "habitual: hazard 3 seen at (12.79, -0.08), radius 0.38 m: on the map",
     data::hazardSeen(3, 12.79, -0.08, 0.38)},
    {44.35, 804, "habitual: leg 2: hazard 3 at (12.79, -0.08) r 0.38 m on the path: stop, replan",
     data::pathBlocked(2, 3, 12.79, -0.08, 0.38)},
    {45.75, 803, "habitual: leg 2 trajectory 11: 7 pts, 5.8/9.7 m, 8056/10994 J", {}},
    {45.75, 805, "habitual: leg 2 replanned (path blocked, run 0): constraints hold: minor anomaly",
     data::minorAnomaly(2, 1, 0)},
    {69.55, 808, "habitual: leg 2 achieved at (14.35, -0.25): 7.9 m, 10781 J driven",
     data::legAchieved(2, 14.35, -0.25, 7.9, 10781)},
    {69.57, 906, "deliberative: leg 2 reached (2 of 6)", data::legReached(2, 2, 6)},
    {69.57, 905, "deliberative: leg 3 (3 of 6) to (17.62, -0.47): <= 6.20 m, <= 7670 J, <= 308 W, risk 1.07e-06",
     data::legSent(3, 3, 6, 17.62, -0.47, 6.20, 7670, 308)},
    {79.39, 761, "drive_modes: ML nominal -> degraded (p=0.997, power x1.13)", data::driveMode(1, 0, 1, 0.997, 1.13)},
    {80.45, 807, "habitual: leg 3 fail-up: power 247.0 W > allowed 246.8 W by 0.3 W (power factor 1.051)",
     data::failUp(3, msg::LegConstraint::kPower, 247.0, 246.8, 1.051)},
    {80.47, 909, "deliberative: leg 3 failed up: power (predicted 247.0, allowed 246.8, excess 0.3)", {}},
    {80.47, 910, "deliberative: leg 3 power bound relaxed x1.051 to 324 W (x1.051 of planned, limit x1.50): resen",
     data::powerRelaxed(3, 1.051, 308, 324)},
    {80.47, 905, "deliberative: leg 4 (3 of 6) to (17.62, -0.47): <= 6.20 m, <= 7670 J, <= 324 W, risk 1.07e-06",
     data::legSent(4, 3, 6, 17.62, -0.47, 6.20, 7670, 324)},
    {81.75, 803, "habitual: leg 4 trajectory 16: 2 pts, 1.6/5.5 m, 1739/6043 J", {}},
    {94.29, 762, "drive_modes: ML degraded -> failed (p=0.983, power x1.40)", data::driveMode(1, 1, 2, 0.983, 1.40)},
    {103.31, 933, "fault protection: drive lost (fault 2): 3 tries used: drive failed, deliberative decides",
     data::gaveUp(0, 2, 1, 3, 0)},
    {103.37, 905, "deliberative: leg 5 (3 of 6) to (20.00, 0.00): <= 3.60 m, <= 7879 J, <= 324 W, risk 3.49e-10",
     data::legSent(5, 3, 6, 20.0, 0.0, 3.60, 7879, 324)},
    {103.45, 807, "habitual: leg 5 fail-up: power 372.1 W > allowed 259.4 W by 112.7 W (power factor 1.583)",
     data::failUp(5, msg::LegConstraint::kPower, 372.1, 259.4, 1.583)},
    {103.47, 911, "deliberative: replan 1/2 (power) t=103.47 s from (18.55, -0.36): goals 0..0 left, 2 hazards", {}},
    {103.47, 990, "deliberative: drive estimate: ML failed: plans at power factor 1.58, noise 0.250 m/step",
     data::failedDrives(0x02, 1.58, 0.25)},
    {103.67, 904, "deliberative: risk bound relaxed to 0.01 (the operator's 0.001 x10, limit x10)", {}},
    {104.67, 912, "deliberative: CALL HOME: no plan within the risk limit (no plan at the relaxed risk limit), goa",
     data::callHome(msg::CallHomeReason::kNoPlanWithinRisk, 0, 0.001)},
    {104.68, 215, "app: onboard call home (reason 1): mode AUTONOMOUS -> SAFE",
     data::safed(msg::CallHomeReason::kNoPlanWithinRisk, 2)},
};

}  // namespace rse::test
