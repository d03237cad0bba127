// rse-ground: the operator's tool. For now only `rse-ground table ...`
// (ground/table_tool.hpp); the link commands come later.
#include <iostream>
#include <string>

#include "ground/table_tool.hpp"

int main(int argc, char** argv) {
    if (argc >= 2 && std::string(argv[1]) == "table") {
        return rse::ground::runTableCommand(argc - 1, argv + 1, std::cout, std::cerr);
    }
    std::cerr << "usage: rse-ground table build|show|check|list ...  (rse-ground table for details)\n";
    return 2;
}
