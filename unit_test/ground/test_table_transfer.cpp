// Table upload and download over a ground session: chunking, the command
// sequence, stopping at a rejection, and reassembling TABLE_DUMP telemetry.
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/core/byte_codec.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/command_encoder.hpp"
#include "ground/ground_session.hpp"
#include "ground/sequence_store.hpp"
#include "ground/table_compiler.hpp"
#include "ground/table_transfer.hpp"
#include "ground/telemetry_decoder.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

using Rig = test::SessionRig;

std::vector<std::uint8_t> geometryImage() { return ground::compileTableSource("tables/rover_geometry.toml"); }

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

ground::DecodedPacket dumpPacket(std::uint16_t table, std::uint8_t buffer, std::uint16_t total, std::uint16_t offset,
                                 const std::vector<std::uint8_t>& data) {
    cmdtlm::TABLE_DUMP_Tlm d{};
    d.table_id = table;
    d.buffer = buffer;
    d.total_length = total;
    d.offset = offset;
    d.length = static_cast<std::uint16_t>(data.size());
    for (std::size_t i = 0; i < data.size(); ++i) {
        d.data[i] = data[i];
    }
    return ground::decodeTelemetry(test::telemetryPacket(d));
}

}  // namespace

TEST_GROUP(GroundTableTransfer){};

TEST(GroundTableTransfer, ImagesAreCutIntoChunksOfAtMost200Bytes) {
    std::vector<std::uint8_t> image(450);
    for (std::size_t i = 0; i < image.size(); ++i) {
        image[i] = static_cast<std::uint8_t>(i);
    }
    const auto chunks = ground::tableLoadChunks(3, image);
    CHECK_EQUAL(3U, chunks.size());
    std::vector<std::uint8_t> joined;
    for (std::size_t i = 0; i < chunks.size(); ++i) {
        cmdtlm::TABLE_LOAD_Args a{};
        core::BeReader r(chunks[i].data(), chunks[i].size());
        cmdtlm::decodeArgs(r, &a);
        CHECK_EQUAL(3, a.table_id);
        CHECK_EQUAL(i * 200, a.offset);
        CHECK_EQUAL(i < 2 ? 200 : 50, a.data_length);
        joined.insert(joined.end(), a.data, a.data + a.data_length);
    }
    CHECK_TRUE(joined == image);
}

TEST(GroundTableTransfer, TableIdComesFromTheImageHeader) {
    const auto image = geometryImage();
    CHECK_TRUE(ground::imageTableId(image).has_value());
    CHECK_EQUAL(1, *ground::imageTableId(image));
    CHECK_FALSE(ground::imageTableId({1, 2, 3}).has_value());
}

TEST(GroundTableTransfer, TablesByNameOrId) {
    CHECK_TRUE(ground::lookupTable("rover_geometry") == tables::findTable(tables::TableId::kRoverGeometry));
    CHECK_TRUE(ground::lookupTable("1") == tables::findTable(tables::TableId::kRoverGeometry));
    CHECK_TRUE(ground::lookupTable("PLANNER") != nullptr);
    CHECK_TRUE(ground::lookupTable("99") == nullptr);
    CHECK_TRUE(ground::lookupTable("NOPE") == nullptr);
}

TEST(GroundTableTransfer, LoadValidateActivateSendsTheImageAndStopsNowhere) {
    Rig rig;
    const auto image = geometryImage();
    CHECK_EQUAL(0, ground::loadTableImage(rig.session, image, true, false, rig.out, rig.err));
    CHECK_TRUE(rig.rover.loadedImage == image);
    const std::size_t chunks = (image.size() + 199) / 200;
    CHECK_EQUAL(chunks + 2, rig.rover.executed.size());
    STRCMP_EQUAL("TABLE_VALIDATE", rig.rover.executed[chunks].c_str());
    STRCMP_EQUAL("TABLE_ACTIVATE", rig.rover.executed[chunks + 1].c_str());
    CHECK_TRUE(contains(rig.out.str(), "loaded, validated and activated"));
    STRCMP_EQUAL("", rig.err.str().c_str());
}

TEST(GroundTableTransfer, ARejectionStopsTheLoadWithItsReason) {
    Rig rig;
    rig.rover.mode = cmdtlm::Mode::kAutonomous;  // table loads are refused in AUTONOMOUS
    CHECK_EQUAL(3, ground::loadTableImage(rig.session, geometryImage(), true, false, rig.out, rig.err));
    CHECK_EQUAL(1U, rig.rover.verdicts.size());
    CHECK_TRUE(contains(rig.err.str(), "TABLE_LOAD 1/"));
    CHECK_TRUE(contains(rig.err.str(), "rejected: wrong_mode"));
}

TEST(GroundTableTransfer, ABadImageIsNotSentUnlessForced) {
    Rig rig;
    auto image = geometryImage();
    image.back() ^= 0xFF;  // CRC no longer matches
    CHECK_EQUAL(1, ground::loadTableImage(rig.session, image, false, false, rig.out, rig.err));
    CHECK_EQUAL(0U, rig.link.sent.size());
    CHECK_TRUE(contains(rig.err.str(), "does not pass the table checks"));

    // Forced, the rover's validation refuses it and the reason is shown.
    CHECK_EQUAL(3, ground::loadTableImage(rig.session, image, false, true, rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "TABLE_VALIDATE: TABLE_VALIDATE"));
    CHECK_TRUE(contains(rig.err.str(), "rejected: execution_failed (detail 7: table bad CRC)"));
}

TEST(GroundTableTransfer, NoAcknowledgementIsALinkFailure) {
    Rig rig;
    rig.rover.answer = false;
    CHECK_EQUAL(1, ground::loadTableImage(rig.session, geometryImage(), false, false, rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "no acknowledgement within 0.3 s"));
}

TEST(GroundTableTransfer, DumpAssemblerCollectsChunksInAnyOrder) {
    std::vector<std::uint8_t> image(260);
    for (std::size_t i = 0; i < image.size(); ++i) {
        image[i] = static_cast<std::uint8_t>(i * 3);
    }
    ground::TableDumpAssembler assembler(2, true);
    CHECK_FALSE(assembler.complete());
    CHECK_FALSE(assembler.add(dumpPacket(2, 0, 260, 0, {1})));  // the active buffer: not ours
    CHECK_FALSE(assembler.add(dumpPacket(3, 1, 260, 0, {1})));  // another table
    CHECK_TRUE(assembler.add(dumpPacket(2, 1, 260, 200, std::vector<std::uint8_t>(image.begin() + 200, image.end()))));
    CHECK_FALSE(assembler.complete());
    CHECK_EQUAL(60U, assembler.bytesReceived());
    CHECK_FALSE(assembler.add(dumpPacket(2, 1, 100, 0, {1})));   // total length changed
    CHECK_FALSE(assembler.add(dumpPacket(2, 1, 260, 250, std::vector<std::uint8_t>(20))));  // beyond the end
    CHECK_TRUE(assembler.add(dumpPacket(2, 1, 260, 0, std::vector<std::uint8_t>(image.begin(), image.begin() + 200))));
    CHECK_TRUE(assembler.complete());
    CHECK_TRUE(assembler.image() == image);
}

TEST(GroundTableTransfer, DumpWritesTheImageAndPrintsItDecoded) {
    Rig rig;
    rig.rover.tableImage = geometryImage();
    const std::string path = rig.dir.file("dump.tbl");
    CHECK_EQUAL(0, ground::dumpTableImage(rig.session, *ground::lookupTable("ROVER_GEOMETRY"), false, path, rig.out,
                                          rig.err));
    STRCMP_EQUAL("", rig.err.str().c_str());
    CHECK_TRUE(ground::readTableImageFile(path) == rig.rover.tableImage);
    CHECK_TRUE(contains(rig.out.str(), "ROVER_GEOMETRY (id 1)"));
    CHECK_TRUE(contains(rig.out.str(), "wrote " + path));
}

TEST(GroundTableTransfer, IncompleteDumpIsReported) {
    Rig rig;
    rig.rover.tableImage = geometryImage();
    // Drop the rover's dump chunks: only the ack and HK arrive.
    rig.rover.answer = true;
    struct DroppingLink : ground::GroundLink {
        explicit DroppingLink(test::FakeRoverLink& inner) : inner_(inner) {}
        void send(const std::vector<std::uint8_t>& p) override { inner_.send(p); }
        std::optional<std::vector<std::uint8_t>> receive(double t) override {
            for (;;) {
                auto p = inner_.receive(t);
                if (!p || ground::decodeTelemetry(*p).apid != cmdtlm::TABLE_DUMP_Tlm::kApid) {
                    return p;
                }
            }
        }
        std::string describe() const override { return "dropping"; }
        test::FakeRoverLink& inner_;
    } dropping(rig.link);
    ground::GroundSession session(dropping, rig.store, ground::labKeyAuth(), 0.2);
    CHECK_EQUAL(1, ground::dumpTableImage(session, *ground::lookupTable("1"), false, "", rig.out, rig.err));
    CHECK_TRUE(contains(rig.err.str(), "dump incomplete: 0 of ? bytes"));
}
