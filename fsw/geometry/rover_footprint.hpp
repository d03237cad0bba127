// The disc the planners keep clear of obstacles, shared by the habitual and
// deliberative layers (it sits below both). ROVER_GEOMETRY.footprint_radius_m
// is the operator's collision disc; it can never be smaller than the disc that
// encloses the wheels: half the diagonal of the wheelbase x track rectangle of
// contact points, plus a wheel radius for the tyres around them. A table that
// gives less is overridden here, so a smaller disc uploaded by mistake cannot
// let a plan clip a rock with a wheel (defaults: 0.60 m footprint, 0.56 m
// wheel envelope for a 0.70 m wheelbase and a 0.60 m track).
#pragma once

#include <cmath>

#include "fsw/tables/table_types.hpp"

namespace rse::geometry {

// Radius of the disc that encloses every wheel.
inline double wheelEnvelopeRadiusM(const tables::RoverGeometryTable& g) {
    return 0.5 * std::hypot(static_cast<double>(g.wheelbase_m), static_cast<double>(g.track_width_m)) +
           static_cast<double>(g.wheel_radius_m);
}

// The clearance radius the planners use: the table's footprint, or the wheel envelope when larger.
inline double clearanceRadiusM(const tables::RoverGeometryTable& g) {
    const double footprint = static_cast<double>(g.footprint_radius_m);
    const double wheels = wheelEnvelopeRadiusM(g);
    return footprint >= wheels ? footprint : wheels;
}

}  // namespace rse::geometry
