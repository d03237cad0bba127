// Monte Carlo of a flown horizon against every rock of a site map (issue 31,
// "the certified risk holds against the whole map"): the plant of
// fsw/deliberative/cc_problem.hpp run open loop on the plan's mean steps, as
// cc_monte_carlo.hpp samples a plan against its own problem's obstacles, but
// a sampled segment x_t -> x_{t+1} collides when it comes within the rover's
// clearance radius of any rock of the map (the site map's grid index lists the
// rocks near it; the exact segment / convex polygon distance decides):
//   x_0 ~ N(mu_0, Sigma_0),  x_{t+1} = x_t + (mu_{t+1} - mu_t) + w_t,  w_t ~ N(0, sigma^2 I)
// Seeded std::mt19937_64 + std::normal_distribution.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/site_map/site_map.hpp"

namespace rse::test {

struct WholeMapMcResult {
    std::size_t samples = 0;
    std::size_t collisions = 0;   // sampled paths that came within the radius of some rock
    bool crowded = false;         // a segment had more rocks near it than the sampler lists (counted as a collision)
};

WholeMapMcResult sampleAgainstWholeMap(const site_map::SiteMap& map, const deliberative::CcProblem& problem,
                                       const deliberative::CcPlan& plan, double radiusM, std::size_t samples,
                                       std::uint64_t seed);

}  // namespace rse::test
