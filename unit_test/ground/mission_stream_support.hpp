// Test support for the ground's reading of a mission: a small coarse map and
// the demo's ten points as the flight software's events say them (abridged
// times), shared by the tracker's tests and the report-from-telemetry tests.
#pragma once

#include <cstdint>
#include <vector>

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

struct Step {
    double t;
    std::uint16_t id;
    const char* text;
};

// The demo's ten points, in the flight software's words (abridged times).
inline const std::vector<Step> kDemo = {
    {0.39, 208, "app: 1 goal(s), risk bound 0.001"},
    {1.47, 902, "deliberative: optimal plan, gap 0.2%: 19.96 m, risk 9.17e-06/0.001, 6 legs, 1 nodes"},
    {1.47, 905, "deliberative: leg 1 (1 of 6) to (3.86, -0.28): <= 6.90 m, <= 8543 J, <= 308 W, risk 7.95e-43"},
    {1.55, 803, "habitual: leg 1 trajectory 2: 2 pts, 3.8/6.2 m, 3632/6834 J"},
    {17.25, 808, "habitual: leg 1 achieved at (3.73, -0.28): 3.6 m, 3473 J driven"},
    {17.27, 906, "deliberative: leg 1 reached (1 of 6)"},
    {17.27, 905, "deliberative: leg 2 (2 of 6) to (14.33, -0.38): <= 12.83 m, <= 15856 J, <= 308 W, risk 4.59e-06"},
    {44.35, 816, "habitual: hazard 3 seen at (12.79, -0.08), radius 0.38 m: on the map"},
    {44.35, 804, "habitual: leg 2: hazard 3 at (12.79, -0.08) r 0.38 m on the path: stop, replan"},
    {45.75, 803, "habitual: leg 2 trajectory 11: 7 pts, 5.8/9.7 m, 8056/10994 J"},
    {45.75, 805, "habitual: leg 2 replanned (path blocked, run 0): constraints hold: minor anomaly"},
    {69.55, 808, "habitual: leg 2 achieved at (14.35, -0.25): 7.9 m, 10781 J driven"},
    {69.57, 906, "deliberative: leg 2 reached (2 of 6)"},
    {69.57, 905, "deliberative: leg 3 (3 of 6) to (17.62, -0.47): <= 6.20 m, <= 7670 J, <= 308 W, risk 1.07e-06"},
    {79.39, 761, "drive_modes: ML nominal -> degraded (p=0.997, power x1.13)"},
    {80.45, 807, "habitual: leg 3 fail-up: power 247.0 W > allowed 246.8 W by 0.3 W (power factor 1.051)"},
    {80.47, 909, "deliberative: leg 3 failed up: power (predicted 247.0, allowed 246.8, excess 0.3)"},
    {80.47, 910, "deliberative: leg 3 power bound relaxed x1.051 to 324 W (x1.051 of planned, limit x1.50): resen"},
    {80.47, 905, "deliberative: leg 4 (3 of 6) to (17.62, -0.47): <= 6.20 m, <= 7670 J, <= 324 W, risk 1.07e-06"},
    {81.75, 803, "habitual: leg 4 trajectory 16: 2 pts, 1.6/5.5 m, 1739/6043 J"},
    {94.29, 762, "drive_modes: ML degraded -> failed (p=0.983, power x1.40)"},
    {103.31, 933, "fault protection: drive lost (fault 2): 3 tries used: drive failed, deliberative decides"},
    {103.37, 905, "deliberative: leg 5 (3 of 6) to (20.00, 0.00): <= 3.60 m, <= 7879 J, <= 324 W, risk 3.49e-10"},
    {103.45, 807, "habitual: leg 5 fail-up: power 372.1 W > allowed 259.4 W by 112.7 W (power factor 1.583)"},
    {103.47, 911, "deliberative: replan 1/2 (power) t=103.47 s from (18.55, -0.36): goals 0..0 left, 2 hazards"},
    {103.47, 990, "deliberative: drive estimate: ML failed: plans at power factor 1.58, noise 0.250 m/step"},
    {103.67, 904, "deliberative: risk bound relaxed to 0.01 (the operator's 0.001 x10, limit x10)"},
    {104.67, 912, "deliberative: CALL HOME: no plan within the risk limit (no plan at the relaxed risk limit), goa"},
    {104.68, 215, "app: onboard call home (reason 1): mode AUTONOMOUS -> SAFE"},
};

}  // namespace rse::test
