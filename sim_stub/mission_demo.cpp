// rse-demo: the autonomous mission demo (`make demo`). The flight software and
// the simulator in one process in lockstep; the scenario's COARSE_MAP, the
// operator's SET_MODE AUTONOMOUS and the mission (the scenario's [mission]: a
// GOTO or a plan; or --goto's) go through the authenticated in-memory ground
// link; the console streams to stdout and a mission summary ends the run.
//
//   rse-demo [--scenario FILE] [--no-faults] [--goto X,Y[,RISK]] [--duration SECONDS] [--quiet]
//            [--command-at SECONDS] [--report DIR | --no-report] [--any-outcome]
//            [--pace F] [--udp-telemetry HOST:PORT [--udp-commands [ADDR:]PORT]]
//
// --pace runs it F times faster than real time against the wall clock;
// --udp-telemetry adds rse-fsw's UDP ground link, so its telemetry also goes
// to a ground as datagrams (docs/mission_control.md).
//
// Exit status: 0 when the mission showed the ten points in order (or ran at
// all, with --any-outcome), 3 when it ran but did not, 1 when the setup failed
// (scenario, flight software, drives, ground link, the plan's ground check)
// or the report was not written, 2 for a bad command line.
// sim_stub/lockstep/mission_runner.hpp has the logic.
#include <cstdio>

#include "sim_stub/lockstep/mission_runner.hpp"

int main(int argc, char** argv) { return rse::sim::missionMain(argc, argv, stdout, stderr); }
