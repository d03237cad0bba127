#include "ground/table_tool.hpp"

#include <fstream>
#include <ostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "fsw/tables/table_image.hpp"
#include "ground/table_compiler.hpp"

namespace rse::ground {
namespace {

constexpr int kExitOk = 0;
constexpr int kExitBadInput = 1;
constexpr int kExitUsage = 2;

int usage(std::ostream& err, const std::string& why) {
    err << "rse-ground table: " << why << "\n"
        << "usage: rse-ground table build SRC.toml -o OUT.tbl\n"
           "       rse-ground table build --cpp OUT.cpp SRC.toml...\n"
           "       rse-ground table show IMAGE.tbl|SRC.toml\n"
           "       rse-ground table check IMAGE.tbl\n"
           "       rse-ground table list\n";
    return kExitUsage;
}

// Writes OUT only once everything compiled, so a failed build leaves no
// half-written file for make to mistake as up to date.
int build(const std::vector<std::string>& args, std::ostream& out) {
    std::string output;
    bool cpp = false;
    std::vector<std::string> sources;
    for (std::size_t i = 0; i < args.size(); ++i) {
        if ((args[i] == "-o" || args[i] == "--cpp") && output.empty() && i + 1 < args.size()) {
            cpp = args[i] == "--cpp";
            output = args[++i];
        } else if (!args[i].empty() && args[i][0] == '-') {
            throw std::invalid_argument("build: unexpected option " + args[i]);
        } else {
            sources.push_back(args[i]);
        }
    }
    if (output.empty() || sources.empty() || (!cpp && sources.size() != 1)) {
        throw std::invalid_argument("build: give one SRC.toml with -o OUT.tbl, or --cpp OUT.cpp and sources");
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
    if (argc < 2) {
        return usage(err, "missing subcommand");
    }
    const std::string command = argv[1];
    const std::vector<std::string> args(argv + 2, argv + argc);
    try {
        if (command == "build") {
            return build(args, out);
        }
        if (command == "show" && args.size() == 1) {
            return show(args[0], out);
        }
        if (command == "check" && args.size() == 1) {
            return check(args[0], out, err);
        }
        if (command == "list" && args.empty()) {
            list(out);
            return kExitOk;
        }
    } catch (const std::invalid_argument& e) {
        return usage(err, e.what());
    } catch (const std::exception& e) {
        // TableSourceError (bad source, unreadable file) and anything unexpected.
        err << e.what() << "\n";
        return kExitBadInput;
    }
    return usage(err, "unknown subcommand or wrong arguments: " + command);
}

}  // namespace rse::ground
