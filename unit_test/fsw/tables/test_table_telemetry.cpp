// The table service's packets: TABLE_STATUS with the verdict of a command,
// TABLE_DUMP in chunks that put the image back together; HK's table_* fields.
#include <vector>

#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_telemetry.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::RecordingSink;

TEST_GROUP(TableTelemetry) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    tables::TableService service{events};
    tables::TableTelemetry telemetry{service};
    RecordingSink sink;
    void setup() override {
        CHECK(core::isOk(service.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
    }
};

TEST(TableTelemetry, StatusCarriesTheTableAndTheVerdict) {
    tables::TableCheck check{};
    check.reason = tables::TableReject::kOutOfRange;
    check.field = 3;
    telemetry.sendStatus(tables::TableId::kPlanner, check, sink);
    const RecordingSink::Packet& p = sink.last<cmdtlm::TABLE_STATUS_Tlm>();
    DOUBLES_EQUAL(static_cast<double>(tables::TableId::kPlanner), RecordingSink::field(p, "table_id"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(tables::TableReject::kOutOfRange), RecordingSink::field(p, "last_reject"), 0.0);
    DOUBLES_EQUAL(3, RecordingSink::field(p, "last_reject_field"), 0.0);
    DOUBLES_EQUAL(service.status(tables::TableId::kPlanner).activeCrc, RecordingSink::field(p, "active_crc"), 0.0);
}

TEST(TableTelemetry, ADumpsChunksPutTheActiveImageBackTogether) {
    std::uint8_t image[tables::kMaxTableImageSize];
    std::size_t length = 0;
    CHECK(service.dump(tables::TableId::kCoarseMap, false, image, sizeof image, &length).ok());
    CHECK(core::isOk(telemetry.sendDump(tables::TableId::kCoarseMap, false, sink)));
    std::vector<std::uint8_t> joined;
    for (const RecordingSink::Packet& p : sink.packets) {
        LONGS_EQUAL(joined.size(), RecordingSink::field(p, "offset"));
        LONGS_EQUAL(length, RecordingSink::field(p, "total_length"));
        const auto n = static_cast<std::size_t>(RecordingSink::field(p, "length"));
        for (std::size_t i = 0; i < n; ++i) {
            joined.push_back(static_cast<std::uint8_t>(RecordingSink::field(p, "data", i)));
        }
    }
    LONGS_EQUAL(length, joined.size());
    CHECK(std::equal(joined.begin(), joined.end(), image));
    CHECK(sink.packets.size() > 1);  // the coarse map takes several packets
}

TEST(TableTelemetry, NoImageNoPacket) {
    CHECK(core::Status::kNotFound == telemetry.sendDump(tables::TableId::kPlanner, true, sink));
    LONGS_EQUAL(0, sink.packets.size());
}

TEST(TableTelemetry, HousekeepingCarriesTheServicesCounters) {
    cmdtlm::HK_Tlm hk{};
    telemetry.fillHousekeeping(hk);
    LONGS_EQUAL(service.activations(), hk.table_activations);
    LONGS_EQUAL(service.rejects(), hk.table_rejects);
    CHECK(hk.table_activations > 0);  // the defaults, at start-up
}
