// Wire formats across machines: every target encodes the same reference
// samples (telemetry, an event's numbers, an authenticated command, a table
// image, a CANopen PDO payload) with its own build of the flight and ground code and writes them to
// RSE_WIRE_DIR/<target>.txt (default build/wire); then each target reads the
// files the other targets wrote (RSE_WIRE_PEERS, names separated by spaces) and
// requires the same bytes and the same decoded values. make test runs the suite
// on every target, then once more per target with the others as peers
// (test-wire/T): x86_64 and the 64-bit and 32-bit ARMs are little-endian, s390x
// big-endian, so a codec that leaned on the host's byte order, word size or
// float layout fails here on one side or the other. Without RSE_WIRE_PEERS the
// peer test reads this target's own file back (no peer, no vacuous pass).
//
// The file is text (sample name, then the bytes in hex): the container itself
// has no byte order to get wrong.
#include <sys/stat.h>

#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_validator.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/command_encoder.hpp"
#include "ground/event_data_pairing.hpp"
#include "ground/table_compiler.hpp"
#include "ground/telemetry_decoder.hpp"
#include "hal/canopen/le_codec.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

using Bytes = std::vector<std::uint8_t>;
using Samples = std::map<std::string, Bytes>;

// The name make test gives this target's build folder (Makefile, arch_of).
const char* thisTarget() {
#if defined(__x86_64__)
    return "x86_64";
#elif defined(__aarch64__)
    return "aarch64";
#elif defined(__arm__)
    return "armhf";
#elif defined(__s390x__)
    return "s390x";
#elif defined(__powerpc__)
    return "powerpc";
#else
    return "unknown";
#endif
}

std::string wireDir() {
    const char* dir = std::getenv("RSE_WIRE_DIR");
    return dir != nullptr && dir[0] != '\0' ? dir : "build/wire";
}

// The reference values: exactly representable in their wire types (f32 ones
// too), so every decoder must give them back exactly.
constexpr std::uint32_t kEventSequence = 0x01020304U;
constexpr double kEventTime = 1234.5678;
constexpr std::uint16_t kEventId = 0xBEEF;
constexpr std::uint8_t kSeverity = 2;
constexpr char kEventText[] = "wire exchange: big-endian on the wire, any byte order at home";
// The event's numbers (EVENT_DATA): a LEG_SENT, every value exact in f64 but
// none an integer in f32, one negative, one tiny.
constexpr double kLegX = 17.625, kLegY = -0.46875, kLegPowerW = 324.2431640625, kTiny = 3.0517578125e-05;
constexpr double kGotoX = 12.5, kGotoY = -3.25, kGotoRisk = 1e-3;
constexpr std::uint32_t kGotoAuthSequence = 0x00ABCDEF;
constexpr std::uint16_t kControlword = 0x000F;
constexpr std::int32_t kTargetVelocity = -123456;  // CiA 402 RPDO: controlword, target velocity (little-endian)

// Sequence 5 at MET 42 s, as the flight's TelemetryOutput builds packets.
template <typename T>
Bytes telemetryPacketOf(const T& telemetry) {
    return test::telemetryPacket(telemetry, 5, 42 * core::kNsPerSec);
}

cmdtlm::PLAN_PATH_Tlm referencePlan() {
    cmdtlm::PLAN_PATH_Tlm p{};
    p.plan_number = 7;
    p.plan_time = 98.25;
    p.status = 1;
    p.steps = 3;
    p.risk_bound = 1e-3;
    p.risk_used = 7.5e-4;
    p.length = 12.75F;
    p.process_sigma = 0.0625F;
    const float cov[4] = {0.015625F, -0.00390625F, -0.00390625F, 0.03125F};
    std::memcpy(p.start_cov, cov, sizeof cov);
    p.goal_x = 12.5F;
    p.goal_y = -3.25F;
    const float xs[4] = {0.0F, 4.5F, 9.25F, 12.5F}, ys[4] = {0.0F, -1.0F, -2.5F, -3.25F};
    for (int i = 0; i < 4; ++i) {
        p.mean_x[i] = xs[i];
        p.mean_y[i] = ys[i];
    }
    return p;
}

// This target's encodings of the reference samples.
Samples encodeSamples() {
    Samples s;
    cmdtlm::EVENT_Tlm event{};
    event.event_sequence = kEventSequence;
    event.event_time = kEventTime;
    event.event_id = kEventId;
    event.severity = kSeverity;
    std::strncpy(event.text, kEventText, sizeof event.text - 1);
    s["tlm_event"] = telemetryPacketOf(event);
    cmdtlm::event_data::LEG_SENT sent;
    sent.leg_id = 4;
    sent.index = 3;
    sent.count = 6;
    sent.x = kLegX;
    sent.y = kLegY;
    sent.length_bound = kTiny;
    sent.power_bound = kLegPowerW;
    const core::EventData values = sent.pack();
    cmdtlm::EVENT_DATA_Tlm data{};
    data.event_sequence = kEventSequence;
    data.event_id = cmdtlm::event_data::LEG_SENT::kFirstId;
    data.value_count = values.count;
    for (std::size_t i = 0; i < values.count; ++i) {
        data.value[i] = values.values[i];
    }
    data.data_withheld = 0x0A0B0C0DU;
    s["tlm_event_data"] = telemetryPacketOf(data);
    s["tlm_plan_path"] = telemetryPacketOf(referencePlan());
    s["cmd_goto"] = ground::encodeCommand("GOTO", {"x=12.5", "y=-3.25", "risk=1e-3"}, ground::labKeyAuth(),
                                          kGotoAuthSequence);
    s["table_rover_geometry"] = ground::compileTableFile("tables/rover_geometry.toml").image;
    Bytes pdo(6);
    hal::le::putU16(&pdo[0], kControlword);
    hal::le::putI32(&pdo[2], kTargetVelocity);
    s["can_rpdo"] = pdo;
    return s;
}

std::string hex(const Bytes& b) {
    static const char digits[] = "0123456789abcdef";
    std::string out;
    for (const std::uint8_t v : b) {
        out += digits[v >> 4];
        out += digits[v & 0xF];
    }
    return out;
}

bool unhex(const std::string& text, Bytes* out) {
    if (text.size() % 2 != 0) {
        return false;
    }
    out->clear();
    for (std::size_t i = 0; i < text.size(); i += 2) {
        const std::string pair = text.substr(i, 2);
        char* end = nullptr;
        const unsigned long v = std::strtoul(pair.c_str(), &end, 16);
        if (end != pair.c_str() + 2) {
            return false;
        }
        out->push_back(static_cast<std::uint8_t>(v));
    }
    return true;
}

std::string fileOf(const std::string& target) { return wireDir() + "/" + target + ".txt"; }

bool writeSamples(const std::string& target, const Samples& samples) {
    const std::string dir = wireDir();
    // build/ exists whenever make runs the suite; the folder below it may not.
    ::mkdir(dir.c_str(), 0755);
    std::ofstream out(fileOf(target));
    for (const auto& [name, bytes] : samples) {
        out << name << ' ' << hex(bytes) << '\n';
    }
    return static_cast<bool>(out);
}

// Empty when the file is missing or a line is malformed (then *why says which).
Samples readSamples(const std::string& target, std::string* why) {
    std::ifstream in(fileOf(target));
    if (!in) {
        *why = fileOf(target) + " is missing: did the " + target + " suites run?";
        return {};
    }
    Samples s;
    std::string line;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string name, text;
        Bytes bytes;
        if (!(fields >> name >> text) || !unhex(text, &bytes)) {
            *why = fileOf(target) + ": malformed line '" + line + "'";
            return {};
        }
        s[name] = bytes;
    }
    return s;
}

// Decodes one target's samples with this target's decoders and checks every
// reference value; `from` names the writer in failure messages.
void checkDecodes(const Samples& s, const std::string& from) {
    const std::string where = "samples written by " + from + ", read on " + thisTarget();

    const ground::DecodedPacket event = ground::decodeTelemetry(s.at("tlm_event"));
    CHECK_TEXT(event.ok, (where + ": EVENT " + event.error).c_str());
    CHECK_EQUAL_TEXT(cmdtlm::EVENT_Tlm::kApid, event.apid, where.c_str());
    DOUBLES_EQUAL_TEXT(42.0, event.met, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kEventSequence, *event.value("event_sequence"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kEventTime, *event.value("event_time"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kEventId, *event.value("event_id"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kSeverity, *event.value("severity"), 0.0, where.c_str());
    STRCMP_EQUAL_TEXT(kEventText, event.field("text")->text.c_str(), where.c_str());

    // The event's numbers, by the names of its layout, paired by event_sequence.
    const ground::DecodedPacket numbers = ground::decodeTelemetry(s.at("tlm_event_data"));
    CHECK_TEXT(numbers.ok, (where + ": EVENT_DATA " + numbers.error).c_str());
    ground::EventDataPacket read;
    CHECK_TEXT(ground::readEventData(numbers, &read), where.c_str());
    CHECK_EQUAL_TEXT(kEventSequence, read.sequence, where.c_str());
    CHECK_EQUAL_TEXT(0x0A0B0C0DU, read.withheld, where.c_str());
    cmdtlm::event_data::LEG_SENT sent;
    CHECK_TEXT(sent.unpack(read.id, read.data), where.c_str());
    DOUBLES_EQUAL_TEXT(4.0, sent.leg_id, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kLegX, sent.x, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kLegY, sent.y, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kTiny, sent.length_bound, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kLegPowerW, sent.power_bound, 0.0, where.c_str());

    const ground::DecodedPacket plan = ground::decodeTelemetry(s.at("tlm_plan_path"));
    CHECK_TEXT(plan.ok, (where + ": PLAN_PATH " + plan.error).c_str());
    const cmdtlm::PLAN_PATH_Tlm ref = referencePlan();
    DOUBLES_EQUAL_TEXT(ref.plan_number, *plan.value("plan_number"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.plan_time, *plan.value("plan_time"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.risk_used, *plan.value("risk_used"), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.start_cov[1], *plan.value("start_cov", 1), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.mean_x[2], *plan.value("mean_x", 2), 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(ref.mean_y[3], *plan.value("mean_y", 3), 0.0, where.c_str());

    // The command through the flight validator's every check (header, checksum,
    // APID and function code, key id, HMAC, sequence, argument ranges), then its
    // arguments as the command handler decodes them.
    const Bytes& command = s.at("cmd_goto");
    cmdtlm::KeyStore keys;
    CHECK_TRUE(core::isOk(keys.add(cmdtlm::kLabKeyId, cmdtlm::kLabKey)));
    cmdtlm::HmacSha256 hmac;
    CHECK_TRUE(core::isOk(hmac.init()));
    cmdtlm::CommandValidator validator(keys, hmac);
    const cmdtlm::CommandVerdict verdict = validator.check(command.data(), command.size(), cmdtlm::Mode::kStandby);
    CHECK_TEXT(verdict.reason == cmdtlm::CommandReject::kAccepted,
               (where + ": GOTO " + cmdtlm::toString(verdict.reason)).c_str());
    STRCMP_EQUAL_TEXT("GOTO", verdict.command->name, where.c_str());
    CHECK_EQUAL_TEXT(kGotoAuthSequence, verdict.authSequence, where.c_str());
    core::BeReader args(verdict.args, verdict.argLength);
    cmdtlm::GOTO_Args go{};
    cmdtlm::decodeArgs(args, &go);
    DOUBLES_EQUAL_TEXT(kGotoX, go.x, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kGotoY, go.y, 0.0, where.c_str());
    DOUBLES_EQUAL_TEXT(kGotoRisk, go.risk, 0.0, where.c_str());

    // The table image through the flight's own image check (header, CRC, the
    // field checks) and the ground's description of every field's value.
    const Bytes& image = s.at("table_rover_geometry");
    const tables::TableCheck check = tables::checkTableImage(image.data(), image.size());
    CHECK_TEXT(check.ok(), (where + ": rover_geometry image " + ground::describeCheck(image.data(), image.size())).c_str());
    const Bytes own = ground::compileTableFile("tables/rover_geometry.toml").image;
    CHECK_EQUAL_TEXT(ground::describeImage(own.data(), own.size()), ground::describeImage(image.data(), image.size()),
                     where.c_str());

    const Bytes& pdo = s.at("can_rpdo");
    CHECK_EQUAL_TEXT(6U, pdo.size(), where.c_str());
    CHECK_EQUAL_TEXT(kControlword, hal::le::getU16(&pdo[0]), where.c_str());
    CHECK_EQUAL_TEXT(kTargetVelocity, hal::le::getI32(&pdo[2]), where.c_str());
}

}  // namespace

TEST_GROUP(WireExchange){};

TEST(WireExchange, ThisTargetEncodesTheSamplesDecodesThemAndWritesThemOut) {
    const Samples mine = encodeSamples();
    for (const auto& [name, bytes] : mine) {
        CHECK_TEXT(!bytes.empty(), (name + " did not encode").c_str());
    }
    checkDecodes(mine, thisTarget());
    CHECK_TEXT(writeSamples(thisTarget(), mine), ("cannot write " + fileOf(thisTarget())).c_str());
}

// Each peer's file: the same sample names, the same bytes as this target's, and
// every value decoded back (checkDecodes). The byte comparison is the ICD's
// promise (one wire format whatever the machine); the decode is the reader's.
TEST(WireExchange, EveryPeerTargetsSamplesAreTheseBytesAndDecodeHere) {
    const Samples mine = encodeSamples();
    const char* peerList = std::getenv("RSE_WIRE_PEERS");
    const bool ownFileOnly = peerList == nullptr || peerList[0] == '\0';
    if (ownFileOnly) {  // this target's file as written now, not one a previous run left
        CHECK_TEXT(writeSamples(thisTarget(), mine), ("cannot write " + fileOf(thisTarget())).c_str());
    }
    std::istringstream peers(ownFileOnly ? thisTarget() : peerList);
    int read = 0;
    std::string peer;
    while (peers >> peer) {
        std::string why;
        const Samples theirs = readSamples(peer, &why);
        CHECK_TEXT(!theirs.empty(), why.c_str());
        CHECK_EQUAL_TEXT(mine.size(), theirs.size(), (peer + ": another set of samples").c_str());
        for (const auto& [name, bytes] : mine) {
            const auto it = theirs.find(name);
            CHECK_TEXT(it != theirs.end(), (peer + " wrote no " + name).c_str());
            CHECK_EQUAL_TEXT(hex(bytes), hex(it->second),
                             (name + ": " + thisTarget() + " (expected) and " + peer + " (actual) differ").c_str());
        }
        checkDecodes(theirs, peer);
        ++read;
    }
    CHECK_TEXT(read > 0, "RSE_WIRE_PEERS named no target");
}
