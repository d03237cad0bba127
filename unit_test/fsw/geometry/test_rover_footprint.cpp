// The planners' clearance disc: the table's footprint, never smaller than the
// disc round the wheels (ROVER_GEOMETRY.wheelbase_m and track_width_m).
#include <cmath>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/tables/table_types.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {
tables::RoverGeometryTable rover(float wheelbase, float track, float wheelRadius, float footprint) {
    tables::RoverGeometryTable g{};
    g.wheelbase_m = wheelbase;
    g.track_width_m = track;
    g.wheel_radius_m = wheelRadius;
    g.footprint_radius_m = footprint;
    return g;
}
}  // namespace

TEST_GROUP(RoverFootprint){};

TEST(RoverFootprint, TheWheelEnvelopeIsHalfTheContactDiagonalPlusAWheelRadius) {
    DOUBLES_EQUAL(0.5 * std::hypot(0.7, 0.6) + 0.1, geometry::wheelEnvelopeRadiusM(rover(0.7F, 0.6F, 0.1F, 0.6F)),
                  1e-6);
}

TEST(RoverFootprint, TheFootprintCountsUnlessTheWheelsStickOutOfIt) {
    DOUBLES_EQUAL(0.6, geometry::clearanceRadiusM(rover(0.7F, 0.6F, 0.1F, 0.6F)), 1e-6);
    // A longer wheelbase puts the wheels outside the 0.6 m disc: they set the clearance.
    const double longBase = geometry::clearanceRadiusM(rover(1.2F, 0.6F, 0.1F, 0.6F));
    DOUBLES_EQUAL(0.5 * std::hypot(1.2, 0.6) + 0.1, longBase, 1e-6);
    CHECK(longBase > 0.6);
}
