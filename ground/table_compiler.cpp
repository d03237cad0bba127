#include "ground/table_compiler.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string_view>

#include <toml++/toml.h>

namespace rse::ground {

using tables::FieldType;
using tables::TableCheck;
using tables::TableDesc;
using tables::TableFieldDesc;
using tables::TableReject;

namespace {

// Sources and images are small; the bound keeps a wrong argument (a disk image,
// a device) from being read whole.
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 20;

const char* typeName(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table:
            return "a table";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::string:
            return "a string";
        case toml::node_type::integer:
            return "an integer";
        case toml::node_type::floating_point:
            return "a floating-point number";
        case toml::node_type::boolean:
            return "a boolean";
        case toml::node_type::date:
        case toml::node_type::time:
        case toml::node_type::date_time:
            return "a date or time";
        default:
            return "nothing";
    }
}

std::string hex32(std::uint32_t v) {
    char text[16];
    std::snprintf(text, sizeof text, "0x%08X", static_cast<unsigned>(v));
    return text;
}

std::string knownTables() {
    std::size_t count = 0;
    const TableDesc* descs = tables::tableDescs(&count);
    std::string names;
    for (std::size_t i = 0; i < count; ++i) {
        names += (i == 0 ? "" : ", ") + std::string(descs[i].name);
    }
    return names;
}

std::string rangeText(const TableFieldDesc& field) {
    return "[" + formatFieldValue(FieldType::kF64, field.min) + ", " + formatFieldValue(FieldType::kF64, field.max) +
           "] " + field.units;
}

std::string elementName(const TableFieldDesc& field, std::size_t element) {
    return field.count > 1 ? std::string(field.name) + "[" + std::to_string(element) + "]" : std::string(field.name);
}

// Collects every fault of a source, each prefixed with file and line, and
// throws them together at the end: an engineer fixes a file in one pass.
class SourceCompiler {
public:
    explicit SourceCompiler(std::string source) : source_(std::move(source)) {}

    CompiledTable compile(const std::string& text);

private:
    void error(const toml::node* at, const std::string& what) {
        std::string where = source_;
        if (at != nullptr && at->source().begin.line > 0) {
            where += ":" + std::to_string(at->source().begin.line);
        }
        errors_.push_back(where + ": " + what);
    }

    const TableDesc* tableName(const toml::table& root);
    bool version(const toml::table& root, std::uint32_t* out);
    void field(const TableDesc& table, std::uint16_t index, const toml::node& node, std::vector<std::uint8_t>* payload);
    bool element(const TableFieldDesc& field, std::size_t index, const toml::node& node, double* value);

    std::string source_;
    std::vector<std::string> errors_;
};

const TableDesc* SourceCompiler::tableName(const toml::table& root) {
    const toml::node* n = root.get("table");
    if (n == nullptr) {
        error(nullptr, "missing key 'table' (one of " + knownTables() + ")");
        return nullptr;
    }
    if (!n->is_string()) {
        error(n, std::string("table: must be a string (got ") + typeName(*n) + ")");
        return nullptr;
    }
    const std::string& name = n->as_string()->get();
    const TableDesc* table = tables::findTable(name.c_str());
    if (table == nullptr) {
        error(n, "table: unknown table '" + name + "' (one of " + knownTables() + ")");
    }
    return table;
}

bool SourceCompiler::version(const toml::table& root, std::uint32_t* out) {
    const toml::node* n = root.get("version");
    if (n == nullptr) {
        error(nullptr, "missing key 'version' (the content revision, 0 .. 4294967295)");
        return false;
    }
    if (!n->is_integer()) {
        error(n, std::string("version: must be an integer (got ") + typeName(*n) + ")");
        return false;
    }
    const std::int64_t v = n->as_integer()->get();
    if (v < 0 || v > 0xFFFFFFFFLL) {
        error(n, "version: " + std::to_string(v) + " is out of range [0, 4294967295]");
        return false;
    }
    *out = static_cast<std::uint32_t>(v);
    return true;
}

bool SourceCompiler::element(const TableFieldDesc& field, std::size_t index, const toml::node& node, double* value) {
    const std::string name = "values." + elementName(field, index);
    if (node.is_integer()) {
        const std::int64_t v = node.as_integer()->get();
        *value = static_cast<double>(v);
        // Beyond 2^53 a double no longer holds every integer; far beyond any range anyway.
        if (v > (std::int64_t{1} << 53) || v < -(std::int64_t{1} << 53)) {
            error(&node, name + ": " + std::to_string(v) + " is out of range " + rangeText(field));
            return false;
        }
    } else if (node.is_floating_point()) {
        if (!tables::isFloatType(field.type)) {
            error(&node, name + ": must be an integer (" + tables::toString(field.type) + " field, got " +
                             formatFieldValue(FieldType::kF64, node.as_floating_point()->get()) + ")");
            return false;
        }
        *value = node.as_floating_point()->get();
    } else {
        error(&node, name + ": must be a number (got " + typeName(node) + ")");
        return false;
    }
    const TableReject verdict = tables::checkFieldValue(field, *value);
    if (verdict == TableReject::kNotFinite) {
        error(&node, name + ": must be a finite number (got " + formatFieldValue(FieldType::kF64, *value) + ")");
        return false;
    }
    if (verdict != TableReject::kNone) {
        error(&node, name + ": " + formatFieldValue(FieldType::kF64, *value) + " is out of range " + rangeText(field));
        return false;
    }
    return true;
}

void SourceCompiler::field(const TableDesc& table, std::uint16_t index, const toml::node& node,
                           std::vector<std::uint8_t>* payload) {
    const TableFieldDesc& desc = table.fields[index];
    const auto write = [&](std::size_t e, const toml::node& n) {
        double value = 0.0;
        if (element(desc, e, n, &value) &&
            !tables::writeFieldValue(table, payload->data(), payload->size(), index, static_cast<std::uint16_t>(e),
                                     value)) {
            error(&n, "values." + elementName(desc, e) + ": cannot be stored as " + tables::toString(desc.type));
        }
    };
    if (desc.count == 1) {
        if (node.is_array()) {
            error(&node, std::string("values.") + desc.name + ": must be a single number, not an array");
            return;
        }
        write(0, node);
        return;
    }
    const toml::array* array = node.as_array();
    if (array == nullptr) {
        error(&node, std::string("values.") + desc.name + ": must be an array of " + std::to_string(desc.count) +
                         " numbers (got " + typeName(node) + ")");
        return;
    }
    if (array->size() != desc.count) {
        error(&node, std::string("values.") + desc.name + ": must have " + std::to_string(desc.count) +
                         " elements (got " + std::to_string(array->size()) + ")");
        return;
    }
    for (std::size_t e = 0; e < desc.count; ++e) {
        write(e, *array->get(e));
    }
}

CompiledTable SourceCompiler::compile(const std::string& text) {
    toml::table root;
    try {
        root = toml::parse(text, source_);
    } catch (const toml::parse_error& e) {
        throw TableSourceError(source_ + ":" + std::to_string(e.source().begin.line) + ":" +
                               std::to_string(e.source().begin.column) + ": " + std::string(e.description()));
    }
    for (auto&& [key, value] : root) {
        if (key.str() != "table" && key.str() != "version" && key.str() != "values") {
            error(&value, std::string(key.str()) + ": unknown key (expected table, version and [values])");
        }
    }
    CompiledTable out;
    out.source = source_;
    out.table = tableName(root);
    (void)version(root, &out.version);
    const toml::node* valuesNode = root.get("values");
    const toml::table* values = valuesNode != nullptr ? valuesNode->as_table() : nullptr;
    if (valuesNode == nullptr) {
        error(nullptr, "missing table [values]");
    } else if (values == nullptr) {
        error(valuesNode, std::string("values: must be a table (got ") + typeName(*valuesNode) + ")");
    }
    if (out.table == nullptr || values == nullptr) {
        throw TableSourceError([&] {
            std::string all;
            for (const std::string& e : errors_) {
                all += (all.empty() ? "" : "\n") + e;
            }
            return all;
        }());
    }
    const TableDesc& table = *out.table;
    std::vector<std::uint8_t> image(tables::kTableHeaderSize + table.payloadSize, 0);
    std::vector<std::uint8_t> payload(table.payloadSize, 0);
    for (auto&& [key, value] : *values) {
        bool known = false;
        for (std::size_t f = 0; f < table.fieldCount; ++f) {
            known = known || key.str() == table.fields[f].name;
        }
        if (!known) {
            error(&value, "values." + std::string(key.str()) + ": unknown field of " + table.name);
        }
    }
    std::vector<const toml::node*> nodes(table.fieldCount, nullptr);
    for (std::size_t f = 0; f < table.fieldCount; ++f) {
        const TableFieldDesc& desc = table.fields[f];
        nodes[f] = values->get(desc.name);
        if (nodes[f] == nullptr) {
            error(valuesNode, std::string("values: missing field '") + desc.name + "' (" +
                                  tables::toString(desc.type) +
                                  (desc.count > 1 ? " x " + std::to_string(desc.count) : std::string()) + ", " +
                                  rangeText(desc) + ": " + desc.description + ")");
            continue;
        }
        field(table, static_cast<std::uint16_t>(f), *nodes[f], &payload);
    }
    if (errors_.empty()) {
        // Per-field checks passed; what is left is the cross-field rules.
        const TableCheck check = tables::checkTablePayload(table, payload.data(), payload.size());
        if (check.reason == TableReject::kInconsistent) {
            std::size_t ruleCount = 0;
            const tables::TableRuleDesc* rules = tables::tableRules(&ruleCount);
            for (std::size_t i = 0; i < ruleCount; ++i) {
                const auto lower = static_cast<std::size_t>(check.field);
                if (rules[i].id == table.id && rules[i].lower == lower) {
                    error(nodes[lower], std::string("values.") + table.fields[lower].name + ": must be below " +
                                            table.fields[rules[i].upper].name + " (" + rules[i].why + ")");
                }
            }
        } else if (!check.ok()) {
            error(nullptr,
                  std::string("internal: compiled payload fails its check: ") + tables::toString(check.reason));
        }
    }
    if (!errors_.empty()) {
        std::string all;
        for (const std::string& e : errors_) {
            all += (all.empty() ? "" : "\n") + e;
        }
        throw TableSourceError(all);
    }
    std::copy(payload.begin(), payload.end(), image.begin() + static_cast<std::ptrdiff_t>(tables::kTableHeaderSize));
    if (tables::sealTableImage(table.id, out.version, image.data(), image.size()) != image.size() ||
        !tables::checkTableImage(image.data(), image.size(), table.id).ok()) {
        throw TableSourceError(source_ + ": internal: sealed image fails its check");
    }
    out.image = std::move(image);
    return out;
}

std::string readWholeFile(const std::string& path, std::size_t limit) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw TableSourceError(path + ": cannot open");
    }
    std::string data((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
    if (in.bad()) {
        throw TableSourceError(path + ": read error");
    }
    if (data.size() > limit) {
        throw TableSourceError(path + ": larger than " + std::to_string(limit) + " bytes: not a table source or image");
    }
    return data;
}

}  // namespace

std::string formatFieldValue(FieldType type, double value) {
    // Shortest round-trip digits; plain notation where that reads well (100000,
    // 0.0001), scientific for the very small or large (1e-09).
    const double magnitude = std::fabs(value);
    const std::chars_format format = (magnitude == 0.0 || (magnitude >= 1e-4 && magnitude < 1e9))
                                         ? std::chars_format::fixed
                                         : std::chars_format::scientific;
    char text[400];
    std::to_chars_result r{};
    if (type == FieldType::kF32) {
        r = std::to_chars(text, text + sizeof text, static_cast<float>(value), format);
    } else {
        r = std::to_chars(text, text + sizeof text, value, format);
    }
    return r.ec == std::errc() ? std::string(text, r.ptr) : std::string("?");
}

CompiledTable compileTableText(const std::string& text, const std::string& sourceName) {
    return SourceCompiler(sourceName).compile(text);
}

CompiledTable compileTableFile(const std::string& path) {
    return compileTableText(readWholeFile(path, kMaxFileBytes), path);
}

std::vector<std::uint8_t> compileTableSource(const std::string& path) { return compileTableFile(path).image; }

std::vector<std::uint8_t> readTableImageFile(const std::string& path) {
    const std::string data = readWholeFile(path, kMaxFileBytes);
    return std::vector<std::uint8_t>(data.begin(), data.end());
}

std::vector<std::uint8_t> readTableFile(const std::string& path) {
    const bool source = path.size() > 5 && path.compare(path.size() - 5, 5, ".toml") == 0;
    return source ? compileTableSource(path) : readTableImageFile(path);
}

void writeTableImageFile(const std::string& path, const std::vector<std::uint8_t>& image) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out.write(reinterpret_cast<const char*>(image.data()), static_cast<std::streamsize>(image.size()));
    out.close();
    if (!out) {
        throw TableSourceError(path + ": cannot write");
    }
}

std::string describeCheck(const std::uint8_t* image, std::size_t length) {
    const TableCheck check = tables::checkTableImage(image, length);
    std::string text = tables::toString(check.reason);
    tables::TableHeader header;
    const bool haveHeader = tables::readTableHeader(image, length, &header);
    const TableDesc* table = haveHeader ? tables::findTable(static_cast<tables::TableId>(header.tableId)) : nullptr;
    switch (check.reason) {
        case TableReject::kTooShort:
            return text + " (" + std::to_string(length) + " bytes, the header alone is " +
                   std::to_string(tables::kTableHeaderSize) + ")";
        case TableReject::kBadMagic:
            return text + " (" + hex32(header.magic) + ", expected " + hex32(tables::kTableMagic) + " \"RSET\")";
        case TableReject::kBadFormat:
            return text + " (" + std::to_string(header.format) + ", expected " + std::to_string(tables::kTableFormat) +
                   ")";
        case TableReject::kUnknownTable:
            return text + " (id " + std::to_string(header.tableId) + ")";
        case TableReject::kBadLength:
            return text + " (header says " + std::to_string(header.payloadLength) + " payload bytes, image has " +
                   std::to_string(length - tables::kTableHeaderSize) + ", table " + table->name + " needs " +
                   std::to_string(table->payloadSize) + ")";
        case TableReject::kBadCrc:
            return text + " (header " + hex32(header.crc) + ", computed " +
                   hex32(tables::computeTableCrc(image, table->payloadSize)) + ")";
        case TableReject::kOutOfRange:
        case TableReject::kNotFinite:
        case TableReject::kInconsistent: {
            const TableFieldDesc& field = table->fields[check.field];
            double value = 0.0;
            (void)tables::readFieldValue(*table, image + tables::kTableHeaderSize, length - tables::kTableHeaderSize,
                                         static_cast<std::uint16_t>(check.field), check.element, &value);
            text += ": " + elementName(field, check.element) + " = " + formatFieldValue(field.type, value);
            if (check.reason == TableReject::kOutOfRange) {
                text += ", allowed " + rangeText(field);
            }
            if (check.reason == TableReject::kInconsistent) {
                std::size_t ruleCount = 0;
                const tables::TableRuleDesc* rules = tables::tableRules(&ruleCount);
                for (std::size_t i = 0; i < ruleCount; ++i) {
                    if (rules[i].id == table->id && rules[i].lower == static_cast<std::uint16_t>(check.field)) {
                        text += ", must be below " + std::string(table->fields[rules[i].upper].name) + " (" +
                                rules[i].why + ")";
                    }
                }
            }
            return text;
        }
        default:
            return text;
    }
}

std::string describeImage(const std::uint8_t* image, std::size_t length) {
    std::ostringstream out;
    tables::TableHeader header;
    if (!tables::readTableHeader(image, length, &header)) {
        out << "not a table image: " << describeCheck(image, length) << "\n";
        return out.str();
    }
    const TableDesc* table = tables::findTable(static_cast<tables::TableId>(header.tableId));
    out << (table != nullptr ? table->name : "unknown table") << " (id " << header.tableId << ")";
    if (table != nullptr) {
        out << ": " << table->description;
    }
    out << "\n  version " << header.version << ", format " << header.format << ", " << length << " bytes (payload "
        << header.payloadLength << "), crc " << hex32(header.crc) << "\n";
    const TableCheck check = tables::checkTableImage(image, length);
    out << "  check: " << (check.ok() ? "ok" : "REJECTED, " + describeCheck(image, length)) << "\n";
    if (table == nullptr || length < tables::kTableHeaderSize + table->payloadSize) {
        return out.str();
    }
    const std::uint8_t* payload = image + tables::kTableHeaderSize;
    std::vector<std::string> names;
    std::vector<std::string> values;
    std::size_t nameWidth = 0;
    std::size_t valueWidth = 0;
    for (std::size_t f = 0; f < table->fieldCount; ++f) {
        const TableFieldDesc& field = table->fields[f];
        std::string text;
        for (std::uint16_t e = 0; e < field.count; ++e) {
            double v = 0.0;
            (void)tables::readFieldValue(*table, payload, table->payloadSize, static_cast<std::uint16_t>(f), e, &v);
            text += (e == 0 ? "" : ", ") + formatFieldValue(field.type, v);
        }
        text = (field.count > 1 ? "[" + text + "]" : text) + " " + field.units;
        names.emplace_back(field.name);
        values.push_back(text);
        nameWidth = std::max(nameWidth, names.back().size());
        valueWidth = std::max(valueWidth, text.size());
    }
    for (std::size_t f = 0; f < table->fieldCount; ++f) {
        const TableFieldDesc& field = table->fields[f];
        out << "  " << names[f] << std::string(nameWidth - names[f].size() + 2, ' ') << values[f]
            << std::string(valueWidth - values[f].size() + 2, ' ') << "["
            << formatFieldValue(FieldType::kF64, field.min) << ", " << formatFieldValue(FieldType::kF64, field.max)
            << "]  " << field.description;
        if (check.field == static_cast<std::int16_t>(f)) {
            out << "   <-- " << tables::toString(check.reason);
        }
        out << "\n";
    }
    return out.str();
}

std::string defaultTablesSource(const std::vector<CompiledTable>& compiled) {
    std::size_t count = 0;
    const TableDesc* descs = tables::tableDescs(&count);
    std::vector<const CompiledTable*> byTable(count, nullptr);
    std::string problems;
    for (const CompiledTable& c : compiled) {
        const std::size_t index = c.table != nullptr ? tables::tableIndex(c.table->id) : count;
        if (index >= count || !tables::checkTableImage(c.image.data(), c.image.size(), c.table->id).ok()) {
            problems += "\n" + c.source + ": not a valid table image";
        } else if (byTable[index] != nullptr) {
            problems += "\n" + c.source + ": table " + descs[index].name + " already given by " +
                        byTable[index]->source;
        } else {
            byTable[index] = &c;
        }
    }
    for (std::size_t i = 0; i < count; ++i) {
        if (byTable[i] == nullptr) {
            problems += std::string("\nno source for table ") + descs[i].name;
        }
    }
    if (!problems.empty()) {
        throw TableSourceError("default tables: every table needs exactly one source:" + problems);
    }
    std::ostringstream out;
    out << "// Generated by `rse-ground table build --cpp` from the table sources named below.\n"
           "// Do not edit: edit tables/*.toml and rebuild (docs/tables.md).\n"
           "#include \"fsw/tables/default_tables.hpp\"\n\n"
           "#include <cstdint>\n\n"
           "namespace rse::tables {\n"
           "namespace {\n";
    for (std::size_t i = 0; i < count; ++i) {
        const CompiledTable& c = *byTable[i];
        tables::TableHeader header;
        (void)tables::readTableHeader(c.image.data(), c.image.size(), &header);
        std::string source;
        for (char ch : c.source) {
            source += (ch >= ' ' && ch <= '~') ? ch : '?';
        }
        out << "\n// " << descs[i].name << " version " << header.version << ", crc " << hex32(header.crc) << ", from "
            << source << "\nconstexpr std::uint8_t kImage_" << descs[i].name << "[] = {";
        for (std::size_t b = 0; b < c.image.size(); ++b) {
            char hex[8];
            std::snprintf(hex, sizeof hex, "0x%02X,", static_cast<unsigned>(c.image[b]));
            out << (b % 12 == 0 ? "\n    " : " ") << hex;
        }
        out << "\n};\n";
    }
    out << "\n}  // namespace\n\nconst TableImageRef kDefaultTableImages[] = {\n";
    for (std::size_t i = 0; i < count; ++i) {
        out << "    {kImage_" << descs[i].name << ", sizeof kImage_" << descs[i].name << "},\n";
    }
    out << "};\n"
           "const std::size_t kDefaultTableImageCount = sizeof kDefaultTableImages / sizeof kDefaultTableImages[0];\n"
           "\n"
           "}  // namespace rse::tables\n";
    return out.str();
}

}  // namespace rse::ground
