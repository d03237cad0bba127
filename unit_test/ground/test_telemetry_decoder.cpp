// The generic telemetry decoder against the flight's generated encoders: every
// packet of the dictionary, filled through its generated struct, must decode to
// the same values by the descriptors alone (the "cannot drift" check), and
// malformed input is described, never a crash.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/byte_codec.hpp"
#include "ground/telemetry_decoder.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::test::telemetryPacket;

namespace {

// Every byte of the struct (padding too) from a pattern: distinct values in
// every field, floats included (compared as bits, so NaN patterns are fine).
template <typename T>
void fillPattern(T* t, unsigned seed) {
    auto* bytes = reinterpret_cast<unsigned char*>(t);
    for (std::size_t i = 0; i < sizeof(T); ++i) {
        bytes[i] = static_cast<unsigned char>(seed * 13 + i * 31 + (i >> 4) + 1);
    }
}

template <typename T>
std::uint64_t bitsOf(const T& v) {
    static_assert(sizeof(T) <= 8, "scalar");
    if constexpr (sizeof(T) == 1) {
        std::uint8_t u = 0;
        std::memcpy(&u, &v, 1);
        return u;
    } else if constexpr (sizeof(T) == 2) {
        std::uint16_t u = 0;
        std::memcpy(&u, &v, 2);
        return u;
    } else if constexpr (sizeof(T) == 4) {
        std::uint32_t u = 0;
        std::memcpy(&u, &v, 4);
        return u;
    } else {
        std::uint64_t u = 0;
        std::memcpy(&u, &v, 8);
        return u;
    }
}

void checkElement(const ground::DecodedField& f, std::size_t i, std::uint64_t expected, const std::string& what) {
    CHECK_TEXT(i < f.raw.size(), what.c_str());
    CHECK_EQUAL_TEXT(expected, f.raw[i], what.c_str());
}

template <typename T>
void compareField(const ground::DecodedPacket& p, const char* name, const T& value) {
    const ground::DecodedField* f = p.field(name);
    CHECK_TEXT(f != nullptr, name);
    CHECK_EQUAL_TEXT(1U, f->raw.size(), name);
    checkElement(*f, 0, bitsOf(value), std::string(p.name()) + "." + name);
    if constexpr (std::is_integral_v<T> && sizeof(T) <= 4) {
        DOUBLES_EQUAL(static_cast<double>(value), f->values[0], 0.0);
    }
}

template <typename T, std::size_t N>
void compareField(const ground::DecodedPacket& p, const char* name, const T (&values)[N]) {
    const ground::DecodedField* f = p.field(name);
    CHECK_TEXT(f != nullptr, name);
    CHECK_EQUAL_TEXT(N, f->raw.size(), name);
    for (std::size_t i = 0; i < N; ++i) {
        checkElement(*f, i, bitsOf(values[i]), std::string(p.name()) + "." + name + "[" + std::to_string(i) + "]");
    }
}

template <typename T>
ground::DecodedPacket roundTrip(const T& tlm, std::uint16_t sequence, core::TimeNs time) {
    const std::vector<std::uint8_t> packet = telemetryPacket(tlm, sequence, time);
    CHECK_TRUE(!packet.empty());
    ground::DecodedPacket p = ground::decodeTelemetry(packet);
    CHECK_TEXT(p.ok, p.error.c_str());
    CHECK_EQUAL(T::kApid, p.apid);
    CHECK_EQUAL(sequence, p.sequenceCount);
    CHECK_TRUE(p.desc == cmdtlm::findTelemetry(T::kApid));
    CHECK_EQUAL(packet.size() - cmdtlm::kTelemetryHeaderSize, static_cast<std::size_t>(p.desc->payloadSize));
    DOUBLES_EQUAL(static_cast<double>(time) / 1e9, p.met, 1.0 / 65536.0);
    return p;
}

std::size_t g_packetsChecked = 0;

}  // namespace

TEST_GROUP(GroundDictionaryDrift){};

// One test per telemetry packet of the dictionary, expanded from the same .def:
// the generated struct and encodeTelemetry against the descriptor-driven decoder.
#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text)                                              \
    TEST(GroundDictionaryDrift, NAME) {                                        \
        cmdtlm::NAME##_Tlm t;                                                  \
        fillPattern(&t, apid);                                                 \
        const ground::DecodedPacket p = roundTrip(t, 0x2A5, 12345678901LL);    \
        STRCMP_EQUAL(#NAME, p.name());                                         \
        std::size_t fields = 0;
#define RSE_FIELD(type, name, count, units, text) \
    compareField(p, #name, t.name);               \
    ++fields;
#define RSE_TLM_END(NAME)                \
    CHECK_EQUAL(p.fields.size(), fields); \
    ++g_packetsChecked;                  \
    }
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_CMD
#undef RSE_ARG
#undef RSE_BLOB
#undef RSE_CMD_END
#undef RSE_TLM
#undef RSE_FIELD
#undef RSE_TLM_END
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END

TEST(GroundDictionaryDrift, EveryDescriptorHasAPacketTestAndAGeneratedStruct) {
    std::size_t expanded = 0;
#define RSE_CMD(NAME, apid, fc, modes, text)
#define RSE_ARG(type, name, units, lo, hi, text)
#define RSE_BLOB(name, max, text)
#define RSE_CMD_END(NAME)
#define RSE_TLM(NAME, apid, text) \
    ++expanded;                   \
    CHECK_EQUAL(cmdtlm::k##NAME##_TlmSize, static_cast<std::size_t>(cmdtlm::findTelemetry(#NAME)->payloadSize));
#define RSE_FIELD(type, name, count, units, text)
#define RSE_TLM_END(NAME)
#define RSE_LIMIT(PACKET, field, warn_low, warn_high, alarm_low, alarm_high, why)
#define RSE_EVENT_DATA(first_id, last_id, NAME, text)
#define RSE_EVENT_VALUE(name, units, text)
#define RSE_EVENT_DATA_END(NAME)
#include "fsw/cmdtlm/dictionary.def"
#undef RSE_CMD
#undef RSE_ARG
#undef RSE_BLOB
#undef RSE_CMD_END
#undef RSE_TLM
#undef RSE_FIELD
#undef RSE_TLM_END
#undef RSE_LIMIT
#undef RSE_EVENT_DATA
#undef RSE_EVENT_VALUE
#undef RSE_EVENT_DATA_END
    std::size_t count = 0;
    (void)cmdtlm::telemetryDescs(&count);
    CHECK_EQUAL(count, expanded);
    CHECK_TRUE(count >= 9);
}

TEST_GROUP(GroundTelemetryDecoder){};

TEST(GroundTelemetryDecoder, HousekeepingValuesAndRendering) {
    cmdtlm::HK_Tlm hk{};
    hk.utc_at_met_zero = 1.7e9;
    hk.mode = 2;
    hk.estop = 1;
    hk.cmd_accepted = 42;
    hk.cmd_rejected = 7;
    for (std::size_t i = 0; i < 16; ++i) {
        hk.cmd_rejected_by_reason[i] = static_cast<std::uint32_t>(i * 3);
    }
    hk.frames_run = 0x123456789ABCULL;
    hk.events_by_severity[4] = 9;
    const ground::DecodedPacket p = roundTrip(hk, 12, 1500 * core::kNsPerMs);
    DOUBLES_EQUAL(1.7e9, *p.value("utc_at_met_zero"), 0.0);
    DOUBLES_EQUAL(2, *p.value("mode"), 0.0);
    DOUBLES_EQUAL(42, *p.value("cmd_accepted"), 0.0);
    DOUBLES_EQUAL(45, *p.value("cmd_rejected_by_reason", 15), 0.0);
    DOUBLES_EQUAL(9, *p.value("events_by_severity", 4), 0.0);
    CHECK_FALSE(p.value("events_by_severity", 5).has_value());
    CHECK_FALSE(p.value("no_such_field").has_value());
    DOUBLES_EQUAL(1.5, p.met, 0.0);
    const std::string line = ground::renderPacket(p);
    CHECK_TRUE(line.rfind("HK ", 0) == 0);
    CHECK_TRUE(line.find("apid=0x001 seq=12 met=1.500") != std::string::npos);
    CHECK_TRUE(line.find(" mode=2 estop=1 ") != std::string::npos);
    CHECK_TRUE(line.find("cmd_rejected_by_reason=[0,3,6,9,") != std::string::npos);
    CHECK_TRUE(line.find("frames_run=20015998343868") != std::string::npos);
    CHECK_TRUE(line.find("utc_at_met_zero=1700000000") != std::string::npos);
}

TEST(GroundTelemetryDecoder, CommandAckRendersTheVerdict) {
    cmdtlm::CMD_ACK_Tlm ack{};
    ack.apid = 0x181;
    ack.function_code = 0;
    ack.ccsds_sequence = 17;
    ack.key_id = 1;
    ack.auth_sequence = 4000000000U;
    ack.reason = static_cast<std::uint8_t>(cmdtlm::CommandReject::kWrongMode);
    ack.detail = 3;
    ack.accepted = 5;
    ack.rejected = 6;
    const ground::DecodedPacket p = roundTrip(ack, 3, 0);
    DOUBLES_EQUAL(4000000000.0, *p.value("auth_sequence"), 0.0);
    DOUBLES_EQUAL(3, *p.value("detail"), 0.0);
    STRCMP_EQUAL("GOTO (0x181/0, auth seq 4000000000) rejected: wrong_mode (detail 3: rover in MANUAL)",
                 ground::describeAck(p).c_str());
    CHECK_TRUE(ground::renderPacket(p).find("=> GOTO (0x181/0") != std::string::npos);

    ack.reason = 0;
    ack.detail = -1;
    STRCMP_EQUAL("GOTO (0x181/0, auth seq 4000000000) accepted",
                 ground::describeAck(roundTrip(ack, 4, 0)).c_str());
    ack.reason = static_cast<std::uint8_t>(cmdtlm::CommandReject::kArgumentOutOfRange);
    ack.detail = 2;
    STRCMP_EQUAL("GOTO (0x181/0, auth seq 4000000000) rejected: argument_out_of_range (detail 2: argument risk)",
                 ground::describeAck(roundTrip(ack, 5, 0)).c_str());
    // EXEC_SET_TASK's refusals are named (fsw/cmdtlm/task_command_refusal.hpp).
    ack.apid = 0x184;
    ack.reason = static_cast<std::uint8_t>(cmdtlm::CommandReject::kExecutionFailed);
    ack.detail = 2;
    STRCMP_EQUAL("EXEC_SET_TASK (0x184/0, auth seq 4000000000) rejected: execution_failed (detail 2: command "
                 "ingest: nothing could enable it again)",
                 ground::describeAck(roundTrip(ack, 5, 0)).c_str());
    ack.detail = 9;  // not a refusal code: the number only
    STRCMP_EQUAL("EXEC_SET_TASK (0x184/0, auth seq 4000000000) rejected: execution_failed (detail 9)",
                 ground::describeAck(roundTrip(ack, 5, 0)).c_str());
    ack.apid = 0x181;
    ack.reason = static_cast<std::uint8_t>(cmdtlm::CommandReject::kArgumentOutOfRange);
    ack.detail = -7;  // negative details decode signed
    DOUBLES_EQUAL(-7, *roundTrip(ack, 5, 0).value("detail"), 0.0);
    CHECK_TRUE(ground::renderPacket(roundTrip(ack, 5, 0)).find(" detail=-7 ") != std::string::npos);
}

TEST(GroundTelemetryDecoder, EventRendersAsEvtIdSeverityText) {
    cmdtlm::EVENT_Tlm e{};
    e.event_sequence = 99;
    e.event_time = 12.25;
    e.event_id = 512;
    e.severity = 2;
    std::strncpy(e.text, "app: mode STANDBY -> MANUAL", sizeof e.text);
    const ground::DecodedPacket p = roundTrip(e, 8, 13 * core::kNsPerSec);
    STRCMP_EQUAL("app: mode STANDBY -> MANUAL", p.field("text")->text.c_str());
    const std::string line = ground::renderPacket(p);
    CHECK_TRUE(line.find("EVT 512 WARN app: mode STANDBY -> MANUAL") != std::string::npos);
    CHECK_TRUE(line.find("event_sequence=99") != std::string::npos);
    STRCMP_EQUAL("CRIT", ground::severityName(4).c_str());
    STRCMP_EQUAL("SEV9", ground::severityName(9).c_str());
}

// EVENT_DATA: the event's numbers by the names the dictionary gives that
// event id's values; an id with no event data known still shows them by index.
TEST(GroundTelemetryDecoder, EventDataRendersTheValuesByName) {
    cmdtlm::event_data::LEG_SENT sent;
    sent.leg_id = 4;
    sent.index = 3;
    sent.count = 6;
    sent.x = 17.625;
    sent.power_bound = 324.25;
    const core::EventData data = sent.pack();
    cmdtlm::EVENT_DATA_Tlm d{};
    d.event_sequence = 147;
    d.event_id = 905;
    d.value_count = data.count;
    for (std::size_t i = 0; i < data.count; ++i) {
        d.value[i] = data.values[i];
    }
    const std::string line = ground::renderPacket(roundTrip(d, 3, 0));
    CHECK_TRUE(line.rfind("EVENT_DATA", 0) == 0);
    CHECK_TRUE(line.find(" event 905 LEG_SENT leg_id=4 index=3 count=6 x=17.625 ") != std::string::npos);
    CHECK_TRUE(line.find(" power_bound=324.25") != std::string::npos);
    CHECK_TRUE(line.find("event_sequence=147") != std::string::npos);
    d.event_id = 1;  // no event data of that id
    d.value_count = 1;
    const std::string unknown = ground::renderPacket(roundTrip(d, 4, 0));
    CHECK_TRUE(unknown.find(" event 1 (no event data known) value[0]=4 ") != std::string::npos);
}

TEST(GroundTelemetryDecoder, NonPrintableTextIsEscaped) {
    cmdtlm::EVENT_Tlm e{};
    e.text[0] = 'a';
    e.text[1] = '\x01';
    e.text[2] = '\n';
    e.text[3] = 'b';
    const std::string line = ground::renderPacket(roundTrip(e, 1, 0));
    CHECK_TRUE(line.find("a\\x01\\x0Ab") != std::string::npos);
}

TEST(GroundTelemetryDecoder, ShortPacketIsDescribed) {
    const std::uint8_t bytes[] = {0x08, 0x01, 0xC0};
    const ground::DecodedPacket p = ground::decodeTelemetry(bytes, sizeof bytes);
    CHECK_FALSE(p.ok);
    STRCMP_EQUAL("length 3 is shorter than the 12-byte telemetry header", p.error.c_str());
    CHECK_TRUE(ground::renderPacket(p).rfind("MALFORMED", 0) == 0);
    CHECK_FALSE(ground::decodeTelemetry(nullptr, 0).ok);
}

TEST(GroundTelemetryDecoder, WrongLengthFieldIsDescribed) {
    cmdtlm::HK_Tlm hk{};
    std::vector<std::uint8_t> packet = telemetryPacket(hk);
    packet.push_back(0);  // one byte more than the length field says
    ground::DecodedPacket p = ground::decodeTelemetry(packet);
    CHECK_FALSE(p.ok);
    CHECK_TRUE(p.error.find("length field says") != std::string::npos);
    packet.resize(packet.size() - 2);
    CHECK_FALSE(ground::decodeTelemetry(packet).ok);
}

TEST(GroundTelemetryDecoder, PayloadSizeOtherThanTheDictionarysIsDescribed) {
    std::uint8_t payload[10] = {};
    std::uint8_t packet[64];
    const std::size_t n =
        cmdtlm::buildTelemetryPacket(cmdtlm::HK_Tlm::kApid, 0, 0, payload, sizeof payload, packet, sizeof packet);
    const ground::DecodedPacket p = ground::decodeTelemetry(packet, n);
    CHECK_FALSE(p.ok);
    CHECK_TRUE(p.error.find("HK payload is 10 bytes, the dictionary says") != std::string::npos);
}

TEST(GroundTelemetryDecoder, UnknownApidIsShownWithItsLength) {
    std::uint8_t payload[4] = {1, 2, 3, 4};
    std::uint8_t packet[64];
    const std::size_t n = cmdtlm::buildTelemetryPacket(0x07F, 3, 0, payload, sizeof payload, packet, sizeof packet);
    const ground::DecodedPacket p = ground::decodeTelemetry(packet, n);
    CHECK_FALSE(p.ok);
    STRCMP_EQUAL("unknown APID 0x07F", p.error.c_str());
    const std::string line = ground::renderPacket(p);
    CHECK_TRUE(line.rfind("UNKNOWN", 0) == 0);
    CHECK_TRUE(line.find("apid=0x07F seq=3 length 16") != std::string::npos);
}

TEST(GroundTelemetryDecoder, CommandPacketsAreNotTelemetry) {
    cmdtlm::HK_Tlm hk{};
    std::vector<std::uint8_t> packet = telemetryPacket(hk);
    packet[0] |= 0x10;  // type bit: command
    const ground::DecodedPacket p = ground::decodeTelemetry(packet);
    CHECK_FALSE(p.ok);
    CHECK_TRUE(p.error.find("bad primary header") != std::string::npos);
}

TEST(GroundTelemetryDecoder, RandomBytesNeverCrashTheDecoderOrTheRenderer) {
    std::mt19937 random(1234);
    std::size_t decoded = 0;
    for (int i = 0; i < 3000; ++i) {
        std::vector<std::uint8_t> bytes(random() % 600);
        for (auto& b : bytes) {
            b = static_cast<std::uint8_t>(random());
        }
        if (i % 2 == 0 && bytes.size() >= 12) {
            // Half of them with a plausible header, so the deeper checks run.
            std::size_t count = 0;
            const cmdtlm::TelemetryDesc* all = cmdtlm::telemetryDescs(&count);
            const cmdtlm::TelemetryDesc& t = all[random() % count];
            bytes.resize(12 + t.payloadSize + (i % 4 == 0 ? 0 : random() % 3));
            bytes[0] = static_cast<std::uint8_t>(0x08 | (t.apid >> 8));
            bytes[1] = static_cast<std::uint8_t>(t.apid);
            bytes[2] = 0xC0;
            bytes[4] = static_cast<std::uint8_t>((bytes.size() - 7) >> 8);
            bytes[5] = static_cast<std::uint8_t>(bytes.size() - 7);
        }
        const ground::DecodedPacket p = ground::decodeTelemetry(bytes);
        CHECK_TRUE(p.ok || !p.error.empty());
        decoded += p.ok ? 1 : 0;
        CHECK_FALSE(ground::renderPacket(p).empty());
    }
    CHECK_TRUE(decoded > 100);
}

TEST(GroundTelemetryDecoder, RejectReasonNamesAndCodes) {
    STRCMP_EQUAL("replayed_sequence", ground::rejectReasonName(10).c_str());
    STRCMP_EQUAL("reason_200", ground::rejectReasonName(200).c_str());
    CHECK_EQUAL(10, ground::rejectReasonCode("REPLAYED_SEQUENCE"));
    CHECK_EQUAL(0, ground::rejectReasonCode("accepted"));
    CHECK_EQUAL(-1, ground::rejectReasonCode("bogus"));
}

// POWER renders every field, and a value outside its display limits
// (dictionary.def's RSE_LIMIT) is marked: the battery below its warn bound,
// a motor past its alarm bound; values inside are not.
TEST(GroundTelemetryDecoder, ValuesOutsideTheirDisplayLimitsAreMarked) {
    cmdtlm::POWER_Tlm power{};
    power.battery_voltage = 24.5F;  // warn (below 25), not alarm (24)
    power.battery_current = 3.25F;
    power.state_of_charge = 0.5F;
    power.solar_current = 1.0F;
    power.power_sample_time = 12.5F;
    for (std::size_t w = 0; w < 6; ++w) {
        power.motor_temperature[w] = 30.0F;
        power.temperature_valid[w] = 1;
    }
    power.motor_temperature[1] = 81.5F;  // alarm (above 80)
    power.motor_temperature[4] = 70.0F;  // warn (above 65)
    const std::string line = ground::renderPacket(roundTrip(power, 3, 13 * core::kNsPerSec));
    CHECK_TEXT(line.rfind("POWER ", 0) == 0, line.c_str());
    CHECK_TEXT(line.find(" battery_voltage=24.5!WARN ") != std::string::npos, line.c_str());
    CHECK_TEXT(line.find(" battery_current=3.25 ") != std::string::npos, line.c_str());
    CHECK_TEXT(line.find(" state_of_charge=0.5 ") != std::string::npos, line.c_str());
    CHECK_TEXT(line.find(" motor_temperature=[30,81.5!ALARM,30,30,70!WARN,30] ") != std::string::npos, line.c_str());
    CHECK_TEXT(line.find(" temperature_valid=[1,1,1,1,1,1]") != std::string::npos, line.c_str());

    power.battery_voltage = 23.75F;
    CHECK_TRUE(ground::renderPacket(roundTrip(power, 4, 0)).find(" battery_voltage=23.75!ALARM ") != std::string::npos);
    power.battery_voltage = 25.0F;  // on the bound: inside it
    CHECK_TRUE(ground::renderPacket(roundTrip(power, 5, 0)).find(" battery_voltage=25 ") != std::string::npos);
}

// HAZARDS shows the hazards in use only (count of the 32 entries), each with
// its detector id, centre and radius.
TEST(GroundTelemetryDecoder, HazardsShowOnlyTheHazardsInUse) {
    cmdtlm::HAZARDS_Tlm h{};
    h.revision = 12;
    h.count = 2;
    h.x[0] = 12.5F;
    h.y[0] = -1.25F;
    h.radius[0] = 0.5F;
    h.obstacle_id[0] = 7;
    h.x[1] = 3.0F;
    h.y[1] = 4.0F;
    h.radius[1] = 0.25F;
    h.obstacle_id[1] = 9;
    h.x[2] = 99.0F;  // beyond count: not shown
    const std::string line = ground::renderPacket(roundTrip(h, 1, 45 * core::kNsPerSec));
    CHECK_TEXT(line.rfind("HAZARDS ", 0) == 0, line.c_str());
    CHECK_TEXT(line.find("apid=0x019 seq=1 met=45.000 revision=12 count=2 hazards=[#7 (12.5,-1.25) r=0.5; #9 (3,4) r=0.25]") !=
                   std::string::npos,
               line.c_str());
    CHECK_TEXT(line.find("99") == std::string::npos, line.c_str());
    h.count = 0;
    CHECK_TRUE(ground::renderPacket(roundTrip(h, 2, 0)).find(" revision=12 count=0 hazards=[]") != std::string::npos);
}
