// docs/dictionary.md and docs/dictionary.json are exactly what the exporter
// makes from the dictionary now (tests run from the repository root), and the
// exports carry every command, argument, packet, field and reason code.
#include <fstream>
#include <iterator>
#include <string>

#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/dictionary_export.hpp"
#include "ground/telemetry_limits.hpp"
#include "ground/text_format.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

bool readFile(const std::string& path, std::string* text) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        return false;
    }
    text->assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
    return true;
}

// The first line where two texts differ, for the failure message.
std::string firstDifference(const std::string& expected, const std::string& actual) {
    std::size_t line = 1;
    std::size_t start = 0;
    for (std::size_t i = 0; i < expected.size() || i < actual.size(); ++i) {
        const char e = i < expected.size() ? expected[i] : '\0';
        const char a = i < actual.size() ? actual[i] : '\0';
        if (e != a) {
            const std::size_t endE = expected.find('\n', start);
            const std::size_t endA = actual.find('\n', start);
            return "line " + std::to_string(line) + ": expected '" +
                   expected.substr(start, endE == std::string::npos ? std::string::npos : endE - start) +
                   "', file has '" + actual.substr(start, endA == std::string::npos ? std::string::npos : endA - start) +
                   "'";
        }
        if (e == '\n') {
            ++line;
            start = i + 1;
        }
    }
    return "";
}

void checkFresh(const std::string& path, const std::string& expected, const char* option) {
    std::string actual;
    const std::string fix = std::string(path) + " is stale: run `build/x86_64/bin/rse-ground dict " + option + " > " +
                            path + "` and commit it";
    if (!readFile(path, &actual)) {
        FAIL((path + " is missing (tests run from the repository root); " + fix).c_str());
    }
    if (actual != expected) {
        FAIL((fix + " (" + firstDifference(expected, actual) + ")").c_str());
    }
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_GROUP(GroundDictionaryExport){};

TEST(GroundDictionaryExport, DocsDictionaryMarkdownIsCurrent) {
    checkFresh("docs/dictionary.md", ground::exportDictionaryMarkdown(), "--markdown");
}

TEST(GroundDictionaryExport, DocsDictionaryJsonIsCurrent) {
    checkFresh("docs/dictionary.json", ground::exportDictionaryJson(), "--json");
}

TEST(GroundDictionaryExport, EveryCommandArgumentPacketFieldAndReasonIsExported) {
    const std::string md = ground::exportDictionaryMarkdown();
    const std::string json = ground::exportDictionaryJson();
    std::size_t count = 0;
    const cmdtlm::CommandDesc* commands = cmdtlm::commandDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        CHECK_TEXT(contains(md, std::string("### ") + commands[i].name + "\n"), commands[i].name);
        CHECK_TEXT(contains(json, std::string("\"name\": \"") + commands[i].name + "\""), commands[i].name);
        for (std::size_t a = 0; a < commands[i].argCount; ++a) {
            CHECK_TEXT(contains(md, std::string("| ") + commands[i].args[a].name + " | "), commands[i].args[a].name);
        }
    }
    const cmdtlm::TelemetryDesc* packets = cmdtlm::telemetryDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        CHECK_TEXT(contains(md, std::string("### ") + packets[i].name + "\n"), packets[i].name);
        CHECK_TEXT(contains(json, "\"payload_bytes\": " + std::to_string(packets[i].payloadSize)), packets[i].name);
        for (std::size_t f = 0; f < packets[i].fieldCount; ++f) {
            CHECK_TEXT(contains(md, std::string(" | ") + packets[i].fields[f].name + " | "), packets[i].fields[f].name);
        }
    }
    for (unsigned r = 0; r < cmdtlm::kRejectReasonCount; ++r) {
        const std::string name = cmdtlm::toString(static_cast<cmdtlm::CommandReject>(r));
        CHECK_TEXT(contains(md, "| " + std::to_string(r) + " | " + name + " | "), name.c_str());
        CHECK_TEXT(contains(json, "{\"code\": " + std::to_string(r) + ", \"name\": \"" + name + "\""), name.c_str());
        CHECK_FALSE(std::string(ground::rejectReasonDescription(r)).empty());
    }
    CHECK_TRUE(contains(md, "| 3 | MANUAL |"));
    CHECK_TRUE(contains(json, "{\"value\": 2, \"name\": \"AUTONOMOUS\"}"));
    CHECK_TRUE(contains(json, "{\"name\": \"risk\", \"type\": \"f64\", \"units\": \"\", \"min\": 1e-09, \"max\": 0.49"));
}

// Every RSE_LIMIT is in both exports: a row under its packet in the Markdown,
// a "limits" object on its field in the JSON, with only the sides it bounds.
TEST(GroundDictionaryExport, EveryDisplayLimitIsExported) {
    const std::string md = ground::exportDictionaryMarkdown();
    const std::string json = ground::exportDictionaryJson();
    std::size_t count = 0;
    const ground::TelemetryLimit* limits = ground::telemetryLimits(&count);
    CHECK_TRUE(count > 0);
    auto bound = [](double b) { return ground::hasBound(b) ? ground::formatNumber(b) : std::string("-"); };
    for (std::size_t i = 0; i < count; ++i) {
        const ground::TelemetryLimit& l = limits[i];
        const std::string row = std::string("| ") + l.field + " | " + bound(l.warnLow) + " | " + bound(l.warnHigh) +
                                " | " + bound(l.alarmLow) + " | " + bound(l.alarmHigh) + " | ";
        CHECK_TEXT(contains(md, row), row.c_str());
        // The row is under its own packet's heading: the last "### " before it names the packet.
        const std::size_t at = md.find(row);
        const std::size_t heading = md.rfind("\n### ", at);
        CHECK_TEXT(md.compare(heading + 5, std::string(l.packet).size() + 1, std::string(l.packet) + "\n") == 0, l.packet);
    }
    CHECK_TRUE(contains(md, "| battery_voltage | 25 | - | 24 | - | alarm_low = FAULT_RESPONSE.battery_low_v"));
    CHECK_TRUE(contains(json, "\"name\": \"battery_voltage\", \"type\": \"f32\", \"count\": 1, \"offset\": 0, "
                              "\"units\": \"V\", \"description\": \"battery bus voltage (the battery-low fault compares it)\", "
                              "\"limits\": {\"warn_low\": 25, \"alarm_low\": 24, \"why\": \"alarm_low = "));
    CHECK_TRUE(contains(json, "\"limits\": {\"warn_high\": 0.5, \"alarm_high\": 1, \"why\": \"alarm_high = ESTIMATOR_NOISE.pose_fault_sigma_m"));
    CHECK_TRUE(contains(json, "\"limits\": {\"warn_low\": -2.52, \"warn_high\": 2.52, \"alarm_low\": -2.8, \"alarm_high\": 2.8, "));
    // One "limits" per RSE_LIMIT, none elsewhere.
    std::size_t objects = 0;
    for (std::size_t at = json.find("\"limits\": {"); at != std::string::npos; at = json.find("\"limits\": {", at + 1)) {
        ++objects;
    }
    CHECK_EQUAL(count, objects);
}

TEST(GroundDictionaryExport, JsonIsBalancedAndHasNoTrailingCommas) {
    const std::string json = ground::exportDictionaryJson();
    int depth = 0;
    bool inString = false;
    char lastSignificant = 0;
    for (std::size_t i = 0; i < json.size(); ++i) {
        const char c = json[i];
        if (inString) {
            if (c == '\\') {
                ++i;
            } else if (c == '"') {
                inString = false;
            }
            continue;
        }
        if (c == '"') {
            inString = true;
        } else if (c == '{' || c == '[') {
            ++depth;
        } else if (c == '}' || c == ']') {
            CHECK_TRUE(lastSignificant != ',');
            --depth;
            CHECK_TRUE(depth >= 0);
        }
        if (c != ' ' && c != '\n') {
            lastSignificant = c;
        }
    }
    CHECK_EQUAL(0, depth);
    CHECK_FALSE(inString);
}
