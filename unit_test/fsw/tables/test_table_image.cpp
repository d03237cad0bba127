// The table image format and its checks (fsw/tables/table_image.hpp), and the
// descriptors generated from fsw/tables/table_defs.def.
#include <cmath>
#include <cstring>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include "fsw/core/crc32.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "unit_test/fsw/tables/table_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::tables;
using rse::test::defaultImage;

namespace {

template <typename T>
std::vector<std::uint8_t> encoded(const T& table, std::uint32_t version = 7) {
    std::vector<std::uint8_t> image(kMaxTableImageSize);
    const std::size_t length = encodeTable(table, version, image.data(), image.size());
    image.resize(length);
    return image;
}

RoverGeometryTable defaultGeometry() {
    const std::vector<std::uint8_t> image = defaultImage(TableId::kRoverGeometry);
    RoverGeometryTable t{};
    CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
    return t;
}

TableCheck checkOf(const std::vector<std::uint8_t>& image) { return checkTableImage(image.data(), image.size()); }
TableReject reasonOf(const std::vector<std::uint8_t>& image) { return checkOf(image).reason; }

// Rewrites the CRC so a deliberately edited header or payload passes the CRC
// and reaches the check under test.
void reseal(std::vector<std::uint8_t>* image) {
    const std::uint32_t crc = computeTableCrc(image->data(), image->size() - kTableHeaderSize);
    for (int i = 0; i < 4; ++i) {
        (*image)[kTableCrcOffset + static_cast<std::size_t>(i)] = static_cast<std::uint8_t>(crc >> (24 - 8 * i));
    }
}

}  // namespace

TEST_GROUP(TableImage){};

TEST(TableImage, Crc32IsTheStandardOne) {
    LONGS_EQUAL(0xCBF43926U, rse::core::crc32("123456789", 9));
}

TEST(TableImage, HeaderLayoutIsBigEndianAsDocumented) {
    const std::vector<std::uint8_t> image = encoded(defaultGeometry(), 0x01020304U);
    LONGS_EQUAL(kTableHeaderSize + kRoverGeometryPayloadSize, image.size());
    const std::uint8_t expected[16] = {'R', 'S', 'E', 'T', 0x00, 0x01, 0x00, 0x01, 0x01, 0x02, 0x03, 0x04,
                                       0x00, 0x00, 0x00, static_cast<std::uint8_t>(kRoverGeometryPayloadSize)};
    MEMCMP_EQUAL(expected, image.data(), sizeof expected);
    // CRC over bytes 0..15 then the payload, stored big-endian at 16.
    const std::uint32_t header = rse::core::crc32(image.data(), 16);
    const std::uint32_t crc = rse::core::crc32(image.data() + kTableHeaderSize, kRoverGeometryPayloadSize, header);
    LONGS_EQUAL(crc >> 24, image[16]);
    LONGS_EQUAL(crc & 0xFFU, image[19]);
    // First payload field: wheel_radius_m as a big-endian IEEE float.
    float radius = 0.0F;
    const std::uint32_t bits = (std::uint32_t{image[20]} << 24) | (std::uint32_t{image[21]} << 16) |
                               (std::uint32_t{image[22]} << 8) | image[23];
    std::memcpy(&radius, &bits, sizeof radius);
    CHECK_EQUAL(defaultGeometry().wheel_radius_m, radius);
}

TEST(TableImage, EncodeDecodeRoundTripsEveryField) {
    CanNodeMapTable map{};
    const std::uint8_t nodes[6] = {11, 12, 13, 14, 15, 16};
    std::memcpy(map.drive_node_id, nodes, sizeof nodes);
    map.imu_node_id = 40;
    map.power_node_id = 41;
    map.hazard_node_id = 42;
    map.position_fix_node_id = 43;
    map.heartbeat_timeout_ms = 4321;
    map.drive_boot_timeout_ms = 5432;
    const std::vector<std::uint8_t> image = encoded(map, 99);
    CanNodeMapTable back{};
    CHECK_TRUE(decodeTable(image.data(), image.size(), &back).ok());
    MEMCMP_EQUAL(nodes, back.drive_node_id, sizeof nodes);
    LONGS_EQUAL(43, back.position_fix_node_id);
    LONGS_EQUAL(4321, back.heartbeat_timeout_ms);
    LONGS_EQUAL(5432, back.drive_boot_timeout_ms);

    FaultResponseTable fr{};
    const std::vector<std::uint8_t> def = defaultImage(TableId::kFaultResponse);
    CHECK_TRUE(decodeTable(def.data(), def.size(), &fr).ok());
    fr.drive_overtemp_c = -12;  // the i32 field: negative values survive
    const std::vector<std::uint8_t> frImage = encoded(fr);
    FaultResponseTable frBack{};
    CHECK_TRUE(decodeTable(frImage.data(), frImage.size(), &frBack).ok());
    LONGS_EQUAL(-12, frBack.drive_overtemp_c);

    PlannerTable planner{};
    const std::vector<std::uint8_t> plannerDefault = defaultImage(TableId::kPlanner);
    CHECK_TRUE(decodeTable(plannerDefault.data(), plannerDefault.size(), &planner).ok());
    DOUBLES_EQUAL(1e-3, planner.default_risk_bound, 0.0);  // f64: exact
}

TEST(TableImage, ReEncodingADecodedImageGivesTheSameBytes) {
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    for (std::size_t i = 0; i < count; ++i) {
        const std::vector<std::uint8_t> image = defaultImage(descs[i].id);
        TableHeader header;
        CHECK_TRUE(readTableHeader(image.data(), image.size(), &header));
        std::vector<std::uint8_t> again;
        switch (descs[i].id) {
            case TableId::kRoverGeometry: {
                RoverGeometryTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kEstimatorNoise: {
                EstimatorNoiseTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kPlanner: {
                PlannerTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kFaultProtection: {
                FaultProtectionTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kHabitual: {
                HabitualTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kCanNodeMap: {
                CanNodeMapTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kFaultResponse: {
                FaultResponseTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kDriveHealthModel: {
                DriveHealthModelTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kFollower: {
                FollowerTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
            case TableId::kCoarseMap: {
                CoarseMapTable t{};
                CHECK_TRUE(decodeTable(image.data(), image.size(), &t).ok());
                again = encoded(t, header.version);
                break;
            }
        }
        CHECK_TEXT(again == image, descs[i].name);
    }
}

TEST(TableImage, EveryDefaultImagePassesAndCarriesTheDocumentedDefaults) {
    LONGS_EQUAL(kTableCount, kDefaultTableImageCount);
    std::set<std::uint16_t> ids;
    for (std::size_t i = 0; i < kDefaultTableImageCount; ++i) {
        const TableImageRef& ref = kDefaultTableImages[i];
        CHECK_TRUE(checkTableImage(ref.data, ref.length).ok());
        CHECK_TRUE(ref.length <= kMaxTableImageSize);
        TableHeader header;
        CHECK_TRUE(readTableHeader(ref.data, ref.length, &header));
        ids.insert(header.tableId);
    }
    LONGS_EQUAL(kTableCount, ids.size());
    const RoverGeometryTable g = defaultGeometry();
    CHECK_EQUAL(5.0F, g.max_wheel_speed_rad_s);
    const std::vector<std::uint8_t> mapImage = defaultImage(TableId::kCanNodeMap);
    CanNodeMapTable map{};
    CHECK_TRUE(decodeTable(mapImage.data(), mapImage.size(), &map).ok());
    for (std::uint8_t w = 0; w < 6; ++w) {
        LONGS_EQUAL(w + 1, map.drive_node_id[w]);
    }
    LONGS_EQUAL(0x20, map.imu_node_id);
    LONGS_EQUAL(0x23, map.position_fix_node_id);
    LONGS_EQUAL(250, map.heartbeat_timeout_ms);
}

TEST(TableImage, AFlippedByteAnywhereIsRejected) {
    for (std::size_t t = 0; t < kDefaultTableImageCount; ++t) {
        const std::vector<std::uint8_t> good(kDefaultTableImages[t].data,
                                             kDefaultTableImages[t].data + kDefaultTableImages[t].length);
        TableHeader header;
        CHECK_TRUE(readTableHeader(good.data(), good.size(), &header));
        const auto id = static_cast<TableId>(header.tableId);
        for (std::size_t i = 0; i < good.size(); ++i) {
            for (std::uint8_t mask : {std::uint8_t{0x01}, std::uint8_t{0x80}, std::uint8_t{0xFF}}) {
                std::vector<std::uint8_t> bad = good;
                bad[i] = static_cast<std::uint8_t>(bad[i] ^ mask);
                const TableCheck check = checkTableImage(bad.data(), bad.size(), id);
                CHECK_FALSE(check.ok());
                if (i >= kTableHeaderSize || (i >= 8 && i < 12) || i >= kTableCrcOffset) {
                    // Version, CRC and payload bytes have no meaning of their own: the CRC catches them.
                    CHECK_TRUE(check.reason == TableReject::kBadCrc);
                }
            }
        }
    }
}

TEST(TableImage, HeaderFaultsAreNamedSpecifically) {
    const std::vector<std::uint8_t> good = defaultImage(TableId::kRoverGeometry);
    std::vector<std::uint8_t> bad = good;
    bad[0] = 'X';
    CHECK_TRUE(TableReject::kBadMagic == reasonOf(bad));
    bad = good;
    bad[5] = 0x00;  // id 0
    CHECK_TRUE(TableReject::kUnknownTable == reasonOf(bad));
    bad = good;
    bad[5] = 0x03;  // a valid id, not the one asked for
    CHECK_TRUE(TableReject::kWrongTable == checkTableImage(bad.data(), bad.size(), TableId::kRoverGeometry).reason);
    bad = good;
    bad[7] = 0x02;
    CHECK_TRUE(TableReject::kBadFormat == reasonOf(bad));
    bad = good;
    bad[15] = static_cast<std::uint8_t>(bad[15] + 1);
    CHECK_TRUE(TableReject::kBadLength == reasonOf(bad));
    CHECK_TRUE(TableReject::kTooShort == checkTableImage(good.data(), kTableHeaderSize - 1).reason);
    CHECK_TRUE(TableReject::kTooShort == checkTableImage(nullptr, 0).reason);
}

TEST(TableImage, WrongLengthsAreRejected) {
    const std::vector<std::uint8_t> good = defaultImage(TableId::kPlanner);
    // Truncated: the last payload byte missing.
    std::vector<std::uint8_t> bad(good.begin(), good.end() - 1);
    CHECK_TRUE(TableReject::kBadLength == reasonOf(bad));
    // Extended: one byte too many.
    bad = good;
    bad.push_back(0);
    CHECK_TRUE(TableReject::kBadLength == reasonOf(bad));
    // Header length disagrees with the table, image consistent with the header, CRC right.
    bad = good;
    bad.push_back(0);
    bad[15] = static_cast<std::uint8_t>(bad[15] + 1);
    reseal(&bad);
    CHECK_TRUE(TableReject::kBadLength == reasonOf(bad));
    // Header only.
    bad.assign(good.begin(), good.begin() + kTableHeaderSize);
    CHECK_TRUE(TableReject::kBadLength == reasonOf(bad));
}

TEST(TableImage, OutOfRangeValueWithAGoodCrcNamesTheField) {
    RoverGeometryTable g = defaultGeometry();
    g.max_wheel_speed_rad_s = 10.5F;  // max 10
    TableCheck check = checkOf(encoded(g));
    CHECK_TRUE(TableReject::kOutOfRange == check.reason);
    LONGS_EQUAL(RoverGeometryField::max_wheel_speed_rad_s, check.field);

    CanNodeMapTable map{};
    const std::vector<std::uint8_t> mapImage = defaultImage(TableId::kCanNodeMap);
    CHECK_TRUE(decodeTable(mapImage.data(), mapImage.size(), &map).ok());
    map.drive_node_id[3] = 0;  // node ids are 1..127
    const std::vector<std::uint8_t> badMap = encoded(map);
    check = checkTableImage(badMap.data(), badMap.size());
    CHECK_TRUE(TableReject::kOutOfRange == check.reason);
    LONGS_EQUAL(CanNodeMapField::drive_node_id, check.field);
    LONGS_EQUAL(3, check.element);

    FaultResponseTable fr{};
    const std::vector<std::uint8_t> frImage = defaultImage(TableId::kFaultResponse);
    CHECK_TRUE(decodeTable(frImage.data(), frImage.size(), &fr).ok());
    fr.drive_overtemp_c = -41;  // min -40
    const std::vector<std::uint8_t> badFr = encoded(fr);
    check = checkTableImage(badFr.data(), badFr.size());
    CHECK_TRUE(TableReject::kOutOfRange == check.reason);
    LONGS_EQUAL(FaultResponseField::drive_overtemp_c, check.field);
}

TEST(TableImage, BoundsAreInclusiveAndF32BoundsAreJudgedAsFloats) {
    RoverGeometryTable g = defaultGeometry();
    g.wheel_radius_m = 0.5F;   // exactly max
    g.track_width_m = 0.2F;    // exactly min (0.2 is not exact in binary: compared as floats)
    CHECK_TRUE(checkOf(encoded(g)).ok());
    g.track_width_m = std::nextafter(0.2F, 0.0F);
    CHECK_TRUE(TableReject::kOutOfRange == checkOf(encoded(g)).reason);
}

TEST(TableImage, NonFiniteFloatsAreRejected) {
    RoverGeometryTable g = defaultGeometry();
    g.footprint_radius_m = std::numeric_limits<float>::quiet_NaN();
    TableCheck check = checkOf(encoded(g));
    CHECK_TRUE(TableReject::kNotFinite == check.reason);
    LONGS_EQUAL(RoverGeometryField::footprint_radius_m, check.field);
    g = defaultGeometry();
    g.max_accel_m_s2 = std::numeric_limits<float>::infinity();
    check = checkOf(encoded(g));
    CHECK_TRUE(TableReject::kNotFinite == check.reason);
    PlannerTable p{};
    const std::vector<std::uint8_t> pImage = defaultImage(TableId::kPlanner);
    CHECK_TRUE(decodeTable(pImage.data(), pImage.size(), &p).ok());
    p.default_risk_bound = -std::numeric_limits<double>::quiet_NaN();
    CHECK_TRUE(TableReject::kNotFinite == checkOf(encoded(p)).reason);
}

TEST(TableImage, SwappedHysteresisPairIsInconsistent) {
    FaultResponseTable fr{};
    const std::vector<std::uint8_t> frImage = defaultImage(TableId::kFaultResponse);
    CHECK_TRUE(decodeTable(frImage.data(), frImage.size(), &fr).ok());
    fr.battery_low_v = 25.5F;
    fr.battery_clear_v = 25.0F;  // each in range, but clear below low
    const TableCheck check = checkOf(encoded(fr));
    CHECK_TRUE(TableReject::kInconsistent == check.reason);
    LONGS_EQUAL(FaultResponseField::battery_low_v, check.field);
    fr.battery_clear_v = 25.5F;  // equal: no hysteresis, also refused
    CHECK_TRUE(TableReject::kInconsistent == checkOf(encoded(fr)).reason);
}

TEST(TableImage, DecodeLeavesTheOutputUntouchedOnRejection) {
    RoverGeometryTable g = defaultGeometry();
    g.wheel_radius_m = 3.0F;
    const std::vector<std::uint8_t> bad = encoded(g);
    RoverGeometryTable out{};
    out.wheel_radius_m = 0.123F;
    CHECK_FALSE(decodeTable(bad.data(), bad.size(), &out).ok());
    CHECK_EQUAL(0.123F, out.wheel_radius_m);
    const std::vector<std::uint8_t> planner = defaultImage(TableId::kPlanner);
    CHECK_TRUE(TableReject::kWrongTable == decodeTable(planner.data(), planner.size(), &out).reason);
    CHECK_EQUAL(0.123F, out.wheel_radius_m);
}

TEST(TableImage, GenericFieldAccessReadsAndWritesEveryType) {
    const TableDesc* fr = findTable(TableId::kFaultResponse);
    CHECK(fr != nullptr);
    std::vector<std::uint8_t> payload(fr->payloadSize, 0);
    CHECK_TRUE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::drive_overtemp_c, 0, -7.0));
    CHECK_TRUE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::battery_low_v, 0, 23.5));
    CHECK_TRUE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_timeout_ms, 0, 65535.0));
    double v = 0.0;
    CHECK_TRUE(readFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::drive_overtemp_c, 0, &v));
    DOUBLES_EQUAL(-7.0, v, 0.0);
    CHECK_TRUE(readFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::battery_low_v, 0, &v));
    DOUBLES_EQUAL(23.5, v, 0.0);
    CHECK_TRUE(readFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_timeout_ms, 0, &v));
    DOUBLES_EQUAL(65535.0, v, 0.0);
    // Beyond the wire type, fractional integers, bad indices: refused.
    CHECK_FALSE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_timeout_ms, 0, 65536.0));
    CHECK_FALSE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_retries, 0, 1.5));
    CHECK_FALSE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_retries, 0, -1.0));
    CHECK_FALSE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::sdo_retries, 1, 1.0));
    CHECK_FALSE(writeFieldValue(*fr, payload.data(), payload.size(), FaultResponseField::kCount, 0, 1.0));
    CHECK_FALSE(readFieldValue(*fr, payload.data(), payload.size() - 1, FaultResponseField::sdo_retries, 0, &v));

    const TableDesc* map = findTable(TableId::kCanNodeMap);
    CHECK(map != nullptr);
    const std::vector<std::uint8_t> image = defaultImage(TableId::kCanNodeMap);
    CHECK_TRUE(readFieldValue(*map, image.data() + kTableHeaderSize, map->payloadSize, CanNodeMapField::drive_node_id,
                              5, &v));
    DOUBLES_EQUAL(6.0, v, 0.0);
    LONGS_EQUAL(6, fieldOffset(*map, CanNodeMapField::imu_node_id));
}

TEST(TableImage, CheckFieldValueAppliesRangeTypeAndFiniteness) {
    const TableDesc* map = findTable(TableId::kCanNodeMap);
    const TableFieldDesc& node = map->fields[CanNodeMapField::imu_node_id];
    CHECK_TRUE(TableReject::kNone == checkFieldValue(node, 127.0));
    CHECK_TRUE(TableReject::kOutOfRange == checkFieldValue(node, 128.0));
    CHECK_TRUE(TableReject::kOutOfRange == checkFieldValue(node, 12.5));
    CHECK_TRUE(TableReject::kOutOfRange == checkFieldValue(node, std::nan("")));
    const TableFieldDesc& radius = findTable(TableId::kRoverGeometry)->fields[RoverGeometryField::wheel_radius_m];
    CHECK_TRUE(TableReject::kNotFinite == checkFieldValue(radius, std::numeric_limits<double>::infinity()));
    CHECK_TRUE(TableReject::kOutOfRange == checkFieldValue(radius, 1e300));
}

TEST(TableImage, SealRefusesUnknownTablesAndSmallBuffers) {
    std::uint8_t buffer[kMaxTableImageSize] = {};
    LONGS_EQUAL(0, sealTableImage(static_cast<TableId>(99), 1, buffer, sizeof buffer));
    LONGS_EQUAL(0, sealTableImage(TableId::kPlanner, 1, buffer, kTableHeaderSize + kPlannerPayloadSize - 1));
    LONGS_EQUAL(kTableHeaderSize + kPlannerPayloadSize, sealTableImage(TableId::kPlanner, 1, buffer, sizeof buffer));
    LONGS_EQUAL(0, encodeTable(defaultGeometry(), 1, buffer, kTableHeaderSize + kRoverGeometryPayloadSize - 1));
}

TEST_GROUP(TableDescriptors){};

TEST(TableDescriptors, IdsNamesAndLookupsAgree) {
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    LONGS_EQUAL(10, count);
    const std::uint16_t ids[] = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10};
    const char* names[] = {"ROVER_GEOMETRY", "ESTIMATOR_NOISE", "PLANNER",           "HABITUAL",
                           "CAN_NODE_MAP",   "FAULT_RESPONSE",  "DRIVE_HEALTH_MODEL", "FOLLOWER",
                           "COARSE_MAP",     "FAULT_PROTECTION"};
    for (std::size_t i = 0; i < count; ++i) {
        LONGS_EQUAL(ids[i], static_cast<std::uint16_t>(descs[i].id));
        STRCMP_EQUAL(names[i], descs[i].name);
        POINTERS_EQUAL(&descs[i], findTable(descs[i].id));
        POINTERS_EQUAL(&descs[i], findTable(names[i]));
        LONGS_EQUAL(i, tableIndex(descs[i].id));
    }
    POINTERS_EQUAL(nullptr, findTable(static_cast<TableId>(0)));
    POINTERS_EQUAL(nullptr, findTable("RoverGeometry"));
    POINTERS_EQUAL(nullptr, findTable(static_cast<const char*>(nullptr)));
    LONGS_EQUAL(count, tableIndex(static_cast<TableId>(11)));
}

TEST(TableDescriptors, EveryFieldIsDescribedAndItsRangeFitsItsType) {
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    std::size_t largest = 0;
    for (std::size_t t = 0; t < count; ++t) {
        const TableDesc& table = descs[t];
        std::size_t bytes = 0;
        std::set<std::string> seen;
        for (std::size_t f = 0; f < table.fieldCount; ++f) {
            const TableFieldDesc& field = table.fields[f];
            CHECK_TEXT(seen.insert(field.name).second, field.name);
            CHECK_TEXT(field.count >= 1, field.name);
            CHECK_TEXT(std::strlen(field.units) > 0, field.name);
            CHECK_TEXT(std::strlen(field.description) > 0, field.name);
            CHECK_TEXT(field.min <= field.max, field.name);
            // The bounds themselves are storable values (else a field could never be set to them).
            CHECK_TEXT(checkFieldValue(field, field.min) == TableReject::kNone, field.name);
            CHECK_TEXT(checkFieldValue(field, field.max) == TableReject::kNone, field.name);
            // ... and the wire type holds them.
            std::vector<std::uint8_t> payload(table.payloadSize);
            const auto index = static_cast<std::uint16_t>(f);
            CHECK_TEXT(writeFieldValue(table, payload.data(), payload.size(), index, 0, field.min), field.name);
            CHECK_TEXT(writeFieldValue(table, payload.data(), payload.size(), index, 0, field.max), field.name);
            bytes += field.count * fieldTypeSize(field.type);
        }
        LONGS_EQUAL(bytes, table.payloadSize);
        largest = bytes > largest ? bytes : largest;
    }
    LONGS_EQUAL(largest, kMaxTablePayloadSize);
    LONGS_EQUAL(kTableHeaderSize + largest, kMaxTableImageSize);
}

TEST(TableDescriptors, RulesReferToScalarFieldsOfTheirTable) {
    std::size_t count = 0;
    const TableRuleDesc* rules = tableRules(&count);
    CHECK(count >= 2);
    for (std::size_t i = 0; i < count; ++i) {
        const TableDesc* table = findTable(rules[i].id);
        CHECK(table != nullptr);
        CHECK(rules[i].lower < table->fieldCount && rules[i].upper < table->fieldCount);
        LONGS_EQUAL(1, table->fields[rules[i].lower].count);
        LONGS_EQUAL(1, table->fields[rules[i].upper].count);
        CHECK(rules[i].why != nullptr);
    }
}

TEST(TableDescriptors, RejectReasonsHaveDistinctNames) {
    std::set<std::string> names;
    for (std::size_t r = 0; r < kTableRejectCount; ++r) {
        const std::string name = toString(static_cast<TableReject>(r));
        CHECK_TEXT(name != "?", name.c_str());
        CHECK_TEXT(names.insert(name).second, name.c_str());
    }
    STRCMP_EQUAL("?", toString(static_cast<TableReject>(kTableRejectCount)));
}
