// The display dictionary and the datum (ground/mission_control/
// openmct_dictionary.hpp, telemetry_datum.hpp) against the flight dictionary's
// own descriptor tables: every telemetry packet and every field (array fields
// per element) with its type and units, so a packet or field added to
// fsw/cmdtlm/dictionary.def that the display would miss fails here; and every
// packet's datum, from bytes the flight encodes, has exactly the keys its
// dictionary entry lists, with exact values.
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "ground/mission_control/openmct_dictionary.hpp"
#include "ground/telemetry_limits.hpp"
#include "ground/mission_control/telemetry_datum.hpp"
#include "ground/telemetry_decoder.hpp"
#include "unit_test/ground/mission_control/mc_test_support.hpp"

#include "CppUTest/TestHarness.h"

namespace cmdtlm = rse::cmdtlm;
using rse::ground::decodeTelemetry;
using rse::ground::DecodedPacket;
using rse::ground::mission_control::datumFromPacket;
using rse::ground::mission_control::dictionaryLimits;
using rse::ground::mission_control::displayDictionary;
using rse::ground::mission_control::FieldLimits;
using rse::ground::mission_control::Json;
using rse::ground::mission_control::jsonText;
using rse::test::mc::packetOf;
using rse::test::mc::patternPacket;

namespace {

const cmdtlm::TelemetryDesc* flightPackets(std::size_t* count) { return cmdtlm::telemetryDescs(count); }

const Json* packetEntry(const Json& dictionary, const std::string& name) {
    for (const Json& p : dictionary["packets"]) {
        if (p["name"] == name) {
            return &p;
        }
    }
    return nullptr;
}

std::size_t expectedKeys(const cmdtlm::FieldDesc& f) {
    return f.type == cmdtlm::FieldType::chr ? 1 : f.count;
}

}  // namespace

TEST_GROUP(OpenMctDictionary){};

TEST(OpenMctDictionary, ListsEveryPacketAndFieldOfTheFlightDictionary) {
    const Json dictionary = displayDictionary();
    STRCMP_EQUAL("RSE rover", dictionary["name"].get<std::string>().c_str());
    std::size_t count = 0;
    const cmdtlm::TelemetryDesc* packets = flightPackets(&count);
    CHECK_TRUE(count >= 10);
    CHECK_EQUAL(count, dictionary["packets"].size());
    for (std::size_t p = 0; p < count; ++p) {
        const cmdtlm::TelemetryDesc& desc = packets[p];
        const Json& entry = dictionary["packets"][p];  // in the flight dictionary's order
        STRCMP_EQUAL(desc.name, entry["name"].get<std::string>().c_str());
        CHECK_EQUAL(desc.apid, entry["apid"].get<unsigned>());
        STRCMP_EQUAL(desc.description, entry["description"].get<std::string>().c_str());
        const Json& fields = entry["fields"];
        std::size_t at = 0;
        for (std::size_t f = 0; f < desc.fieldCount; ++f) {
            const cmdtlm::FieldDesc& field = desc.fields[f];
            for (std::size_t e = 0; e < expectedKeys(field); ++e, ++at) {
                const std::string key = expectedKeys(field) == 1 ? std::string(field.name)
                                                                 : std::string(field.name) + "." + std::to_string(e);
                const std::string where = std::string(desc.name) + "." + key;
                CHECK_TEXT(at < fields.size(), where.c_str());
                const Json& entryField = fields[at];
                STRCMP_EQUAL_TEXT(key.c_str(), entryField["key"].get<std::string>().c_str(), where.c_str());
                STRCMP_EQUAL_TEXT(key.c_str(), entryField["name"].get<std::string>().c_str(), where.c_str());
                STRCMP_EQUAL_TEXT(cmdtlm::toString(field.type), entryField["type"].get<std::string>().c_str(),
                                  where.c_str());
                STRCMP_EQUAL_TEXT(field.units, entryField["units"].get<std::string>().c_str(), where.c_str());
                STRCMP_EQUAL_TEXT(field.description, entryField["description"].get<std::string>().c_str(),
                                  where.c_str());
                // Limits exactly where an RSE_LIMIT bounds the field (their values: LimitsAreListedWhereGiven).
                CHECK_TEXT(entryField.contains("limits") ==
                               (rse::ground::findTelemetryLimit(desc.name, field.name) != nullptr),
                           where.c_str());
            }
        }
        CHECK_EQUAL_TEXT(at, fields.size(), desc.name);
    }
}

TEST(OpenMctDictionary, ExpandsArraysAndKeepsUnitsOfNamedFields) {
    const Json dictionary = displayDictionary();
    const Json* drives = packetEntry(dictionary, "DRIVES");
    CHECK_TRUE(drives != nullptr);
    std::set<std::string> keys;
    for (const Json& f : (*drives)["fields"]) {
        keys.insert(f["key"].get<std::string>());
        if (f["key"] == "current.5") {
            STRCMP_EQUAL("A", f["units"].get<std::string>().c_str());
            STRCMP_EQUAL("f32", f["type"].get<std::string>().c_str());
        }
    }
    for (int i = 0; i < 6; ++i) {
        CHECK_TRUE(keys.count("current." + std::to_string(i)) == 1);
    }
    CHECK_TRUE(keys.count("current") == 0);
    CHECK_TRUE(keys.count("current.6") == 0);
    const Json* event = packetEntry(dictionary, "EVENT");
    CHECK_TRUE(event != nullptr);
    bool text = false;
    for (const Json& f : (*event)["fields"]) {
        if (f["key"] == "text") {
            text = true;
            STRCMP_EQUAL("chr", f["type"].get<std::string>().c_str());
        }
    }
    CHECK_TRUE(text);  // one text, not 96 characters
}

TEST(OpenMctDictionary, NoFieldKeyCollidesWithUtcMetOrAnother) {
    const Json dictionary = displayDictionary();
    for (const Json& packet : dictionary["packets"]) {
        std::set<std::string> keys{"utc", "met"};
        for (const Json& f : packet["fields"]) {
            const std::string key = f["key"].get<std::string>();
            CHECK_TEXT(keys.insert(key).second, (packet["name"].get<std::string>() + "." + key).c_str());
        }
    }
}

TEST(OpenMctDictionary, LimitsAreListedWhereGiven) {
    std::size_t count = 0;
    const cmdtlm::TelemetryDesc* packets = flightPackets(&count);
    // The flight dictionary's own: exactly its RSE_LIMIT lines, every side as written.
    std::size_t limited = 0;
    for (std::size_t p = 0; p < count; ++p) {
        for (std::size_t f = 0; f < packets[p].fieldCount; ++f) {
            const std::optional<FieldLimits> got = dictionaryLimits(packets[p], packets[p].fields[f]);
            const rse::ground::TelemetryLimit* want =
                rse::ground::findTelemetryLimit(packets[p].name, packets[p].fields[f].name);
            CHECK_EQUAL(want != nullptr, got.has_value());
            if (want == nullptr) {
                continue;
            }
            ++limited;
            const auto same = [](double bound, const std::optional<double>& side) {
                return rse::ground::hasBound(bound) ? side.has_value() && *side == bound : !side.has_value();
            };
            CHECK(same(want->warnLow, got->warnLow));
            CHECK(same(want->warnHigh, got->warnHigh));
            CHECK(same(want->alarmLow, got->alarmLow));
            CHECK(same(want->alarmHigh, got->alarmHigh));
        }
    }
    std::size_t declared = 0;
    (void)rse::ground::telemetryLimits(&declared);
    CHECK(declared > 0);
    LONGS_EQUAL(declared, limited);
    // A lookup with limits on DRIVES.current (all four) and HK.mode (a high alarm only).
    const auto limits = [](const cmdtlm::TelemetryDesc& packet, const cmdtlm::FieldDesc& field) -> std::optional<FieldLimits> {
        if (std::string(packet.name) == "DRIVES" && std::string(field.name) == "current") {
            return FieldLimits{-4.0, 4.0, -6.0, 6.5};
        }
        if (std::string(packet.name) == "HK" && std::string(field.name) == "mode") {
            FieldLimits high;
            high.alarmHigh = 3.0;
            return high;
        }
        return std::nullopt;
    };
    const Json dictionary = displayDictionary(limits);
    std::size_t withLimits = 0;
    for (const Json& packet : dictionary["packets"]) {
        for (const Json& f : packet["fields"]) {
            if (!f.contains("limits")) {
                continue;
            }
            ++withLimits;
            const Json& l = f["limits"];
            if (packet["name"] == "DRIVES") {
                CHECK_EQUAL(0U, f["key"].get<std::string>().rfind("current.", 0));
                DOUBLES_EQUAL(-4.0, l["warn_low"].get<double>(), 0.0);
                DOUBLES_EQUAL(4.0, l["warn_high"].get<double>(), 0.0);
                DOUBLES_EQUAL(-6.0, l["alarm_low"].get<double>(), 0.0);
                DOUBLES_EQUAL(6.5, l["alarm_high"].get<double>(), 0.0);
            } else {
                STRCMP_EQUAL("mode", f["key"].get<std::string>().c_str());
                CHECK_EQUAL(1U, l.size());
                DOUBLES_EQUAL(3.0, l["alarm_high"].get<double>(), 0.0);
            }
        }
    }
    CHECK_EQUAL(7U, withLimits);  // current.0 .. current.5 and mode
}

TEST_GROUP(TelemetryDatum){};

TEST(TelemetryDatum, EveryPacketsDatumHasExactlyItsDictionaryKeys) {
    const Json dictionary = displayDictionary();
    std::size_t count = 0;
    const cmdtlm::TelemetryDesc* packets = flightPackets(&count);
    for (std::size_t p = 0; p < count; ++p) {
        const DecodedPacket decoded = decodeTelemetry(patternPacket(packets[p], static_cast<unsigned>(p)));
        CHECK_TEXT(decoded.ok, decoded.error.c_str());
        const Json datum = datumFromPacket(decoded, 1700000000123);
        std::set<std::string> datumKeys;
        for (auto it = datum.begin(); it != datum.end(); ++it) {
            datumKeys.insert(it.key());
        }
        std::set<std::string> expected{"utc", "met"};
        for (const Json& f : dictionary["packets"][p]["fields"]) {
            expected.insert(f["key"].get<std::string>());
        }
        CHECK_TEXT(datumKeys == expected, packets[p].name);
        CHECK_EQUAL(1700000000123, datum["utc"].get<std::int64_t>());
        // Serialises whatever the bytes (NaN patterns, text that is not UTF-8).
        CHECK_TRUE(!jsonText(datum).empty());
    }
}

TEST(TelemetryDatum, ValuesAreExact) {
    cmdtlm::ROVER_STATE_Tlm state{};
    state.estimate_valid = 1;
    state.x = 12.345678901234;
    state.y = -3.5;
    for (int i = 0; i < 9; ++i) {
        state.covariance[i] = 0.1f * static_cast<float>(i);
    }
    state.speed = std::numeric_limits<float>::quiet_NaN();
    state.fixes_accepted = 4000000000U;
    const DecodedPacket decoded = decodeTelemetry(packetOf(state, 3, 2500 * 1000000LL));  // MET 2.5 s
    CHECK_TRUE(decoded.ok);
    const Json datum = datumFromPacket(decoded, 42);
    DOUBLES_EQUAL(2.5, datum["met"].get<double>(), 0.0);
    DOUBLES_EQUAL(12.345678901234, datum["x"].get<double>(), 0.0);  // f64 exact
    DOUBLES_EQUAL(-3.5, datum["y"].get<double>(), 0.0);
    DOUBLES_EQUAL(0.3, datum["covariance.3"].get<double>(), 0.0);  // f32 as its shortest decimal
    CHECK_TRUE(datum["speed"].is_null());                          // NaN: JSON has none
    CHECK_EQUAL(4000000000U, datum["fixes_accepted"].get<std::uint64_t>());
    CHECK_EQUAL(1U, datum["estimate_valid"].get<unsigned>());

    cmdtlm::HK_Tlm hk{};
    hk.frames_run = (1ULL << 62) + 1;  // beyond a double's 53 bits: exact as an integer
    CHECK_TRUE(jsonText(datumFromPacket(decodeTelemetry(packetOf(hk)), 0)).find("\"frames_run\":4611686018427387905") !=
               std::string::npos);

    cmdtlm::CMD_ACK_Tlm ack{};
    ack.detail = -1;
    CHECK_EQUAL(-1, datumFromPacket(decodeTelemetry(packetOf(ack)), 0)["detail"].get<int>());

    cmdtlm::EVENT_Tlm event{};
    const char text[] = "hazard seen \xff";  // a byte that is not UTF-8
    for (std::size_t i = 0; i + 1 < sizeof text; ++i) {
        event.text[i] = text[i];
    }
    const Json eventDatum = datumFromPacket(decodeTelemetry(packetOf(event)), 0);
    CHECK_TRUE(eventDatum["text"].is_string());
    CHECK_TRUE(jsonText(eventDatum).find("\"text\":\"hazard seen \xEF\xBF\xBD\"") != std::string::npos);  // U+FFFD
}
