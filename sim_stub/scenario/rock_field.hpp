// Rock fields that look like Mars (issue 31, item 4): Golombek and Rapp's
// rock size-frequency model (J. Geophys. Res. 102, 1997; Golombek et al.
// 2003 for the Mars Exploration Rover sites). The cumulative fractional area
// covered by rocks of diameter D or more is
//   F_k(D) = k exp(-q(k) D),   q(k) = 1.79 + 0.152 / k
// with k the total fraction of the ground rocks cover (about 0.05 at typical
// landing sites, 0.10 - 0.20 in boulder fields). Rocks per m^2 with diameters
// in [D, D + dD]: n(D) dD = -dF / (pi D^2 / 4) = 4 k q exp(-q D) / (pi D^2) dD.
//
// generateRockField() draws a field from it, seeded: the number of rocks with
// diameters in [minDiameter, maxDiameter] is Poisson with mean area x the
// integral of n, each diameter from n (a tabulated inverse CDF), each centre
// uniform on the site, each shape the convex hull of 7 points round a circle
// of that diameter (counter-clockwise, convex by construction). A rock at or
// above the orbital resolution is known (on the site map), a smaller one
// hidden. Host only (the simulator's side); std::vector allowed.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace rse::sim {

struct RockFieldParams {
    double k = 0.10;                 // cumulative fractional area of all rocks
    double xMin = 0.0, yMin = 0.0, xMax = 100.0, yMax = 100.0;  // the site (m)
    double minDiameterM = 0.5;       // smaller rocks are not drawn (a rover drives over them)
    double maxDiameterM = 8.0;
    double orbitalResolutionM = 1.0; // known at or above
    std::uint64_t seed = 1;
};

struct RockVertex {
    double x = 0.0;
    double y = 0.0;
};

struct FieldRock {
    double x = 0.0, y = 0.0;     // centre
    double diameterM = 0.0;      // of the circle the shape is drawn round
    bool known = false;          // diameter >= the orbital resolution
    std::vector<RockVertex> vertices;  // convex, counter-clockwise, 3 .. 8
};

// q(k) of the model.
double golombekRappQ(double k);
// F_k(D): the fraction of the ground covered by rocks of diameter >= D.
double rockAreaFraction(double k, double diameterM);
// Rocks per m^2 with diameters in [fromM, toM] (the integral of n).
double rocksPerSquareMetre(double k, double fromM, double toM);

// The field, or none for parameters out of range (k not in (0, 1), an empty
// site, diameters not 0 < min < max).
std::vector<FieldRock> generateRockField(const RockFieldParams& params);

}  // namespace rse::sim
