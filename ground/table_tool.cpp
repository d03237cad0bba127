#include "ground/table_tool.hpp"

#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fsw/tables/table_image.hpp"
#include "ground/cli_options.hpp"
#include "ground/table_compiler.hpp"

namespace rse::ground {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 1;

constexpr const char* kBuildUsage =
    "usage: rse-ground table build SRC.toml -o OUT.tbl, or table build --cpp OUT.cpp SRC.toml...";

// Writes OUT only once everything compiled, so a failed build leaves no
// half-written file for make to mistake as up to date.
int build(const std::vector<std::string>& args, std::ostream& out) {
    const ParsedOptions parsed = parseCliOptions("table build", args, {{nullptr, 'o', true}, {"cpp", 0, true}});
    const bool cpp = parsed.has("--cpp");
    if (cpp && parsed.has("-o")) {
        throw UsageError("table build: -o or --cpp, not both");
    }
    const std::string output = parsed.value(cpp ? "--cpp" : "-o").value_or("");
    const std::vector<std::string>& sources = parsed.operands;
    if (output.empty() || sources.empty() || (!cpp && sources.size() != 1)) {
        throw UsageError("table build: give one SRC.toml with -o OUT.tbl, or --cpp OUT.cpp and sources (" +
                         std::string(kBuildUsage) + ")");
    }
    if (!cpp) {
        const CompiledTable c = compileTableFile(sources[0]);
        writeTableImageFile(output, c.image);
        out << output << ": " << c.table->name << " version " << c.version << ", " << c.image.size() << " bytes\n";
        return kExitOk;
    }
    std::vector<CompiledTable> compiled;
    std::string errors;
    for (const std::string& source : sources) {
        try {
            compiled.push_back(compileTableFile(source));
        } catch (const TableSourceError& e) {
            errors += (errors.empty() ? "" : "\n") + std::string(e.what());
        }
    }
    if (!errors.empty()) {
        throw TableSourceError(errors);
    }
    const std::string text = defaultTablesSource(compiled);
    std::ofstream file(output, std::ios::trunc);
    file << text;
    file.close();
    if (!file) {
        throw TableSourceError(output + ": cannot write");
    }
    return kExitOk;
}

int show(const std::string& path, std::ostream& out) {
    const std::vector<std::uint8_t> image = readTableFile(path);
    out << describeImage(image.data(), image.size());
    return tables::checkTableImage(image.data(), image.size()).ok() ? kExitOk : kExitBadInput;
}

int check(const std::string& path, std::ostream& out, std::ostream& err) {
    const std::vector<std::uint8_t> image = readTableImageFile(path);
    if (!tables::checkTableImage(image.data(), image.size()).ok()) {
        err << path << ": rejected: " << describeCheck(image.data(), image.size()) << "\n";
        return kExitBadInput;
    }
    tables::TableHeader header;
    (void)tables::readTableHeader(image.data(), image.size(), &header);
    out << path << ": ok, " << tables::findTable(static_cast<tables::TableId>(header.tableId))->name << " version "
        << header.version << "\n";
    return kExitOk;
}

void list(std::ostream& out) {
    std::size_t count = 0;
    const tables::TableDesc* descs = tables::tableDescs(&count);
    for (std::size_t t = 0; t < count; ++t) {
        const tables::TableDesc& table = descs[t];
        out << table.name << " (id " << static_cast<unsigned>(table.id) << ", payload " << table.payloadSize
            << " bytes): " << table.description << "\n";
        for (std::size_t f = 0; f < table.fieldCount; ++f) {
            const tables::TableFieldDesc& field = table.fields[f];
            out << "  " << field.name << "  " << tables::toString(field.type)
                << (field.count > 1 ? "[" + std::to_string(field.count) + "]" : std::string()) << "  "
                << formatFieldValue(tables::FieldType::kF64, field.min) << " .. "
                << formatFieldValue(tables::FieldType::kF64, field.max) << " " << field.units << "  "
                << field.description << "\n";
        }
    }
}

}  // namespace

int runTableCommand(int argc, char** argv, std::ostream& out, std::ostream& err) {
    const std::string command = argc >= 2 ? argv[1] : "";
    const std::vector<std::string> args(argv + (argc >= 2 ? 2 : argc), argv + argc);
    try {
        if (command == "build") {
            return build(args, out);
        }
        // show, check and list take no option: --help is the only one they know.
        const ParsedOptions parsed = parseCliOptions(command.empty() ? "table" : "table " + command, args, {});
        if (command == "show") {
            expectOperands(parsed, 1, "table show", "usage: rse-ground table show IMAGE.tbl|SRC.toml");
            return show(parsed.operands[0], out);
        }
        if (command == "check") {
            expectOperands(parsed, 1, "table check", "usage: rse-ground table check IMAGE.tbl");
            return check(parsed.operands[0], out, err);
        }
        if (command == "list") {
            expectOperands(parsed, 0, "table list", "usage: rse-ground table list");
            list(out);
            return kExitOk;
        }
        throw UsageError(command.empty() ? "table: load, dump, build, show, check or list"
                                         : "table: unknown sub-command '" + command +
                                               "' (load, dump, build, show, check or list)");
    } catch (const UsageError& e) {
        return reportUsageError(err, e.what());
    } catch (const HelpRequested&) {
        out << groundUsage();
        return kExitOk;
    } catch (const std::exception& e) {
        // TableSourceError (bad source, unreadable file) and anything unexpected.
        err << e.what() << "\n";
        return kExitBadInput;
    }
}

}  // namespace rse::ground
