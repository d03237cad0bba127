// `rse-ground serve` (docs/mission_control.md, docs/ground.md): the mission
// control server fed by the ground link.
//
//   rse-ground [global options] serve [--http [ADDR:]PORT] [--archive FILE] [--web DIR]
//                                     [--tables DIR] [--seconds S]
//
// The link is the one of rse-ground's global options (--tlm-port, --can ...),
// opened as `watch` and `record` open it. Every packet it receives is handed
// to MissionControl::onPacket with its receive time; SIGINT or SIGTERM (or
// --seconds) stops it: connections closed, then the archive. Exit codes are
// rse-ground's: 0 stopped, 1 archive, port or link failure, 2 usage.
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "ground/ground_link.hpp"
#include "ground/mission_control/mc_server.hpp"

namespace rse::ground::mission_control {

struct ServeOptions {
    ServerOptions server;
    double seconds = 0.0;  // > 0: stop after this long
};

// Parses serve's arguments (after "serve") with getopt_long: UsageError for a
// bad command line, HelpRequested for -h/--help (ground/cli_options.hpp).
ServeOptions parseServeOptions(const std::vector<std::string>& args);

// Runs serve: the server, then the link from openLink, packets from the link
// to the server until a signal or --seconds. A bad command line is reported
// here (one line and "see 'rse-ground --help'", exit 2); --help is thrown on
// to runGroundCli, which prints the usage.
int runServe(const std::vector<std::string>& args, const std::function<std::unique_ptr<GroundLink>()>& openLink,
             std::ostream& out, std::ostream& err);

}  // namespace rse::ground::mission_control
