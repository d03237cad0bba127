// The ground table compiler and `rse-ground table` (ground/table_compiler.hpp,
// ground/table_tool.hpp). That docs/tables.md describes every table field:
// unit_test/fsw/tables/test_table_docs.cpp.
#include <unistd.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/table_compiler.hpp"
#include "ground/table_tool.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::ground;
using namespace rse::tables;
using rse::test::defaultImage;

namespace {

const char* const kGoodGeometry = R"(# a comment
table = "ROVER_GEOMETRY"
version = 3

[values]
wheel_radius_m = 0.125
track_width_m = 0.6
wheelbase_m = 0.7
footprint_radius_m = 0.6
skid_factor = 1.5
max_wheel_speed_rad_s = 5     # an integer is fine for a float field
max_body_speed_m_s = 0.3
max_body_rate_rad_s = 0.5
max_accel_m_s2 = 0.2
max_manual_drive_s = 60
)";

// Replaces the first occurrence of `from` in the good source.
std::string goodWith(const std::string& from, const std::string& to) {
    std::string text = kGoodGeometry;
    const std::size_t at = text.find(from);
    CHECK_TEXT(at != std::string::npos, from.c_str());
    return text.replace(at, from.size(), to);
}

// The message of the TableSourceError compiling `text` throws ("" if none).
std::string errorOf(const std::string& text) {
    try {
        (void)compileTableText(text, "src.toml");
    } catch (const TableSourceError& e) {
        return e.what();
    }
    return "";
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string tempPath(const std::string& name) {
    return "/tmp/rse_test_tables_" + std::to_string(::getpid()) + "_" + name;
}

void writeText(const std::string& path, const std::string& text) {
    std::ofstream out(path, std::ios::binary | std::ios::trunc);
    out << text;
}

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

struct ToolResult {
    int status;
    std::string out;
    std::string err;
};

ToolResult tool(std::vector<std::string> args) {
    args.insert(args.begin(), "table");
    std::vector<char*> argv;
    for (std::string& a : args) {
        argv.push_back(&a[0]);
    }
    std::ostringstream out;
    std::ostringstream err;
    const int status = runTableCommand(static_cast<int>(argv.size()), argv.data(), out, err);
    return {status, out.str(), err.str()};
}

const char* const kSources[] = {"tables/rover_geometry.toml", "tables/estimator_noise.toml",
                                "tables/planner.toml",        "tables/habitual.toml",
                                "tables/can_node_map.toml",   "tables/fault_response.toml",
                                "tables/drive_health_model.toml", "tables/follower.toml",
                                "tables/coarse_map.toml",     "tables/fault_protection.toml"};

}  // namespace

TEST_GROUP(TableCompiler){};

TEST(TableCompiler, CompilesASourceIntoACheckedImage) {
    const CompiledTable c = compileTableText(kGoodGeometry, "src.toml");
    CHECK(c.table == findTable(TableId::kRoverGeometry));
    LONGS_EQUAL(3, c.version);
    CHECK_TRUE(checkTableImage(c.image.data(), c.image.size(), TableId::kRoverGeometry).ok());
    RoverGeometryTable t{};
    CHECK_TRUE(decodeTable(c.image.data(), c.image.size(), &t).ok());
    CHECK_EQUAL(0.125F, t.wheel_radius_m);
    CHECK_EQUAL(5.0F, t.max_wheel_speed_rad_s);
    LONGS_EQUAL(60, t.max_manual_drive_s);
}

TEST(TableCompiler, TheSourcesInTablesAreTheDefaultImages) {
    for (const char* source : kSources) {
        const CompiledTable c = compileTableFile(source);
        CHECK_TEXT(c.image == defaultImage(c.table->id), source);
    }
}

TEST(TableCompiler, SourceToImageToTextRoundTrip) {
    const std::vector<std::uint8_t> image = compileTableSource("tables/can_node_map.toml");
    const std::string text = describeImage(image.data(), image.size());
    CHECK_TEXT(contains(text, "CAN_NODE_MAP (id 5)"), text.c_str());
    CHECK_TEXT(contains(text, "version 1, format 1"), text.c_str());
    CHECK_TEXT(contains(text, "check: ok"), text.c_str());
    CHECK_TEXT(contains(text, "[1, 2, 3, 4, 5, 6] node"), text.c_str());
    CHECK_TEXT(contains(text, "heartbeat_timeout_ms"), text.c_str());
    CHECK_TEXT(contains(text, "250 ms"), text.c_str());
    // Every field is listed.
    const TableDesc* table = findTable(TableId::kCanNodeMap);
    for (std::size_t f = 0; f < table->fieldCount; ++f) {
        CHECK_TEXT(contains(text, table->fields[f].name), table->fields[f].name);
    }
    // Floats print as written in the source, not as their binary expansion.
    const std::vector<std::uint8_t> geometry = compileTableSource("tables/rover_geometry.toml");
    const std::string g = describeImage(geometry.data(), geometry.size());
    CHECK_TEXT(contains(g, "0.1 m"), g.c_str());
    CHECK_TEXT(!contains(g, "0.100000"), g.c_str());
    const std::vector<std::uint8_t> planner = compileTableSource("tables/planner.toml");
    CHECK_TEXT(contains(describeImage(planner.data(), planner.size()), "0.001 -"), "risk bound");
}

TEST(TableCompiler, DescribesABadImageAndMarksTheField) {
    CanNodeMapTable map{};
    const std::vector<std::uint8_t> good = defaultImage(TableId::kCanNodeMap);
    CHECK_TRUE(decodeTable(good.data(), good.size(), &map).ok());
    map.hazard_node_id = 0;
    std::vector<std::uint8_t> bad(kMaxTableImageSize);
    bad.resize(encodeTable(map, 1, bad.data(), bad.size()));
    const std::string text = describeImage(bad.data(), bad.size());
    CHECK_TEXT(contains(text, "REJECTED, out of range: hazard_node_id = 0, allowed [1, 127] node"), text.c_str());
    CHECK_TEXT(contains(text, "<-- out of range"), text.c_str());
    std::vector<std::uint8_t> flipped = good;
    flipped[25] ^= 0x01;
    CHECK_TEXT(contains(describeCheck(flipped.data(), flipped.size()), "bad CRC (header 0x"), "crc");
    CHECK_TEXT(contains(describeImage(flipped.data(), 3), "not a table image: too short"), "short");
}

TEST(TableCompiler, UnknownKeyIsNamedWithItsLine) {
    const std::string e = errorOf(goodWith("max_manual_drive_s = 60", "max_manual_drive_s = 60\nmax_warp = 9"));
    CHECK_TEXT(contains(e, "src.toml:16: values.max_warp: unknown field of ROVER_GEOMETRY"), e.c_str());
    const std::string top = errorOf(goodWith("version = 3", "version = 3\nauthor = \"me\""));
    CHECK_TEXT(contains(top, "src.toml:4: author: unknown key"), top.c_str());
}

TEST(TableCompiler, OutOfRangeIsNamedWithItsRange) {
    const std::string e = errorOf(goodWith("wheel_radius_m = 0.125", "wheel_radius_m = 5.0"));
    CHECK_TEXT(contains(e, "src.toml:6: values.wheel_radius_m: 5 is out of range [0.05, 0.5] m"), e.c_str());
    const std::string n = errorOf(goodWith("max_manual_drive_s = 60", "max_manual_drive_s = -1"));
    CHECK_TEXT(contains(n, "values.max_manual_drive_s: -1 is out of range [1, 600] s"), n.c_str());
    const std::string inf = errorOf(goodWith("skid_factor = 1.5", "skid_factor = inf"));
    CHECK_TEXT(contains(inf, "values.skid_factor: must be a finite number"), inf.c_str());
}

TEST(TableCompiler, MissingKeyIsNamedWithWhatItIs) {
    const std::string e = errorOf(goodWith("skid_factor = 1.5\n", ""));
    CHECK_TEXT(contains(e, "values: missing field 'skid_factor' (f32, [1, 3] -"), e.c_str());
    CHECK_TEXT(contains(errorOf(goodWith("version = 3\n", "")), "missing key 'version'"), "version");
    CHECK_TEXT(contains(errorOf(goodWith("table = \"ROVER_GEOMETRY\"\n", "")), "missing key 'table'"), "table");
}

TEST(TableCompiler, WrongTypesAndShapesAreNamed) {
    CHECK_TEXT(contains(errorOf(goodWith("max_manual_drive_s = 60", "max_manual_drive_s = 60.5")),
                        "values.max_manual_drive_s: must be an integer (u16 field, got 60.5)"),
               "integer");
    CHECK_TEXT(contains(errorOf(goodWith("skid_factor = 1.5", "skid_factor = \"fast\"")),
                        "values.skid_factor: must be a number (got a string)"),
               "string");
    CHECK_TEXT(contains(errorOf(goodWith("skid_factor = 1.5", "skid_factor = [1.5]")),
                        "values.skid_factor: must be a single number, not an array"),
               "array");
    CHECK_TEXT(contains(errorOf(goodWith("ROVER_GEOMETRY", "ROVER_GEOMETRI")),
                        "table: unknown table 'ROVER_GEOMETRI' (one of ROVER_GEOMETRY, ESTIMATOR_NOISE"),
               "table name");
    CHECK_TEXT(contains(errorOf(goodWith("version = 3", "version = -3")), "version: -3 is out of range"), "version");
    const std::string map = readText("tables/can_node_map.toml");
    std::string shortMap = map;
    shortMap.replace(shortMap.find("[1, 2, 3, 4, 5, 6]"), 18, "[1, 2, 3, 4, 5]");
    CHECK_TEXT(contains(errorOf(shortMap), "values.drive_node_id: must have 6 elements (got 5)"), "length");
    std::string badElement = map;
    badElement.replace(badElement.find("[1, 2, 3, 4, 5, 6]"), 18, "[1, 2, 3, 400, 5, 6]");
    CHECK_TEXT(contains(errorOf(badElement), "values.drive_node_id[3]: 400 is out of range [1, 127] node"),
               "element");
}

TEST(TableCompiler, CrossFieldRulesAreChecked) {
    std::string text = readText("tables/fault_response.toml");
    text.replace(text.find("battery_low_v = 24.0"), 20, "battery_low_v = 26.0");
    const std::string e = errorOf(text);
    CHECK_TEXT(contains(e, "values.battery_low_v: must be below battery_clear_v"), e.c_str());
}

TEST(TableCompiler, EveryFaultIsReportedAtOnce) {
    std::string text = goodWith("wheel_radius_m = 0.125", "wheel_radius_m = 9");
    text += "bogus = 1\n";
    const std::string e = errorOf(text);
    CHECK_TEXT(contains(e, "values.wheel_radius_m"), e.c_str());
    CHECK_TEXT(contains(e, "values.bogus"), e.c_str());
    CHECK_TEXT(contains(e, "\n"), e.c_str());
}

TEST(TableCompiler, SyntaxErrorsNameTheLine) {
    const std::string e = errorOf(goodWith("skid_factor = 1.5", "skid_factor = = 1.5"));
    CHECK_TEXT(contains(e, "src.toml:10:"), e.c_str());
}

TEST(TableCompiler, ErrorsFromFilesNameTheFile) {
    const std::string path = tempPath("bad.toml");
    writeText(path, goodWith("track_width_m = 0.6", "track_width_m = 0.1"));
    std::string message;
    try {
        (void)compileTableSource(path);
    } catch (const TableSourceError& e) {
        message = e.what();
    }
    std::remove(path.c_str());
    CHECK_TEXT(contains(message, path + ":7: values.track_width_m: 0.1 is out of range [0.2, 2] m"), message.c_str());
    CHECK_THROWS(TableSourceError, compileTableSource(tempPath("does_not_exist.toml")));
}

TEST(TableCompiler, DefaultSourceNeedsEveryTableExactlyOnce) {
    std::vector<CompiledTable> all;
    for (const char* source : kSources) {
        all.push_back(compileTableFile(source));
    }
    const std::string cpp = defaultTablesSource(all);
    CHECK_TEXT(contains(cpp, "#include \"fsw/tables/default_tables.hpp\""), "include");
    CHECK_TEXT(contains(cpp, "kImage_ROVER_GEOMETRY[] = {\n    0x52, 0x53, 0x45, 0x54, 0x00, 0x01,"), cpp.c_str());
    CHECK_TEXT(contains(cpp, "const TableImageRef kDefaultTableImages[]"), "array");

    std::vector<CompiledTable> missing(all.begin(), all.end() - 1);
    std::string message;
    try {
        (void)defaultTablesSource(missing);
    } catch (const TableSourceError& e) {
        message = e.what();
    }
    CHECK_TEXT(contains(message, "no source for table FAULT_PROTECTION"), message.c_str());

    std::vector<CompiledTable> twice = all;
    twice.push_back(compileTableText(kGoodGeometry, "other.toml"));
    message.clear();
    try {
        (void)defaultTablesSource(twice);
    } catch (const TableSourceError& e) {
        message = e.what();
    }
    CHECK_TEXT(contains(message, "other.toml: table ROVER_GEOMETRY already given by tables/rover_geometry.toml"),
               message.c_str());
}

TEST(TableCompiler, FormatsValuesShortestAndReadable) {
    STRCMP_EQUAL("0.1", formatFieldValue(FieldType::kF32, static_cast<double>(0.1F)).c_str());
    STRCMP_EQUAL("1e-09", formatFieldValue(FieldType::kF64, 1e-9).c_str());
    STRCMP_EQUAL("100000", formatFieldValue(FieldType::kF64, 100000.0).c_str());
    STRCMP_EQUAL("-40", formatFieldValue(FieldType::kI32, -40.0).c_str());
}

TEST_GROUP(TableTool){};

TEST(TableTool, BuildShowAndCheckAnImage) {
    const std::string image = tempPath("geometry.tbl");
    ToolResult r = tool({"build", "tables/rover_geometry.toml", "-o", image});
    LONGS_EQUAL(0, r.status);
    CHECK_TEXT(contains(r.out, "ROVER_GEOMETRY version 1"), r.out.c_str());
    const std::string bytes = readText(image);
    CHECK_TRUE(std::vector<std::uint8_t>(bytes.begin(), bytes.end()) == defaultImage(TableId::kRoverGeometry));
    r = tool({"check", image});
    LONGS_EQUAL(0, r.status);
    CHECK_TEXT(contains(r.out, "ok, ROVER_GEOMETRY version 1"), r.out.c_str());
    r = tool({"show", image});
    LONGS_EQUAL(0, r.status);
    CHECK_TEXT(contains(r.out, "max_wheel_speed_rad_s"), r.out.c_str());

    writeText(image, bytes + "x");
    r = tool({"check", image});
    LONGS_EQUAL(1, r.status);
    CHECK_TEXT(contains(r.err, "rejected: bad length (header says 38 payload bytes, image has 39"), r.err.c_str());

    std::string corrupt = bytes;
    corrupt[30] = static_cast<char>(corrupt[30] ^ 0x40);
    writeText(image, corrupt);
    r = tool({"check", image});
    LONGS_EQUAL(1, r.status);
    CHECK_TEXT(contains(r.err, "rejected: bad CRC"), r.err.c_str());
    r = tool({"show", image});
    LONGS_EQUAL(1, r.status);
    CHECK_TEXT(contains(r.out, "REJECTED"), r.out.c_str());
    std::remove(image.c_str());
    LONGS_EQUAL(1, tool({"check", image}).status);  // gone: cannot open
}

TEST(TableTool, BuildCppWritesTheDefaultImagesSource) {
    const std::string out = tempPath("defaults.cpp");
    std::vector<std::string> args = {"build", "--cpp", out};
    args.insert(args.end(), std::begin(kSources), std::end(kSources));
    const ToolResult r = tool(args);
    LONGS_EQUAL(0, r.status);
    const std::string cpp = readText(out);
    std::remove(out.c_str());
    CHECK_TEXT(contains(cpp, "kImage_DRIVE_HEALTH_MODEL"), "all tables");
    // Missing a table: an error and no file.
    const ToolResult missing = tool({"build", "--cpp", out, "tables/planner.toml"});
    LONGS_EQUAL(1, missing.status);
    CHECK_TEXT(contains(missing.err, "no source for table ROVER_GEOMETRY"), missing.err.c_str());
    CHECK_TRUE(readText(out).empty());
}

TEST(TableTool, BadSourcesAndBadUsageHaveTheirExitCodes) {
    const std::string src = tempPath("bad_source.toml");
    writeText(src, goodWith("wheel_radius_m = 0.125", "wheel_radius_m = 0"));
    ToolResult r = tool({"build", src, "-o", tempPath("never.tbl")});
    std::remove(src.c_str());
    LONGS_EQUAL(1, r.status);
    CHECK_TEXT(contains(r.err, "values.wheel_radius_m: 0 is out of range"), r.err.c_str());
    LONGS_EQUAL(2, tool({}).status);
    LONGS_EQUAL(2, tool({"frobnicate"}).status);
    LONGS_EQUAL(2, tool({"build", "tables/planner.toml"}).status);  // no -o
    LONGS_EQUAL(2, tool({"build", "a.toml", "b.toml", "-o", "x.tbl"}).status);
    LONGS_EQUAL(2, tool({"check"}).status);
    r = tool({"list"});
    LONGS_EQUAL(0, r.status);
    CHECK_TEXT(contains(r.out, "drive_node_id  u8[6]  1 .. 127 node"), r.out.c_str());
}
