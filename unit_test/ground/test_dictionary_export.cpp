// docs/dictionary.md and docs/dictionary.json are exactly what the exporter
// makes from the dictionary now (tests run from the repository root), and the
// exports carry every command, argument, packet, field, reason code and event
// data layout (each naming its flight events).
#include <fstream>
#include <iterator>
#include <string>

#include "fsw/cmdtlm/cmdtlm_events.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/estimator/drive_mode_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
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

// Every event data layout of the dictionary names the flight constants of its
// events (the owners' suites check their own at compile time; this one keeps
// the list whole: a layout added without its events here fails), and both
// exports list every layout with every value.
TEST(GroundDictionaryExport, EveryEventDataNamesItsFlightEventsAndIsExported) {
    struct Expected {
        const char* name;
        core::EventId first;
        core::EventId last;
    };
    namespace dev = deliberative::events;
    namespace hev = habitual::events;
    namespace eev = estimator::events;
    namespace fev = fault_protection::events;
    const Expected expected[] = {
        {"GOALS_COMMANDED", plan_executive::events::kGoalsCommanded, plan_executive::events::kGoalsCommanded},
        {"SAFED_ON_REQUEST", cmdtlm::events::kSafedOnRequest, cmdtlm::events::kSafedOnRequest},
        {"DRIVE_MODE_DECLARED", eev::kDriveModeDeclaredNominal, eev::kDriveModeDeclaredUnknown},
        {"PATH_BLOCKED", hev::kPathBlocked, hev::kPathBlocked},
        {"MINOR_ANOMALY", hev::kMinorAnomaly, hev::kMinorAnomaly},
        {"HABITUAL_FAIL_UP", hev::kFailUp, hev::kFailUp},
        {"LEG_ACHIEVED", hev::kLegAchieved, hev::kLegAchieved},
        {"HAZARD_REMEMBERED", hev::kHazardRemembered, hev::kHazardRemembered},
        {"LEG_SENT", dev::kLegSent, dev::kLegSent},
        {"LEG_REACHED", dev::kLegAchieved, dev::kLegAchieved},
        {"BOUND_RELAXED", dev::kBoundRelaxed, dev::kBoundRelaxed},
        {"CALL_HOME", dev::kCallHome, dev::kCallHome},
        {"FAULT_GAVE_UP", fev::kGaveUp, fev::kGaveUp},
        {"FAULT_CALL_HOME", fev::kCallHome, fev::kCallHome},
        {"FAILED_DRIVE_MODEL", dev::kFailedDriveModel, dev::kFailedDriveModel},
    };
    std::size_t count = 0;
    const cmdtlm::EventDataDesc* layouts = cmdtlm::eventDataDescs(&count);
    LONGS_EQUAL(sizeof expected / sizeof expected[0], count);
    const std::string md = ground::exportDictionaryMarkdown();
    const std::string json = ground::exportDictionaryJson();
    for (std::size_t i = 0; i < count; ++i) {
        STRCMP_EQUAL(expected[i].name, layouts[i].name);
        LONGS_EQUAL(expected[i].first, layouts[i].firstId);
        LONGS_EQUAL(expected[i].last, layouts[i].lastId);
        CHECK(layouts[i].valueCount >= 1 && layouts[i].valueCount <= core::kEventDataValues);
        CHECK_TRUE(cmdtlm::findEventData(layouts[i].firstId) == &layouts[i]);
        CHECK_TRUE(md.find("### " + std::string(layouts[i].name) + "\n") != std::string::npos);
        CHECK_TRUE(json.find("\"name\": \"" + std::string(layouts[i].name) + "\"") != std::string::npos);
        for (std::size_t v = 0; v < layouts[i].valueCount; ++v) {
            CHECK_TRUE(md.find("| " + std::to_string(v) + " | " + layouts[i].values[v].name + " |") != std::string::npos);
        }
    }
    CHECK_TRUE(cmdtlm::findEventData(dev::kPlanFound) == nullptr);  // an event without numbers
    CHECK_TRUE(json.find("\"event_data\": [") != std::string::npos);
    const cmdtlm::TelemetryDesc* packet = cmdtlm::findTelemetry("EVENT_DATA");
    CHECK_TRUE(packet != nullptr);
    LONGS_EQUAL(0x005, packet->apid);
}
