// Scenario files: TOML (format in sim_stub/scenarios/README.md), parsed with
// toml++ and validated strictly. Every problem is reported as
//   <source>: <key path>: <what is wrong>
// e.g. "scenario.toml: obstacles[2].vertices: polygon must be convex and
// counter-clockwise" (array indices from 0), or for TOML syntax errors
//   <source>:<line>:<column>: <toml++'s description>
// Unknown keys are rejected at every level, numbers are range-checked, faults
// must be listed in time order. Host start-up code: uses exceptions and the heap.
#pragma once

#include <stdexcept>
#include <string>
#include <string_view>

#include "sim_stub/scenario/scenario.hpp"

namespace rse::sim {

class ScenarioError : public std::runtime_error {
public:
    explicit ScenarioError(const std::string& what) : std::runtime_error(what) {}
};

// Throw ScenarioError.
Scenario parseScenario(std::string_view text, const std::string& sourceName);
Scenario loadScenarioFile(const std::string& path);

// Non-throwing forms: true with *out filled, or false with the message in *error.
bool tryParseScenario(std::string_view text, const std::string& sourceName, Scenario* out, std::string* error);
bool tryLoadScenarioFile(const std::string& path, Scenario* out, std::string* error);

}  // namespace rse::sim
