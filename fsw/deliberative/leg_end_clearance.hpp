// Whether a point the layer would send the rover to (a leg end, a back-up
// target) stands too near what it must keep clear of: within the rover's
// clearance radius (the footprint) + kLegEndMarginM of a seen hazard's disc
// (KnownHazardsMsg) or of a coarse-map polygon.
//
// The plan keeps its means off the grown polygons only with the chance margin
// of the moment, and a polygon grown less for a close start keeps less: an end
// the habitual layer could reach only without its planning margin is not
// handed to it. Pure: reads the map and the hazards it is given.
#pragma once

#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::deliberative {

// A leg end must clear a seen hazard's disc by the footprint and this: the
// habitual layer plans with habitual::kPlanMarginM beyond the footprint, and a
// disc grows as more of its rock comes into view.
constexpr double kLegEndMarginM = 0.25;

class LegEndClearance {
public:
    // roverClearanceM: geometry::clearanceRadiusM of the rover's geometry table.
    LegEndClearance(const tables::CoarseMapTable& map, double roverClearanceM, const msg::KnownHazardsMsg& hazards)
        : map_(map), clearanceM_(roverClearanceM + kLegEndMarginM), hazards_(hazards) {}

    bool tooClose(double xM, double yM) const;

private:
    const tables::CoarseMapTable& map_;
    double clearanceM_;
    const msg::KnownHazardsMsg& hazards_;
};

}  // namespace rse::deliberative
