// `rse-ground table ...`: the command line over ground/table_compiler.hpp.
//
//   table build SRC.toml -o OUT.tbl          one source -> one image
//   table build --cpp OUT.cpp SRC.toml...    the default-images source (one per table)
//   table show FILE                          check and print an image (or a .toml source, compiled)
//   table check IMAGE.tbl                    check only: prints one line
//   table list                               every table and field with units and range
//
// Exit status: 0 ok, 1 bad input (the message on err), 2 bad usage.
#pragma once

#include <iosfwd>

namespace rse::ground {

// argv[0] is "table". Output goes to out, diagnostics to err.
int runTableCommand(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace rse::ground
