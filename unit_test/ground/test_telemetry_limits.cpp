// The display limits of fsw/cmdtlm/dictionary.def (RSE_LIMIT, expanded by
// ground/telemetry_limits.cpp): every one keeps the .def's rules, the check
// refuses each way of breaking them, and a bound that says it mirrors a table
// field ("alarm_low = FAULT_RESPONSE.battery_low_v") equals that field's
// default value; the warn bounds derived from the health monitor's clear
// levels follow its constants.
#include <algorithm>
#include <cctype>
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/estimator/health_monitor.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "ground/telemetry_limits.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

constexpr double kNone = std::numeric_limits<double>::quiet_NaN();

ground::TelemetryLimit limitOf(const char* packet, const char* field, double warnLow, double warnHigh, double alarmLow,
                               double alarmHigh) {
    return ground::TelemetryLimit{packet, field, warnLow, warnHigh, alarmLow, alarmHigh, "test"};
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The default value of a table field, by the names the sources use
// ("FAULT_RESPONSE", "battery_low_v"); false when there is no such field.
bool defaultTableValue(const std::string& table, const std::string& field, double* value, bool* isFloat32) {
    const tables::TableDesc* desc = tables::findTable(table.c_str());
    if (desc == nullptr) {
        return false;
    }
    for (std::size_t i = 0; i < desc->fieldCount; ++i) {
        if (field == desc->fields[i].name) {
            const std::vector<std::uint8_t> image = test::defaultImage(desc->id);
            *isFloat32 = desc->fields[i].type == tables::FieldType::kF32;
            return image.size() == tables::kTableHeaderSize + desc->payloadSize &&
                   tables::readFieldValue(*desc, image.data() + tables::kTableHeaderSize, desc->payloadSize,
                                          static_cast<std::uint16_t>(i), 0, value);
        }
    }
    return false;
}

double boundNamed(const ground::TelemetryLimit& limit, const std::string& name) {
    if (name == "warn_low") return limit.warnLow;
    if (name == "warn_high") return limit.warnHigh;
    if (name == "alarm_low") return limit.alarmLow;
    if (name == "alarm_high") return limit.alarmHigh;
    FAIL(("no bound named " + name).c_str());
    return kNone;
}

struct TableClaim {
    std::size_t at;     // where in the text
    std::string bound;  // "alarm_low"
    bool negated;       // "= -TABLE.field"
    std::string table;  // "FAULT_RESPONSE"
    std::string field;  // "battery_low_v"
};

// Every "BOUND = TABLE.field" and "BOUND = -TABLE.field" in a why text, in text order
// ("warn_high 0.9 x TABLE.field" is no claim: a derived bound, checked apart).
std::vector<TableClaim> tableClaims(const std::string& why) {
    std::vector<TableClaim> claims;
    for (const char* bound : {"warn_low", "warn_high", "alarm_low", "alarm_high"}) {
        const std::string prefix = std::string(bound) + " = ";
        for (std::size_t at = why.find(prefix); at != std::string::npos; at = why.find(prefix, at + 1)) {
            std::size_t p = at + prefix.size();
            TableClaim c{at, bound, false, "", ""};
            if (p < why.size() && why[p] == '-') {
                c.negated = true;
                ++p;
            }
            while (p < why.size() && (std::isupper(static_cast<unsigned char>(why[p])) || why[p] == '_')) {
                c.table += why[p++];
            }
            if (c.table.empty() || p >= why.size() || why[p] != '.') {
                continue;  // not a table field: a number or words
            }
            ++p;
            while (p < why.size() && (std::islower(static_cast<unsigned char>(why[p])) ||
                                      std::isdigit(static_cast<unsigned char>(why[p])) || why[p] == '_')) {
                c.field += why[p++];
            }
            claims.push_back(c);
        }
    }
    std::sort(claims.begin(), claims.end(), [](const TableClaim& a, const TableClaim& b) { return a.at < b.at; });
    return claims;
}

// Equal as the table stores it: an f32 field's default is a float.
bool sameAsStored(double limit, double tableValue, bool isFloat32) {
    return isFloat32 ? static_cast<float>(limit) == static_cast<float>(tableValue) : limit == tableValue;
}

}  // namespace

TEST_GROUP(TelemetryLimits){};

TEST(TelemetryLimits, EveryLimitNamesANumericFieldAndKeepsTheRules) {
    std::size_t count = 0;
    const ground::TelemetryLimit* limits = ground::telemetryLimits(&count);
    CHECK_TRUE(count >= 6);
    std::set<std::string> seen;
    for (std::size_t i = 0; i < count; ++i) {
        const ground::TelemetryLimit& l = limits[i];
        const std::string name = std::string(l.packet) + "." + l.field;
        STRCMP_EQUAL_TEXT("", ground::checkTelemetryLimit(l).c_str(), name.c_str());
        CHECK_TEXT(seen.insert(name).second, ("two RSE_LIMIT lines for " + name).c_str());
        CHECK_TEXT(std::strlen(l.why) > 20, name.c_str());
        CHECK_TRUE(ground::findTelemetryLimit(l.packet, l.field) == &l);
    }
    CHECK_TRUE(ground::findTelemetryLimit("POWER", "battery_voltage") != nullptr);
    CHECK_TRUE(ground::findTelemetryLimit("HK", "mode") == nullptr);
    CHECK_TRUE(ground::findTelemetryLimit(nullptr, "mode") == nullptr);
}

TEST(TelemetryLimits, TheCheckRefusesEachWayOfBreakingTheRules) {
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("NO_SUCH", "x", kNone, 1, kNone, 2)), "no telemetry packet"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("POWER", "no_such", kNone, 1, kNone, 2)),
                        "packet POWER has no field no_such"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("EVENT", "text", kNone, 1, kNone, 2)), "text field"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("POWER", "battery_voltage", kNone, kNone, kNone, kNone)),
                        "no bound at all"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(
                            limitOf("POWER", "battery_voltage", kNone, std::numeric_limits<double>::infinity(), kNone, kNone)),
                        "warn_high is not finite"));
    // Warn outside alarm, each side; a warn equal to its alarm is outside too.
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("POWER", "battery_voltage", 23, kNone, 24, kNone)),
                        "warn_low 23 is not inside (above) alarm_low 24"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("POWER", "battery_voltage", 24, kNone, 24, kNone)),
                        "not inside"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("DRIVES", "current", kNone, 3, kNone, 2.8)),
                        "warn_high 3 is not inside (below) alarm_high 2.8"));
    // Every low below every high.
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("DRIVES", "current", 2, 1, kNone, kNone)),
                        "warn_low 2 is not below warn_high 1"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("DRIVES", "current", kNone, 1, 1, kNone)),
                        "alarm_low 1 is not below warn_high 1"));
    CHECK_TRUE(contains(ground::checkTelemetryLimit(limitOf("DRIVES", "current", 3, kNone, kNone, 2.8)),
                        "warn_low 3 is not below alarm_high 2.8"));
    // And the good ones pass: one side only, warn only, alarm only.
    STRCMP_EQUAL("", ground::checkTelemetryLimit(limitOf("DRIVES", "current", -1, 1, -2, 2)).c_str());
    STRCMP_EQUAL("", ground::checkTelemetryLimit(limitOf("DRIVES", "current", kNone, 1, kNone, kNone)).c_str());
    STRCMP_EQUAL("", ground::checkTelemetryLimit(limitOf("DRIVES", "current", kNone, kNone, -2, kNone)).c_str());
}

// A parameter is a promise: a limit that says it is a table field's value is.
TEST(TelemetryLimits, BoundsNamedAfterATableFieldEqualItsDefault) {
    std::size_t count = 0;
    const ground::TelemetryLimit* limits = ground::telemetryLimits(&count);
    std::size_t checked = 0;
    std::set<std::string> fields;
    for (std::size_t i = 0; i < count; ++i) {
        const ground::TelemetryLimit& l = limits[i];
        for (const TableClaim& c : tableClaims(l.why)) {
            const std::string what = std::string(l.packet) + "." + l.field + " " + c.bound + " = " +
                                     (c.negated ? "-" : "") + c.table + "." + c.field;
            double value = 0.0;
            bool isFloat32 = false;
            CHECK_TEXT(defaultTableValue(c.table, c.field, &value, &isFloat32), ("no such table field: " + what).c_str());
            const double bound = boundNamed(l, c.bound);
            CHECK_TEXT(ground::hasBound(bound), what.c_str());
            CHECK_TEXT(sameAsStored(bound, c.negated ? -value : value, isFloat32),
                       (what + ": the limit is " + std::to_string(bound) + ", the table's default " +
                        std::to_string(value))
                           .c_str());
            fields.insert(c.table + "." + c.field);
            ++checked;
        }
    }
    // The limits chosen today: both sides of the battery voltage, the bus and
    // drive over-current, the over-temperature and both pose thresholds.
    CHECK_EQUAL(8U, checked);
    CHECK_TRUE(fields.count("FAULT_RESPONSE.battery_low_v") == 1 && fields.count("FAULT_RESPONSE.battery_clear_v") == 1);
    CHECK_TRUE(fields.count("FAULT_RESPONSE.overcurrent_a") == 1 && fields.count("FAULT_RESPONSE.drive_overtemp_c") == 1);
    CHECK_TRUE(fields.count("FAULT_RESPONSE.drive_overcurrent_a") == 1);
    CHECK_TRUE(fields.count("ESTIMATOR_NOISE.pose_fault_sigma_m") == 1 &&
               fields.count("ESTIMATOR_NOISE.pose_clear_sigma_m") == 1);
}

// The claim reader itself: it finds claims, takes the sign, skips numbers.
TEST(TelemetryLimits, TableClaimsAreReadFromTheWhyText) {
    const std::vector<TableClaim> c =
        tableClaims("alarm_high = FAULT_RESPONSE.overcurrent_a, above; warn_high = 0.9 x that; alarm_low = -A_B.c_1 x");
    CHECK_EQUAL(2U, c.size());
    STRCMP_EQUAL("alarm_high", c[0].bound.c_str());
    STRCMP_EQUAL("FAULT_RESPONSE", c[0].table.c_str());
    STRCMP_EQUAL("overcurrent_a", c[0].field.c_str());
    CHECK_FALSE(c[0].negated);
    STRCMP_EQUAL("alarm_low", c[1].bound.c_str());
    CHECK_TRUE(c[1].negated);
    STRCMP_EQUAL("A_B", c[1].table.c_str());
    STRCMP_EQUAL("c_1", c[1].field.c_str());
    double value = 0.0;
    bool isFloat32 = false;
    CHECK_FALSE(defaultTableValue("A_B", "c_1", &value, &isFloat32));
    CHECK_TRUE(defaultTableValue("FAULT_RESPONSE", "overcurrent_a", &value, &isFloat32));
    DOUBLES_EQUAL(20.0, value, 0.0);
    CHECK_TRUE(isFloat32);
}

// The warn bounds at a fault's clear level: 0.9 of an over-current limit,
// 15 degC under the over-temperature limit (fsw/estimator/health_monitor.hpp).
TEST(TelemetryLimits, WarnBoundsAtAFaultsClearLevelFollowTheHealthMonitor) {
    double busLimit = 0.0;
    double driveLimit = 0.0;
    double overtemp = 0.0;
    bool f32 = false;
    CHECK_TRUE(defaultTableValue("FAULT_RESPONSE", "overcurrent_a", &busLimit, &f32));
    CHECK_TRUE(defaultTableValue("FAULT_RESPONSE", "drive_overcurrent_a", &driveLimit, &f32));
    CHECK_TRUE(defaultTableValue("FAULT_RESPONSE", "drive_overtemp_c", &overtemp, &f32));
    const ground::TelemetryLimit* bus = ground::findTelemetryLimit("POWER", "battery_current");
    const ground::TelemetryLimit* drive = ground::findTelemetryLimit("DRIVES", "current");
    const ground::TelemetryLimit* temperature = ground::findTelemetryLimit("POWER", "motor_temperature");
    CHECK_TRUE(bus != nullptr && drive != nullptr && temperature != nullptr);
    const double fraction = estimator::kOvercurrentClearFraction;
    DOUBLES_EQUAL(fraction * busLimit, bus->warnHigh, 1e-6);
    DOUBLES_EQUAL(fraction * driveLimit, drive->warnHigh, 1e-6);
    DOUBLES_EQUAL(-fraction * driveLimit, drive->warnLow, 1e-6);
    DOUBLES_EQUAL(overtemp - estimator::kOvertempClearMarginC, temperature->warnHigh, 0.0);
}

// How the display and `rse-ground watch` judge a value: strictly beyond a bound.
TEST(TelemetryLimits, LevelsAreStrictlyBeyondTheBounds) {
    const ground::TelemetryLimit* v = ground::findTelemetryLimit("POWER", "battery_voltage");
    CHECK_TRUE(v != nullptr);
    CHECK_TRUE(ground::LimitLevel::kNominal == ground::limitLevel(*v, 28.0));
    CHECK_TRUE(ground::LimitLevel::kNominal == ground::limitLevel(*v, v->warnLow));
    CHECK_TRUE(ground::LimitLevel::kWarn == ground::limitLevel(*v, 24.5));
    CHECK_TRUE(ground::LimitLevel::kWarn == ground::limitLevel(*v, v->alarmLow));
    CHECK_TRUE(ground::LimitLevel::kAlarm == ground::limitLevel(*v, 23.9));
    CHECK_TRUE(ground::LimitLevel::kNominal == ground::limitLevel(*v, 1e6));  // no high bound
    const ground::TelemetryLimit* c = ground::findTelemetryLimit("DRIVES", "current");
    CHECK_TRUE(c != nullptr);
    CHECK_TRUE(ground::LimitLevel::kAlarm == ground::limitLevel(*c, -3.0));
    CHECK_TRUE(ground::LimitLevel::kWarn == ground::limitLevel(*c, 2.6));
    CHECK_TRUE(ground::LimitLevel::kNominal == ground::limitLevel(*c, -1.0));
}
