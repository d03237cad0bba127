// A pool of worker processes for Monte Carlo runs (rse-montecarlo): fork()ed
// children, each given one seed at a time over a pipe, answering with that
// seed's two lines (its R and T lines). A worker that dies mid-seed (a signal,
// an exit) leaves a "crashed" row for that seed, and a new worker takes its
// place, so no seed is lost. The parent runs no mission itself.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "sim_stub/montecarlo/campaign.hpp"

namespace rse::sim::mc {

// Runs work(seed) for every seed on `jobs` worker processes (at least 1) and
// calls done(seed, run) in the parent as each finishes (in the order they
// finish). False with *error when a worker could not be started at all.
bool runOnWorkers(const std::vector<std::uint64_t>& seeds, int jobs,
                  const std::function<SeedRun(std::uint64_t)>& work,
                  const std::function<void(std::uint64_t, const SeedRun&)>& done, std::string* error);

}  // namespace rse::sim::mc
