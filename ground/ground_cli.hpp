// rse-ground: the operator's command-line tool (docs/ground.md).
//
//   rse-ground [global options] COMMAND [its options and operands, in any order]
//
//   rse-ground [global options] send NAME [arg=value ...] [--auth-seq N] [--no-wait]
//   rse-ground [global options] watch [--count N] [--seconds S] [--only NAME,...]
//   rse-ground [global options] run SCRIPT [--verbose]
//   rse-ground [global options] record FILE [--seconds S] [--until-outcome] [--tail S] [--quiet]
//   rse-ground summary FILE [--facts] [--no-events]     (ground/mission_telemetry.hpp)
//   rse-ground [global options] table load IMAGE.tbl [--activate] [--force]
//   rse-ground [global options] table dump ID|NAME [--inactive] [-o FILE]
//   rse-ground table build|show|check|list ...        (ground/table_tool.hpp)
//   rse-ground plan check FILE [--failed C,...] [--degraded C,...]   (ground/plan_tool.hpp)
//   rse-ground [global options] plan load FILE [--failed C,...] [--degraded C,...] [--force]
//   rse-ground [global options] plan short TEXT [--failed C,...] [--degraded C,...] [--force]
//   rse-ground [global options] plan abort                            (ground/plan_transfer.hpp)
//   rse-ground dict --markdown|--json [-o FILE]
//   rse-ground [global options] encode NAME [arg=value ...] [--auth-seq N] [-o FILE]
//   rse-ground [global options] serve [--http [ADDR:]PORT] [--archive FILE] [--web DIR] [--tables DIR] [--seconds S]
//                                                      (ground/mission_control/serve_command.hpp)
//
// Global options (before the command; parsed with getopt_long, as every
// command's own options: ground/cli_options.hpp):
//   --udp HOST[:PORT]     commands to HOST:PORT (default 127.0.0.1:1234)
//   --tlm-port [ADDR:]PORT  telemetry received on ADDR:PORT (default 0.0.0.0:1235)
//   --can IFACE           ISO-TP on SocketCAN instead of UDP (tx 0x6C0, rx 0x6C1)
//   --can-tx ID --can-rx ID --pad    ISO-TP ids (hex) and frame padding
//   --key-file FILE       keys "ID:64hex" per line ('#' comments); the first, or --key-id's
//   --key-id N            which key (default: the built-in lab key, id 1)
//   --no-auth             unauthenticated (key id 0, no MAC): lab setting only
//   --state-dir DIR       anti-replay sequence state (default $RSE_GROUND_STATE or ~/.rse-ground)
//   --timeout S           acknowledgement wait (default 2)
//
// -h or --help anywhere (or the command `help`): the usage on stdout, exit 0.
//
// Exit codes: 0 success (accepted); 1 link error, no acknowledgement, failed script
// or wait; 2 a bad command line (unknown command or option, a missing or bad value:
// one line saying what, then "rse-ground: see 'rse-ground --help'", on stderr) or
// a bad argument or key file (nothing sent); 3 the rover rejected the command
// (report: the ten points not all seen in order).
//
// The sub-commands are in ground/cli_*.cpp (ground/cli_subcommands.hpp).
#pragma once

#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include "ground/ground_link.hpp"

namespace rse::ground {

constexpr int kExitOk = 0;
constexpr int kExitLink = 1;
constexpr int kExitUsage = 2;
constexpr int kExitRejected = 3;

// argv[0] is the program name. Output on out, diagnostics on err.
int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err);

// The same with the link supplied by the caller instead of --udp/--can (tests,
// embedding): linkFactory(listen) returns the link a subcommand uses; listen is
// false for send --no-wait, which needs no telemetry.
using LinkFactory = std::function<std::unique_ptr<GroundLink>(bool listen)>;
int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory);

// The body of `serve` (the mission control server): it lives in
// ground/mission_control/ (host only: SQLite and Boost.Beast), outside the
// ground library that the cross-built suites link, so rse-ground's main hands
// it in (without it `serve` says it is not built in). It gets serve's
// arguments and opens the link of the global options with openLink.
using ServeCommand = std::function<int(const std::vector<std::string>& args,
                                       const std::function<std::unique_ptr<GroundLink>()>& openLink,
                                       std::ostream& out, std::ostream& err)>;
int runGroundCli(int argc, char** argv, std::ostream& out, std::ostream& err, const LinkFactory& linkFactory,
                 const ServeCommand& serve);

}  // namespace rse::ground
