// Writes the fuzz seed corpora (make fuzz-seeds; unit_test/fuzz/README.md):
//
//   DIR/command/NAME.bin          one valid packet per dictionary command,
//                                 authenticated with the lab key (key id 1),
//                                 arguments in range
//   DIR/command/NAME.nokey.bin    a few unauthenticated ones (key id 0): valid
//                                 in the lab setting, mac_missing otherwise
//   DIR/command/invalid.REASON[.WHAT].bin
//                                 packets the validator must refuse with REASON
//                                 (toString(CommandReject)) in every mode
//   DIR/table/NAME.tbl            the default image of every table (the bytes
//                                 `rse-ground table build tables/NAME.toml` writes)
//   DIR/table/invalid.REASON[.WHAT].tbl
//                                 images checkTableImage refuses with REASON
//                                 (toString(TableReject), spaces as '_', lower case)
//
// The packets are built with encodeCommandPacket and the images are the
// generated default images, so the seeds follow the dictionary and the table
// sources; unit_test/system/corpus_replay checks them. Host tool: full language.
#include <cctype>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/command_packet.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"

using namespace rse;
using Bytes = std::vector<std::uint8_t>;

namespace {

std::string g_dir;
int g_written = 0;
bool g_failed = false;

void writeFile(const std::string& sub, const std::string& name, const Bytes& bytes) {
    const std::string path = g_dir + "/" + sub + "/" + name;
    FILE* f = std::fopen(path.c_str(), "wb");
    if (f == nullptr || std::fwrite(bytes.data(), 1, bytes.size(), f) != bytes.size() || std::fclose(f) != 0) {
        std::fprintf(stderr, "make_seeds: cannot write %s\n", path.c_str());
        g_failed = true;
        return;
    }
    ++g_written;
}

// ---- Commands ------------------------------------------------------------------

cmdtlm::HmacSha256 g_hmac;

// A readable in-range value for an argument: a named choice when it fits the
// dictionary's range, else 1 when that fits, else the minimum.
double pickValue(const cmdtlm::ArgDesc& arg) {
    struct Choice {
        const char* name;
        double value;
    };
    static const Choice kChoices[] = {{"mode", 1},     {"x", 12.5},     {"y", -4.0},     {"risk", 0.01},
                                      {"priority", 5}, {"v", 0.3},      {"omega", 0.1},  {"duration", 5},
                                      {"table_id", 1}, {"offset", 0},   {"buffer", 0}};
    for (const Choice& c : kChoices) {
        if (std::strcmp(c.name, arg.name) == 0 && c.value >= arg.min && c.value <= arg.max) {
            return c.value;
        }
    }
    return (arg.min <= 1 && 1 <= arg.max) ? 1 : arg.min;
}

void writeArg(core::BeWriter& w, cmdtlm::FieldType type, double value) {
    using cmdtlm::FieldType;
    switch (type) {
        case FieldType::u8: w.u8(static_cast<std::uint8_t>(value)); break;
        case FieldType::chr: w.u8(static_cast<std::uint8_t>(value)); break;
        case FieldType::u16: w.u16(static_cast<std::uint16_t>(value)); break;
        case FieldType::u32: w.u32(static_cast<std::uint32_t>(value)); break;
        case FieldType::u64: w.u64(static_cast<std::uint64_t>(value)); break;
        case FieldType::i16: w.i16(static_cast<std::int16_t>(value)); break;
        case FieldType::i32: w.i32(static_cast<std::int32_t>(value)); break;
        case FieldType::i64: w.i64(static_cast<std::int64_t>(value)); break;
        case FieldType::f32: w.f32(static_cast<float>(value)); break;
        case FieldType::f64: w.f64(value); break;
        case FieldType::blob: break;
    }
}

// Valid arguments for a command; the blob (TABLE_LOAD's data) is the start of
// the first default table image, which table_id 1 names.
Bytes validArgs(const cmdtlm::CommandDesc& c, const std::vector<double>* overrides = nullptr) {
    Bytes out(cmdtlm::kMaxCommandPacket);
    core::BeWriter w(out.data(), out.size());
    for (std::size_t i = 0; i < c.argCount; ++i) {
        const cmdtlm::ArgDesc& arg = c.args[i];
        if (arg.type == cmdtlm::FieldType::blob) {
            const tables::TableImageRef& image = tables::kDefaultTableImages[0];
            const std::size_t n = image.length < arg.maxBytes ? image.length : arg.maxBytes;
            w.bytes(image.data, n);
            continue;
        }
        const double value = overrides != nullptr && i < overrides->size() && !std::isnan((*overrides)[i]) ?
                                 (*overrides)[i] : pickValue(arg);
        writeArg(w, arg.type, value);
    }
    out.resize(w.size());
    return out;
}

Bytes packet(const cmdtlm::CommandDesc& c, const Bytes& args, std::uint16_t keyId, const std::uint8_t* key,
             std::uint32_t authSequence) {
    cmdtlm::CommandFields f;
    f.apid = c.apid;
    f.functionCode = c.functionCode;
    f.sequenceCount = static_cast<std::uint16_t>(authSequence & cmdtlm::kSequenceCountMask);
    f.keyId = keyId;
    f.authSequence = authSequence;
    Bytes out(cmdtlm::kMaxCommandPacket);
    const std::size_t n =
        cmdtlm::encodeCommandPacket(f, args.data(), args.size(), key, g_hmac, out.data(), out.size());
    if (n == 0) {
        std::fprintf(stderr, "make_seeds: cannot encode %s\n", c.name);
        g_failed = true;
    }
    out.resize(n);
    return out;
}

const cmdtlm::CommandDesc& command(const char* name) {
    const cmdtlm::CommandDesc* c = cmdtlm::findCommand(name);
    if (c == nullptr) {
        std::fprintf(stderr, "make_seeds: no command %s in the dictionary\n", name);
        std::exit(1);
    }
    return *c;
}

Bytes authenticated(const char* name, const Bytes& args, std::uint32_t sequence) {
    return packet(command(name), args, cmdtlm::kLabKeyId, cmdtlm::kLabKey, sequence);
}

void refreshChecksum(Bytes& p) { p[cmdtlm::kChecksumOffset] = cmdtlm::commandChecksum(p.data(), p.size()); }

void commandSeeds() {
    std::size_t count = 0;
    const cmdtlm::CommandDesc* descs = cmdtlm::commandDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const cmdtlm::CommandDesc& c = descs[i];
        writeFile("command", std::string(c.name) + ".bin",
                  packet(c, validArgs(c), cmdtlm::kLabKeyId, cmdtlm::kLabKey, static_cast<std::uint32_t>(100 + i)));
    }
    for (const char* name : {"NOOP", "SET_MODE", "GOTO", "DRIVE", "TABLE_LOAD"}) {
        const cmdtlm::CommandDesc& c = command(name);
        writeFile("command", std::string(name) + ".nokey.bin", packet(c, validArgs(c), cmdtlm::kNoKey, nullptr, 7));
    }

    const double nan = std::numeric_limits<double>::quiet_NaN();
    std::uint8_t otherKey[cmdtlm::kKeySize];
    for (std::size_t i = 0; i < sizeof otherKey; ++i) {
        otherKey[i] = static_cast<std::uint8_t>(0xC3 ^ (i * 29));
    }

    Bytes p = authenticated("NOOP", {}, 201);
    p.resize(p.size() - 3);  // the length field now disagrees with the bytes
    writeFile("command", "invalid.bad_length.truncated.bin", p);

    writeFile("command", "invalid.bad_length.args.bin", authenticated("SET_MODE", {1, 0}, 202));

    {
        const cmdtlm::CommandDesc& load = command("TABLE_LOAD");
        Bytes args = validArgs(load);
        args.resize(load.fixedArgBytes + load.maxBlobBytes + 1U, 0x5A);  // one byte over the blob's maximum
        writeFile("command", "invalid.bad_length.blob_too_long.bin", authenticated("TABLE_LOAD", args, 203));
    }

    {
        // Longer than any command packet, header and length field consistent.
        Bytes big(cmdtlm::kMaxCommandPacket + 40, 0);
        cmdtlm::PrimaryHeader h;
        h.type = cmdtlm::PacketType::kCommand;
        h.apid = command("NOOP").apid;
        h.dataLength = static_cast<std::uint16_t>(big.size() - 7);
        cmdtlm::encodePrimaryHeader(h, big.data());
        refreshChecksum(big);
        writeFile("command", "invalid.bad_length.oversize.bin", big);
    }

    p = authenticated("NOOP", {}, 204);
    p[0] = static_cast<std::uint8_t>(p[0] | 0x20);  // version 1
    refreshChecksum(p);
    writeFile("command", "invalid.bad_header.version.bin", p);

    p = authenticated("NOOP", {}, 205);
    p[0] = static_cast<std::uint8_t>(p[0] & ~0x10);  // telemetry type
    refreshChecksum(p);
    writeFile("command", "invalid.bad_header.telemetry_type.bin", p);

    p = authenticated("GOTO", validArgs(command("GOTO")), 206);
    p[cmdtlm::kCommandHeaderSize] ^= 0x01;
    writeFile("command", "invalid.bad_checksum.bin", p);

    {
        cmdtlm::CommandDesc fake = command("NOOP");
        fake.apid = 0x7F0;
        writeFile("command", "invalid.unknown_apid.bin", packet(fake, {}, cmdtlm::kLabKeyId, cmdtlm::kLabKey, 207));
        fake = command("NOOP");
        fake.functionCode = 0x55;
        writeFile("command", "invalid.unknown_function_code.bin",
                  packet(fake, {}, cmdtlm::kLabKeyId, cmdtlm::kLabKey, 208));
    }

    writeFile("command", "invalid.unknown_key.bin", packet(command("NOOP"), {}, 7, otherKey, 209));
    writeFile("command", "invalid.bad_mac.bin", packet(command("NOOP"), {}, cmdtlm::kLabKeyId, otherKey, 210));

    {
        const cmdtlm::CommandDesc& c = command("SET_RISK_BOUND");
        const std::vector<double> risk = {0.9};
        writeFile("command", "invalid.argument_out_of_range.risk.bin", authenticated(c.name, validArgs(c, &risk), 211));
    }
    {
        // NaN is "keep the default" in the override list: write the bytes by hand.
        const cmdtlm::CommandDesc& c = command("GOTO");
        Bytes args = validArgs(c);
        core::BeWriter w(args.data(), 8);
        w.f64(nan);
        writeFile("command", "invalid.argument_out_of_range.nan.bin", authenticated(c.name, args, 212));
    }
    {
        const cmdtlm::CommandDesc& c = command("TABLE_VALIDATE");
        const std::vector<double> id = {static_cast<double>(tables::kTableCount + 1)};  // one past the last table
        writeFile("command", "invalid.argument_out_of_range.table_id.bin",
                  authenticated(c.name, validArgs(c, &id), 213));
    }
}

// ---- Tables --------------------------------------------------------------------

std::string lower(const char* s) {
    std::string out;
    for (; *s != '\0'; ++s) {
        out += static_cast<char>(std::tolower(static_cast<unsigned char>(*s)));
    }
    return out;
}

Bytes defaultImage(tables::TableId id) {
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& image = tables::kDefaultTableImages[i];
        tables::TableHeader h;
        if (tables::readTableHeader(image.data, image.length, &h) && h.tableId == static_cast<std::uint16_t>(id)) {
            return Bytes(image.data, image.data + image.length);
        }
    }
    std::fprintf(stderr, "make_seeds: no default image for table %u\n", static_cast<unsigned>(id));
    std::exit(1);
}

// Changes one field of a default image and seals it again (header and CRC).
Bytes withField(tables::TableId id, std::uint16_t field, double value) {
    Bytes image = defaultImage(id);
    const tables::TableDesc* table = tables::findTable(id);
    tables::TableHeader h;
    tables::readTableHeader(image.data(), image.size(), &h);
    if (!tables::writeFieldValue(*table, image.data() + tables::kTableHeaderSize,
                                 image.size() - tables::kTableHeaderSize, field, 0, value) ||
        tables::sealTableImage(id, h.version, image.data(), image.size()) != image.size()) {
        std::fprintf(stderr, "make_seeds: cannot set field %u of %s\n", field, table->name);
        g_failed = true;
    }
    return image;
}

double fieldValue(tables::TableId id, std::uint16_t field) {
    const Bytes image = defaultImage(id);
    double value = 0.0;
    tables::readFieldValue(*tables::findTable(id), image.data() + tables::kTableHeaderSize,
                           image.size() - tables::kTableHeaderSize, field, 0, &value);
    return value;
}

void tableSeeds() {
    using tables::TableId;
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& image = tables::kDefaultTableImages[i];
        tables::TableHeader h;
        const tables::TableDesc* table =
            tables::readTableHeader(image.data, image.length, &h) ? tables::findTable(static_cast<TableId>(h.tableId))
                                                                  : nullptr;
        if (table == nullptr) {
            std::fprintf(stderr, "make_seeds: default image %zu names no table\n", i);
            g_failed = true;
            continue;
        }
        writeFile("table", lower(table->name) + ".tbl", Bytes(image.data, image.data + image.length));
    }

    const TableId geometry = TableId::kRoverGeometry;
    Bytes image = defaultImage(geometry);
    image[tables::kTableHeaderSize] ^= 0x01;
    writeFile("table", "invalid.bad_crc.tbl", image);

    writeFile("table", "invalid.out_of_range.wheel_radius.tbl",
              withField(geometry, tables::RoverGeometryField::wheel_radius_m, 5.0));

    image = defaultImage(geometry);
    const std::uint8_t nanBits[4] = {0x7F, 0xC0, 0x00, 0x00};  // f32 quiet NaN in wheel_radius_m
    std::memcpy(image.data() + tables::kTableHeaderSize, nanBits, sizeof nanBits);
    {
        tables::TableHeader h;
        tables::readTableHeader(image.data(), image.size(), &h);
        tables::sealTableImage(geometry, h.version, image.data(), image.size());
    }
    writeFile("table", "invalid.not_finite.wheel_radius.tbl", image);

    // The clear threshold equal to the fault threshold breaks the hysteresis rule.
    writeFile("table", "invalid.inconsistent.pose_sigma.tbl",
              withField(TableId::kEstimatorNoise, tables::EstimatorNoiseField::pose_clear_sigma_m,
                        fieldValue(TableId::kEstimatorNoise, tables::EstimatorNoiseField::pose_fault_sigma_m)));

    image = defaultImage(geometry);
    image.pop_back();
    writeFile("table", "invalid.bad_length.truncated.tbl", image);

    image = defaultImage(geometry);
    image.resize(10);
    writeFile("table", "invalid.too_short.tbl", image);

    image = defaultImage(geometry);
    image[0] = 'X';
    writeFile("table", "invalid.bad_magic.tbl", image);

    image = defaultImage(geometry);
    image[4] = 0x00;
    image[5] = 0x2A;  // table id 42
    writeFile("table", "invalid.unknown_table.tbl", image);

    image = defaultImage(geometry);
    image[7] = 0x02;  // format 2
    writeFile("table", "invalid.bad_format.tbl", image);
}

}  // namespace

int main(int argc, char** argv) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: make_seeds CORPUS_DIR  (writes CORPUS_DIR/command and CORPUS_DIR/table)\n");
        return 2;
    }
    g_dir = argv[1];
    if (!core::isOk(g_hmac.init())) {
        std::fprintf(stderr, "make_seeds: HMAC engine unavailable\n");
        return 1;
    }
    commandSeeds();
    tableSeeds();
    std::printf("make_seeds: %d files in %s/command and %s/table\n", g_written, g_dir.c_str(), g_dir.c_str());
    return g_failed ? 1 : 0;
}
