// `rse-ground table ...`: the command line over ground/table_compiler.hpp.
//
//   table build SRC.toml -o OUT.tbl          one source -> one image
//   table build --cpp OUT.cpp SRC.toml...    the default-images source (one per table)
//   table show FILE                          check and print an image (or a .toml source, compiled)
//   table check IMAGE.tbl                    check only: prints one line
//   table list                               every table and field with units and range
//
// Options are parsed with getopt_long (ground/cli_options.hpp). Exit status: 0 ok
// (or --help: the usage on out), 1 bad input (the message on err), 2 a bad
// command line (one line and "see 'rse-ground --help'" on err).
#pragma once

#include <iosfwd>

namespace rse::ground {

// argv[0] is "table". Output goes to out, diagnostics to err.
int runTableCommand(int argc, char** argv, std::ostream& out, std::ostream& err);

}  // namespace rse::ground
