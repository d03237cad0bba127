// rse-demo: the autonomous mission demo (`make demo`). The flight software and
// the simulator in one process in lockstep; the operator's SET_MODE AUTONOMOUS
// and GOTO go through the authenticated in-memory ground link; the console
// streams to stdout and a mission summary ends the run.
//
//   rse-demo [--scenario FILE] [--no-faults] [--goto X,Y[,RISK]] [--duration SECONDS] [--quiet]
//
// Exit status: 0 when the mission ran (whatever its outcome), 1 when the setup
// failed (scenario, flight software, drives, ground link), 2 for a bad command
// line. sim_stub/lockstep/mission_runner.hpp has the logic.
#include <cstdio>

#include "sim_stub/lockstep/mission_runner.hpp"

int main(int argc, char** argv) { return rse::sim::missionMain(argc, argv, stdout, stderr); }
