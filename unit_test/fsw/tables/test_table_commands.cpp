// The table commands (APID 0x183): load, validate, activate and dump through
// the table service, each answered with TABLE_STATUS, a refusal's reason as
// CMD_ACK.detail; RESET_COUNTERS zeroes the service's counters.
#include <cstring>

#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_commands.hpp"
#include "fsw/tables/table_image.hpp"
#include "unit_test/support/app_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;
using test::RecordingSink;

TEST_GROUP(TableCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    tables::TableService service{events};
    tables::TableTelemetry telemetry{service};
    RecordingSink sink;
    tables::TableCommands commands{service, telemetry, sink};
    void setup() override {
        CHECK(core::isOk(service.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount)));
    }
    cmdtlm::CommandOutcome load(const std::uint8_t* image, std::size_t length) {
        cmdtlm::TABLE_LOAD_Args a{};
        a.table_id = 1;
        a.offset = 0;
        a.data_length = static_cast<std::uint16_t>(length);
        std::memcpy(a.data, image, length);
        const test::AcceptedCommand c(CommandCode::TABLE_LOAD, a);
        return commands.execute(c.verdict());
    }
    cmdtlm::CommandOutcome run(CommandCode code, std::uint16_t table) {
        const test::AcceptedCommand c(code, cmdtlm::TABLE_VALIDATE_Args{table});
        return commands.execute(c.verdict());
    }
};

TEST(TableCommands, OwnsTheTablesApid) { LONGS_EQUAL(0x183, commands.apid()); }

TEST(TableCommands, ANewImageIsLoadedValidatedAndActivatedEachAnsweredWithItsStatus) {
    tables::RoverGeometryTable g = service.roverGeometry();
    g.max_wheel_speed_rad_s = 3.0F;
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t n = tables::encodeTable(g, 7, image, sizeof image);
    CHECK(n > 0 && n <= 200);  // one chunk
    CHECK_TRUE(load(image, n).ok);
    CHECK_TRUE(run(CommandCode::TABLE_VALIDATE, 1).ok);
    CHECK_TRUE(run(CommandCode::TABLE_ACTIVATE, 1).ok);
    LONGS_EQUAL(3, sink.count<cmdtlm::TABLE_STATUS_Tlm>());
    service.run(core::FrameContext{});
    DOUBLES_EQUAL(3.0, service.roverGeometry().max_wheel_speed_rad_s, 0.0);
    (void)run(CommandCode::TABLE_VALIDATE, 1);  // its status shows the version now active
    const RecordingSink::Packet& status = sink.last<cmdtlm::TABLE_STATUS_Tlm>();
    DOUBLES_EQUAL(1, RecordingSink::field(status, "table_id"), 0.0);
    DOUBLES_EQUAL(7, RecordingSink::field(status, "active_version"), 0.0);
}

TEST(TableCommands, ABadImageIsRefusedWithTheReasonAsDetail) {
    std::uint8_t junk[40] = {};
    CHECK_TRUE(load(junk, sizeof junk).ok);  // a chunk is only bytes
    const cmdtlm::CommandOutcome o = run(CommandCode::TABLE_VALIDATE, 1);
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(static_cast<int>(tables::TableReject::kBadMagic), o.detail);
    DOUBLES_EQUAL(static_cast<double>(tables::TableReject::kBadMagic),
                  RecordingSink::field(sink.last<cmdtlm::TABLE_STATUS_Tlm>(), "last_reject"), 0.0);
    LONGS_EQUAL(1, service.rejects());
}

TEST(TableCommands, ADumpSendsTheImageThenItsStatusAndAMissingImageIsNotLoaded) {
    const test::AcceptedCommand active(CommandCode::TABLE_DUMP, cmdtlm::TABLE_DUMP_Args{1, 0});
    CHECK_TRUE(commands.execute(active.verdict()).ok);
    CHECK(sink.count<cmdtlm::TABLE_DUMP_Tlm>() >= 1);
    LONGS_EQUAL(cmdtlm::TABLE_STATUS_Tlm::kApid, sink.packets.back().apid);
    const test::AcceptedCommand inactive(CommandCode::TABLE_DUMP, cmdtlm::TABLE_DUMP_Args{1, 1});
    const cmdtlm::CommandOutcome o = commands.execute(inactive.verdict());
    CHECK_FALSE(o.ok);
    LONGS_EQUAL(static_cast<int>(tables::TableReject::kNotLoaded), o.detail);
}

TEST(TableCommands, ResetCountersZeroesTheServicesCounters) {
    std::uint8_t junk[40] = {};
    (void)load(junk, sizeof junk);
    (void)run(CommandCode::TABLE_VALIDATE, 1);
    CHECK(service.rejects() > 0);
    commands.resetCounters();
    LONGS_EQUAL(0, service.rejects());
    LONGS_EQUAL(0, service.activations());
}
