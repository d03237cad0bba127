// The site map service through its commands (APID 0x186): an image uploaded
// in MAP_LOAD chunks and put in force by MAP_COMMIT, each answered with
// SITE_MAP; and every refusal the issue names (a bad CRC, a gap, too many
// rocks, a rock outside the site, a non-convex or clockwise rock) with its
// reason (CMD_ACK.detail and SITE_MAP.last_refusal), its counter and its
// event, the map in force kept.
#include <algorithm>
#include <cstring>
#include <vector>

#include "fsw/core/crc32.hpp"
#include "fsw/site_map/site_map_commands.hpp"
#include "fsw/site_map/site_map_events.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"
#include "unit_test/support/app_test_support.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using cmdtlm::CommandCode;
using site_map::UploadRefusal;
using test::RecordingSink;

namespace {

site_map::SiteMapService* service = nullptr;

std::vector<std::uint8_t> image(const ground::SiteMapSpec& spec) { return ground::encodeSiteMap(spec); }

}  // namespace

TEST_GROUP(SiteMapCommands) {
    core::VirtualClock clock;
    core::EventLog events{clock};
    RecordingSink sink;
    site_map::SiteMapTelemetry* telemetry = nullptr;
    site_map::SiteMapCommands* commands = nullptr;

    void setup() override {
        service = new site_map::SiteMapService(events);  // 1.5 MB: off the stack
        telemetry = new site_map::SiteMapTelemetry(*service);
        commands = new site_map::SiteMapCommands(*service, *telemetry, sink);
    }
    void teardown() override {
        delete commands;
        delete telemetry;
        delete service;
    }

    cmdtlm::CommandOutcome loadChunk(const std::vector<std::uint8_t>& img, std::size_t offset, std::size_t length) {
        cmdtlm::MAP_LOAD_Args a{};
        a.offset = static_cast<std::uint32_t>(offset);
        a.data_length = static_cast<std::uint16_t>(length);
        std::memcpy(a.data, img.data() + offset, length);
        const test::AcceptedCommand c(CommandCode::MAP_LOAD, a);
        return commands->execute(c.verdict());
    }
    // Every chunk, 200 bytes each; true when all were taken.
    bool upload(const std::vector<std::uint8_t>& img) {
        bool ok = true;
        for (std::size_t at = 0; at < img.size(); at += 200) {
            ok = loadChunk(img, at, std::min<std::size_t>(200, img.size() - at)).ok && ok;
        }
        return ok;
    }
    cmdtlm::CommandOutcome commit(std::size_t length, std::uint32_t crc) {
        const test::AcceptedCommand c(CommandCode::MAP_COMMIT,
                                      cmdtlm::MAP_COMMIT_Args{static_cast<std::uint32_t>(length), crc});
        return commands->execute(c.verdict());
    }
    cmdtlm::CommandOutcome commit(const std::vector<std::uint8_t>& img) {
        return commit(img.size(), core::crc32(img.data(), img.size()));
    }
    double field(const char* name) { return RecordingSink::field(sink.last<cmdtlm::SITE_MAP_Tlm>(), name); }
    // A refused commit of img: the detail, SITE_MAP's reason, one more refusal
    // counted, one event 592, and the map in force as it was.
    void expectCommitRefused(const std::vector<std::uint8_t>& img, std::uint8_t code, const char* what) {
        const double refusedBefore = sink.count<cmdtlm::SITE_MAP_Tlm>() > 0 ? field("commits_refused") : 0.0;
        const std::uint32_t revision = service->map().revision();
        const std::size_t rocks = service->map().rockCount();
        CHECK_TRUE(upload(img));
        const cmdtlm::CommandOutcome out = commit(img);
        CHECK_FALSE_TEXT(out.ok, what);
        LONGS_EQUAL_TEXT(code, out.detail, what);
        LONGS_EQUAL_TEXT(code, static_cast<int>(field("last_refusal")), what);
        DOUBLES_EQUAL(refusedBefore + 1, field("commits_refused"), 0.0);
        LONGS_EQUAL_TEXT(1, test::drainEventsWithId(events, site_map::events::kCommitRefused), what);
        LONGS_EQUAL(revision, service->map().revision());
        LONGS_EQUAL(rocks, service->map().rockCount());
    }
};

TEST(SiteMapCommands, OwnsTheSiteMapApid) { LONGS_EQUAL(0x186, commands->apid()); }

// 1 000 rocks on 500 m x 500 m: 41 KB, 207 chunks; SITE_MAP after each command.
TEST(SiteMapCommands, AnImageUploadedInChunksAndCommittedIsInForce) {
    const std::vector<std::uint8_t> img = image(test::randomField(1000, 500.0F, 9));
    CHECK_TRUE(upload(img));
    const std::size_t chunks = (img.size() + 199) / 200;
    LONGS_EQUAL(chunks, sink.count<cmdtlm::SITE_MAP_Tlm>());
    DOUBLES_EQUAL(static_cast<double>(img.size()), field("upload_bytes"), 0.0);
    DOUBLES_EQUAL(1, field("upload_open"), 0.0);
    DOUBLES_EQUAL(0, field("revision"), 0.0);
    CHECK_TRUE(commit(img).ok);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kMapLoaded));
    DOUBLES_EQUAL(1, field("revision"), 0.0);
    DOUBLES_EQUAL(1000, field("rocks"), 0.0);
    DOUBLES_EQUAL(500, field("x_max"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(img.size()), field("map_bytes"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(core::crc32(img.data(), img.size())), field("map_crc32"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(chunks), field("chunks_taken"), 0.0);
    DOUBLES_EQUAL(1, field("maps_loaded"), 0.0);
    DOUBLES_EQUAL(0, field("upload_open"), 0.0);
    LONGS_EQUAL(1000, service->map().rockCount());
    // One commit an upload.
    const cmdtlm::CommandOutcome again = commit(img);
    CHECK_FALSE(again.ok);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kNothingUploaded), again.detail);
}

TEST(SiteMapCommands, ABadCrcOrLengthIsRefusedAndTheMapInForceKept) {
    const std::vector<std::uint8_t> good = image(test::randomField(100, 100.0F, 1));
    CHECK_TRUE(upload(good));
    CHECK_TRUE(commit(good).ok);
    const std::vector<std::uint8_t> next = image(test::randomField(200, 100.0F, 2));
    CHECK_TRUE(upload(next));
    cmdtlm::CommandOutcome out = commit(next.size(), core::crc32(next.data(), next.size()) ^ 1U);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kBadCrc), out.detail);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kCommitRefused));
    out = commit(next.size() - 1, core::crc32(next.data(), next.size() - 1));
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kBadLength), out.detail);
    DOUBLES_EQUAL(2, field("commits_refused"), 0.0);
    LONGS_EQUAL(100, service->map().rockCount());
    // The upload is still whole: the right CRC puts it in force.
    CHECK_TRUE(commit(next).ok);
    LONGS_EQUAL(200, service->map().rockCount());
}

TEST(SiteMapCommands, AGapSpoilsTheUploadUntilOffsetZeroAgain) {
    const std::vector<std::uint8_t> img = image(test::randomField(100, 100.0F, 3));
    CHECK_TRUE(loadChunk(img, 0, 200).ok);
    cmdtlm::CommandOutcome out = loadChunk(img, 400, 200);  // 200 .. 400 never sent
    CHECK_FALSE(out.ok);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kGap), out.detail);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kChunkRefused));
    DOUBLES_EQUAL(1, field("chunks_refused"), 0.0);
    out = loadChunk(img, 200, 200);  // too late: spoiled
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kSpoiled), out.detail);
    out = commit(img);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kSpoiled), out.detail);
    CHECK_FALSE(service->map().loaded());
    // From offset 0 again: whole, and in force.
    CHECK_TRUE(upload(img));
    CHECK_TRUE(commit(img).ok);
}

TEST(SiteMapCommands, EachBadImageIsRefusedWithItsReasonCounterAndEvent) {
    CHECK_TRUE(upload(image(test::randomField(10, 100.0F, 4))));
    CHECK_TRUE(commit(image(test::randomField(10, 100.0F, 4))).ok);
    (void)test::drainEventsWithId(events, site_map::events::kMapLoaded);
    // Too many rocks: 8 193 triangles.
    ground::SiteMapSpec many;
    many.site = {0.0F, 0.0F, 1000.0F, 1000.0F};
    for (std::size_t i = 0; i <= site_map::kMaxSiteRocks; ++i) {
        const float x = 5.0F + static_cast<float>(i % 90) * 11.0F;
        const float y = 5.0F + static_cast<float>(i / 90) * 10.0F;
        many.rocks.push_back(test::regularRock(x, y, 0.5F, 3));
    }
    expectCommitRefused(image(many), site_map::refusalCode(site_map::SiteMapReject::kTooManyRocks), "too many");
    // A rock outside the site, the 8th.
    ground::SiteMapSpec spec = test::randomField(20, 100.0F, 5);
    spec.rocks[7] = test::regularRock(99.8F, 50.0F, 0.5F);
    expectCommitRefused(image(spec), site_map::refusalCode(site_map::SiteMapReject::kOutsideSite), "outside");
    DOUBLES_EQUAL(7, field("last_refusal_item"), 0.0);
    // Not convex.
    spec = test::randomField(20, 100.0F, 6);
    spec.rocks[3] = {{10, 10}, {14, 10}, {11, 11}, {10, 14}};
    expectCommitRefused(image(spec), site_map::refusalCode(site_map::SiteMapReject::kNotConvex), "not convex");
    DOUBLES_EQUAL(3, field("last_refusal_item"), 0.0);
    // Clockwise.
    spec = test::randomField(20, 100.0F, 7);
    std::reverse(spec.rocks[12].begin(), spec.rocks[12].end());
    expectCommitRefused(image(spec), site_map::refusalCode(site_map::SiteMapReject::kClockwise), "clockwise");
    DOUBLES_EQUAL(12, field("last_refusal_item"), 0.0);
    LONGS_EQUAL(10, service->map().rockCount());
}

TEST(SiteMapCommands, AbortDropsTheUploadAndIsRefusedWithNoneOpen) {
    const std::vector<std::uint8_t> img = image(test::randomField(50, 100.0F, 8));
    CHECK_TRUE(loadChunk(img, 0, 200).ok);
    const test::AcceptedCommand abort(CommandCode::MAP_ABORT);
    CHECK_TRUE(commands->execute(abort.verdict()).ok);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kUploadAborted));
    DOUBLES_EQUAL(0, field("upload_open"), 0.0);
    DOUBLES_EQUAL(1, field("uploads_aborted"), 0.0);
    const cmdtlm::CommandOutcome out = commands->execute(abort.verdict());
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kNothingUploaded), out.detail);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kAbortRefused));
    DOUBLES_EQUAL(1, field("aborts_refused"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(UploadRefusal::kNothingUploaded), field("last_refusal"), 0.0);
    // RESET_COUNTERS zeroes them.
    commands->resetCounters();
    CHECK_TRUE(loadChunk(img, 0, 200).ok);
    DOUBLES_EQUAL(1, field("chunks_taken"), 0.0);
    DOUBLES_EQUAL(0, field("uploads_aborted"), 0.0);
}

TEST(SiteMapCommands, AChunkPastTheLargestImageOverflows) {
    std::vector<std::uint8_t> img(site_map::kMaxSiteMapImageSize + 200, 0);
    CHECK_TRUE(loadChunk(img, 0, 200).ok);
    // Chunks up to the end, then one past it (offsets must be contiguous).
    std::size_t at = 200;
    while (at + 200 <= site_map::kMaxSiteMapImageSize) {
        CHECK_TRUE(loadChunk(img, at, 200).ok);
        at += 200;
    }
    const cmdtlm::CommandOutcome out = loadChunk(img, at, 200);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kOverflow), out.detail);
}
