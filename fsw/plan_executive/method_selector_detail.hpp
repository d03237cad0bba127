// Method selection's shared constants and helpers (method_selector.hpp is
// the interface). Internal to the selector's files:
//   method_selector.cpp          the interface: start, step, the phases; costs and loadStn
//   method_selector_analysis.cpp start()'s checks and analysis: options usable, the
//                                choices' order, the network's edges, presolve, costs
//   method_selector_network.cpp  the incremental network: threads on and off, Dijkstra repairs
//   method_selector_search.cpp   the branch and bound search and the support checks
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>

#include "fsw/plan_executive/method_selector.hpp"

namespace rse::plan_executive::selector_detail {

constexpr double kInfinite = std::numeric_limits<double>::infinity();
constexpr std::int64_t kNoCutoff = std::numeric_limits<std::int64_t>::max();
// A Dijkstra's marks per event.
constexpr std::uint8_t kUnseen = 0;
constexpr std::uint8_t kQueued = 1;
constexpr std::uint8_t kSettled = 2;

// Where execution stands is usable: times after the start, within the bounds' range.
bool executionOk(const SelectionInput& input, std::size_t events);
// The start's bounds to event e (SelectionInput "Regeneration"); input null: [0, inf).
Bounds fromStart(const SelectionInput* input, std::size_t e);

}  // namespace rse::plan_executive::selector_detail
