// rse-ground table: load and dump move table images over the link
// (ground/table_transfer.hpp); build, show, check and list work on this
// machine and are the table tool's (ground/table_tool.hpp).
#include <ostream>

#include "fsw/tables/table_types.hpp"
#include "ground/cli_subcommands.hpp"
#include "ground/table_compiler.hpp"
#include "ground/table_tool.hpp"
#include "ground/table_transfer.hpp"

namespace rse::ground {
namespace {

// Upload, validate (and with --activate activate) an image.
int loadTable(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("table load", words, {{"activate", 0, false}, {"force", 0, false}});
    expectOperands(parsed, 1, "table load", "usage: rse-ground table load IMAGE.tbl [--activate] [--force]");
    std::vector<std::uint8_t> image;
    try {
        image = readTableImageFile(parsed.operands[0]);
    } catch (const std::exception& e) {
        cli.err() << "table load: " << e.what() << "\n";
        return kExitLink;
    }
    CliContext::Session s = cli.openSession();
    return loadTableImage(*s.session, image, parsed.has("--activate"), parsed.has("--force"), cli.out(), cli.err());
}

// "1 ROVER_GEOMETRY, 2 ..." for the message naming a table that is not one.
std::string knownTables() {
    std::size_t n = 0;
    const tables::TableDesc* all = tables::tableDescs(&n);
    std::string known;
    for (std::size_t i = 0; i < n; ++i) {
        known += (i > 0 ? ", " : "") + std::to_string(static_cast<unsigned>(all[i].id)) + " " + all[i].name;
    }
    return known;
}

// Download the active (or --inactive) image of a table and print it (or write it with -o).
int dumpTable(CliContext& cli, const Words& words) {
    const ParsedOptions parsed = parseCliOptions("table dump", words, {{"inactive", 0, false}, {nullptr, 'o', true}});
    expectOperands(parsed, 1, "table dump", "usage: rse-ground table dump ID|NAME [--inactive] [-o FILE]");
    const tables::TableDesc* table = lookupTable(parsed.operands[0]);
    if (table == nullptr) {
        throw UsageError("table dump: no table '" + parsed.operands[0] + "' (tables: " + knownTables() + ")");
    }
    CliContext::Session s = cli.openSession();
    return dumpTableImage(*s.session, *table, parsed.has("--inactive"), parsed.value("-o").value_or(""), cli.out(),
                          cli.err());
}

}  // namespace

int runTable(CliContext& cli, const Words& words) {
    const std::string sub = words.empty() ? std::string() : words[0];
    const Words rest(words.begin() + (words.empty() ? 0 : 1), words.end());
    if (sub == "load") {
        return loadTable(cli, rest);
    }
    if (sub == "dump") {
        return dumpTable(cli, rest);
    }
    // build, show, check, list: the table tool's, with its own argv ("table" first).
    std::vector<std::string> storage(words);
    storage.insert(storage.begin(), "table");
    std::vector<char*> argv;
    for (std::string& s : storage) {
        argv.push_back(s.data());
    }
    argv.push_back(nullptr);
    return runTableCommand(static_cast<int>(storage.size()), argv.data(), cli.out(), cli.err());
}

}  // namespace rse::ground
