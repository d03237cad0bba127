// A scenario file's [[faults]] (format in sim_stub/scenarios/README.md): each
// fault's `type` picks its kind's own parser from a table in FaultType's order,
// which checks the keys that kind allows and reads its fields; the faults
// must be listed in time order. Problems throw ScenarioError, worded as every
// scenario error is (scenario_toml.hpp).
//
// Host start-up code: uses exceptions and the heap.
#pragma once

#include <vector>

#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/scenario/scenario_toml.hpp"

namespace rse::sim::scenario_toml {

// The array n ([[faults]]) into *out, in the file's order.
void parseFaults(const Reader& reader, const toml::node& n, std::vector<FaultSpec>* out);

}  // namespace rse::sim::scenario_toml
