// `rse-ground plan check FILE [--failed C,...] [--degraded C,...]`: checks a
// mission plan on this machine before it is sent, with the flight code itself
// (fsw/plan_executive/: the same parser, method selection and temporal
// network that run on board), so a plan the rover would refuse is refused
// here first, with the same reason, line and token.
//
// Prints the plan's size, the methods selection chooses under the given
// component states (all ok unless --failed / --degraded name some), the
// expected cost, every event's window [earliest, latest] in seconds from the
// plan's start, and each selected drive's point (and region, `within R`).
// docs/plan_executive.md "Checking a plan on the ground".
//
// The same check guards `rse-ground plan load` and `plan short`
// (ground/plan_transfer.hpp): checkPlanText() and applyComponentStates().
//
// Exit status: 0 the plan parses and has a valid selection (or --help); 1 the
// file cannot be read; 2 a bad command line (one line and "see 'rse-ground
// --help'"), a plan the parser refuses, or no valid selection.
#pragma once

#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "fsw/plan_executive/method_selector.hpp"
#include "ground/cli_options.hpp"

namespace rse::ground {

// args: what follows "plan" ("check", FILE and options).
int runPlanCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err);

// The component-state options of plan check, load and short.
std::vector<CliOption> componentStateOptions();  // --failed C,... --degraded C,...

// Every --failed C,... and --degraded C,... of parsed, in the order given
// (components drive_FL .. drive_RR, grinder, camera), into input. Returns why it
// could not (an unknown component), nullopt when all was well.
std::optional<std::string> applyComponentStates(const ParsedOptions& parsed, plan_executive::SelectionInput* input);

// The check `plan check` makes, on plan text: the flight parser, then method
// selection under input, then the selection's temporal network. Prints the
// plan's size, the selection, each choice's option and the expected cost on
// out (and every event's window and each selected drive's goal when windows);
// a refusal goes to err as
// "WHERE:LINE: reason at 'token'" or "WHERE: no valid selection ...".
// True when the rover would accept the plan under those component states.
bool checkPlanText(const std::string& text, const std::string& where, const plan_executive::SelectionInput& input,
                   bool windows, std::ostream& out, std::ostream& err);

}  // namespace rse::ground
