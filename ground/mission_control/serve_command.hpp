// `rse-ground serve` (docs/mission_control.md, docs/ground.md): the mission
// control server fed by the ground link.
//
//   rse-ground [link options] serve [--http [ADDR:]PORT] [--archive FILE] [--web DIR]
//                                   [--tables DIR] [--seconds S]
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
#include <stdexcept>
#include <string>
#include <vector>

#include "ground/ground_link.hpp"
#include "ground/mission_control/mc_server.hpp"

namespace rse::ground::mission_control {

class ServeUsageError : public std::runtime_error {
public:
    using std::runtime_error::runtime_error;
};

struct ServeOptions {
    ServerOptions server;
    double seconds = 0.0;  // > 0: stop after this long
};

// Parses serve's arguments (after "serve"); throws ServeUsageError.
ServeOptions parseServeOptions(const std::vector<std::string>& args);

// Runs serve: the server, then the link from openLink, packets from the link
// to the server until a signal or --seconds.
int runServe(const std::vector<std::string>& args, const std::function<std::unique_ptr<GroundLink>()>& openLink,
             std::ostream& out, std::ostream& err);

}  // namespace rse::ground::mission_control
