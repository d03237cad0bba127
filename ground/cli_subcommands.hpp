// rse-ground's sub-commands (the usage is ground/ground_cli.cpp's, the reference
// docs/ground.md). Each takes the words after its name, parses its own options
// (ground/cli_options.hpp: UsageError for a bad command line) and returns the
// exit code (ground/ground_cli.hpp).
#pragma once

#include <string>
#include <vector>

#include "ground/cli_context.hpp"

namespace rse::ground {

using Words = std::vector<std::string>;

// Commands to the rover and their packets (ground/cli_commanding.cpp).
int runSend(CliContext& cli, const Words& words);
int runResync(CliContext& cli, const Words& words);
int runScript(CliContext& cli, const Words& words);  // `run`
int runEncode(CliContext& cli, const Words& words);
int runDict(CliContext& cli, const Words& words);

// Telemetry as it comes (ground/cli_telemetry.cpp).
int runWatch(CliContext& cli, const Words& words);
int runRecord(CliContext& cli, const Words& words);

// A recording read back (ground/cli_recording.cpp).
int runSummary(CliContext& cli, const Words& words);
int runReport(CliContext& cli, const Words& words);

// Parameter tables: load and dump over the link, the rest the table tool's (ground/cli_table.cpp).
int runTable(CliContext& cli, const Words& words);

// Mission plans: load, short and abort over the link, check the plan tool's (ground/cli_plan.cpp).
int runPlan(CliContext& cli, const Words& words);

// The site map: check, load and abort over the link (ground/cli_map.cpp).
int runMap(CliContext& cli, const Words& words);

}  // namespace rse::ground
