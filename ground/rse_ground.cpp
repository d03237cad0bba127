// rse-ground: the operator's tool. Everything is in ground/ground_cli.hpp
// (usage, options, exit codes) and docs/ground.md.
#include <iostream>

#include "ground/ground_cli.hpp"

int main(int argc, char** argv) { return rse::ground::runGroundCli(argc, argv, std::cout, std::cerr); }
