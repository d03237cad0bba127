// Test-only: site maps to load (ground/site_map_encoder.hpp): seeded random
// fields of hexagonal rocks, and single polygons to break on purpose.
#pragma once

#include <cmath>
#include <cstddef>
#include <random>
#include <vector>

#include "ground/site_map_encoder.hpp"

namespace rse::test {

// A regular polygon of n vertices, radius r about (x, y), counter-clockwise.
inline std::vector<::rse::ground::MapVertex> regularRock(float x, float y, float r, std::size_t n = 6, float turn = 0.0F) {
    std::vector<::rse::ground::MapVertex> v;
    for (std::size_t k = 0; k < n; ++k) {
        const double a = turn + 6.283185307179586 * static_cast<double>(k) / static_cast<double>(n);
        v.push_back({x + r * static_cast<float>(std::cos(a)), y + r * static_cast<float>(std::sin(a))});
    }
    return v;
}

// count rocks of radius 0.3 .. 1.5 m at uniform random centres on a side x side site from (0, 0).
inline ::rse::ground::SiteMapSpec randomField(std::size_t count, float side, unsigned seed) {
    ::rse::ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, side, side};
    std::mt19937 rng(seed);
    std::uniform_real_distribution<float> where(2.0F, side - 2.0F);
    std::uniform_real_distribution<float> size(0.3F, 1.5F);
    std::uniform_real_distribution<float> turn(0.0F, 1.0F);
    for (std::size_t i = 0; i < count; ++i) {
        const float x = where(rng);
        const float y = where(rng);
        spec.rocks.push_back(regularRock(x, y, size(rng), 6, turn(rng)));
    }
    return spec;
}

}  // namespace rse::test
