// `rse-ground plan check FILE [--failed C,...] [--degraded C,...]`: checks a
// mission plan on this machine before it is sent, with the flight code itself
// (fsw/plan_executive/: the same parser, method selection and temporal
// network that run on board), so a plan the rover would refuse is refused
// here first, with the same reason, line and token.
//
// Prints the plan's size, the methods selection chooses under the given
// component states (all ok unless --failed / --degraded name some), the
// expected cost, and every event's window [earliest, latest] in seconds from
// the plan's start. docs/plan_executive.md "Checking a plan on the ground".
//
// Exit status: 0 the plan parses and has a valid selection; 1 the file cannot
// be read; 2 bad usage, a plan the parser refuses, or no valid selection.
#pragma once

#include <iosfwd>
#include <string>
#include <vector>

namespace rse::ground {

// args: what follows "plan" ("check", FILE and options).
int runPlanCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

}  // namespace rse::ground
