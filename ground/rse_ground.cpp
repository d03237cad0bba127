// rse-ground: the operator's tool. Everything is in ground/ground_cli.hpp
// (usage, options, exit codes) and docs/ground.md; `serve`, the mission
// control server, in ground/mission_control/ (docs/mission_control.md).
#include <iostream>

#include "ground/ground_cli.hpp"
#include "ground/mission_control/serve_command.hpp"

int main(int argc, char** argv) {
    return rse::ground::runGroundCli(argc, argv, std::cout, std::cerr, rse::ground::LinkFactory(),
                                     rse::ground::mission_control::runServe);
}
