// The site map service through its commands (APID 0x186): an image uploaded
// in MAP_LOAD chunks and put in force by MAP_COMMIT, each answered with
// SITE_MAP; and every refusal the issue names (a bad CRC, a gap, too many
// rocks, a rock outside the site, a non-convex or clockwise rock) with its
// reason (CMD_ACK.detail at once, or SITE_MAP.last_refusal when the sliced
// commit ends), its counter and its event, the map in force kept. A commit of
// 20 000 rocks runs in slices, one a command-task run, with the map in force
// used until the new one is whole; chunks and commits meanwhile are refused
// and MAP_ABORT cancels it.
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
        service = new site_map::SiteMapService(events);  // 6 MB: off the stack
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
    cmdtlm::CommandOutcome startCommit(std::size_t length, std::uint32_t crc) {
        const test::AcceptedCommand c(CommandCode::MAP_COMMIT,
                                      cmdtlm::MAP_COMMIT_Args{static_cast<std::uint32_t>(length), crc});
        return commands->execute(c.verdict());
    }
    // Command-task runs until the commit under way ends (SITE_MAP sent with
    // commit_phase 0): the runs it took.
    std::size_t runCommit() {
        const std::size_t packets = sink.count<cmdtlm::SITE_MAP_Tlm>();
        std::size_t runs = 0;
        while (sink.count<cmdtlm::SITE_MAP_Tlm>() == packets && runs < 1000) {
            commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);
            ++runs;
        }
        DOUBLES_EQUAL(0, field("commit_phase"), 0.0);
        return runs;
    }
    // MAP_COMMIT as the ground sees it: refused at once (CMD_ACK), or
    // accepted and then in force or refused when its slices end (SITE_MAP).
    cmdtlm::CommandOutcome commit(std::size_t length, std::uint32_t crc) {
        const cmdtlm::CommandOutcome started = startCommit(length, crc);
        if (!started.ok) {
            return started;
        }
        (void)runCommit();
        const auto why = static_cast<std::int16_t>(field("last_refusal"));
        return why == 0 ? cmdtlm::CommandOutcome{} : cmdtlm::commandFailed(why);
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

// 20 000 rocks on a square kilometre (about 0.8 MB, 4 100 chunks): the
// commit takes a slice each command-task run, CRC-32 then check then load,
// and until the run that ends it the map in force (100 rocks) is the one
// the service gives readers; then it is the new one, told by SITE_MAP.
TEST(SiteMapCommands, ACommitOfTwentyThousandRocksRunsInSlicesAndTheMapInForceServesUntilItEnds) {
    const std::vector<std::uint8_t> small = image(test::randomField(100, 100.0F, 1));
    CHECK_TRUE(upload(small));
    CHECK_TRUE(commit(small).ok);
    const std::uint32_t revision = service->map().revision();
    const std::vector<std::uint8_t> big = image(test::randomField(20000, 1000.0F, 2));
    CHECK(big.size() > 540832);
    CHECK_TRUE(upload(big));  // offsets past the 540 831 the dictionary once capped them at
    (void)test::drainEventsWithId(events, site_map::events::kMapLoaded);
    CHECK_TRUE(startCommit(big.size(), core::crc32(big.data(), big.size())).ok);
    DOUBLES_EQUAL(1, field("commit_phase"), 0.0);  // the answer at once: started, CRC first
    DOUBLES_EQUAL(2, field("commits_started"), 0.0);
    std::size_t runs = 0;
    std::uint8_t phase = 1;
    std::size_t runsIn[4] = {};
    while (service->commitPhase() != site_map::CommitPhase::kNone && runs < 1000) {
        LONGS_EQUAL(revision, service->map().revision());
        LONGS_EQUAL(100, service->map().rockCount());
        const auto now = static_cast<std::uint8_t>(service->commitPhase());
        CHECK_TEXT(now >= phase, "phases in order: CRC, check, load");
        phase = now;
        ++runsIn[now];
        commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);
        ++runs;
    }
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kMapLoaded));
    LONGS_EQUAL(20000, service->map().rockCount());
    CHECK(service->map().revision() != revision);
    DOUBLES_EQUAL(0, field("commit_phase"), 0.0);
    DOUBLES_EQUAL(static_cast<double>(runs), field("commit_runs"), 0.0);
    DOUBLES_EQUAL(2, field("maps_loaded"), 0.0);
    // Each slice did at most its share: the CRC of 0.8 MB took
    // ceil(bytes / kCommitCrcBytes) runs, the check ceil(20 000 /
    // kCommitCheckRecords), the load at least 3 passes of 20 000 rocks in
    // kCommitStageUnits.
    LONGS_EQUAL((big.size() + site_map::kCommitCrcBytes - 1) / site_map::kCommitCrcBytes, runsIn[1]);
    LONGS_EQUAL((20000 + site_map::kCommitCheckRecords - 1) / site_map::kCommitCheckRecords, runsIn[2]);
    CHECK(runsIn[3] >= 3 * 20000 / site_map::kCommitStageUnits);
}

TEST(SiteMapCommands, DuringACommitChunksAndCommitsAreRefusedAndAbortCancelsItKeepingTheMapInForce) {
    const std::vector<std::uint8_t> small = image(test::randomField(100, 100.0F, 3));
    CHECK_TRUE(upload(small));
    CHECK_TRUE(commit(small).ok);
    const std::uint32_t revision = service->map().revision();
    const std::vector<std::uint8_t> big = image(test::randomField(5000, 1000.0F, 4));
    CHECK_TRUE(upload(big));
    CHECK_TRUE(startCommit(big.size(), core::crc32(big.data(), big.size())).ok);
    commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);  // the CRC under way
    cmdtlm::CommandOutcome out = loadChunk(big, 0, 200);
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kCommitUnderWay), out.detail);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kChunkRefused));
    out = startCommit(big.size(), core::crc32(big.data(), big.size()));
    LONGS_EQUAL(static_cast<int>(UploadRefusal::kCommitUnderWay), out.detail);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kCommitRefused));
    // Into the check, then MAP_ABORT: cancelled, nothing put in force.
    while (service->commitPhase() == site_map::CommitPhase::kCrc) {
        commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);
    }
    LONGS_EQUAL(static_cast<int>(site_map::CommitPhase::kCheck), static_cast<int>(service->commitPhase()));
    const test::AcceptedCommand abort(CommandCode::MAP_ABORT);
    CHECK_TRUE(commands->execute(abort.verdict()).ok);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kUploadAborted));
    DOUBLES_EQUAL(0, field("commit_phase"), 0.0);
    DOUBLES_EQUAL(1, field("commits_cancelled"), 0.0);   // the ground tells a cancel from telemetry
    for (int i = 0; i < 50; ++i) {
        commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);
    }
    LONGS_EQUAL(revision, service->map().revision());
    LONGS_EQUAL(100, service->map().rockCount());
    LONGS_EQUAL(0, test::drainEventsWithId(events, site_map::events::kMapLoaded));
    // The same image uploaded again goes in force.
    CHECK_TRUE(upload(big));
    CHECK_TRUE(commit(big).ok);
    LONGS_EQUAL(5000, service->map().rockCount());
}

// The dictionary's ranges reach the largest image (MAP_LOAD's offset was
// once capped at 540 831 bytes, a map of about 8 000 rocks).
TEST(SiteMapCommands, TheDictionaryRangesCoverTheLargestImage) {
    const cmdtlm::CommandDesc& load = cmdtlm::describe(CommandCode::MAP_LOAD);
    DOUBLES_EQUAL(static_cast<double>(site_map::kMaxSiteMapImageSize - 1), load.args[0].max, 0.0);
    const cmdtlm::CommandDesc& commitDesc = cmdtlm::describe(CommandCode::MAP_COMMIT);
    DOUBLES_EQUAL(static_cast<double>(site_map::kMaxSiteMapImageSize), commitDesc.args[0].max, 0.0);
}

// The mode is checked when MAP_COMMIT is taken and again every slice: a
// commit still under way when the rover is put in AUTONOMOUS (or MANUAL) is
// refused (8) in the next run, the map in force kept: the rover never
// changes maps while driving.
TEST(SiteMapCommands, ACommitUnderWayWhenTheRoverStartsDrivingIsRefusedAndTheMapInForceKept) {
    const std::vector<std::uint8_t> small = image(test::randomField(100, 100.0F, 5));
    CHECK_TRUE(upload(small));
    CHECK_TRUE(commit(small).ok);
    const std::uint32_t revision = service->map().revision();
    const std::vector<std::uint8_t> big = image(test::randomField(5000, 1000.0F, 6));
    CHECK_TRUE(upload(big));
    CHECK_TRUE(startCommit(big.size(), core::crc32(big.data(), big.size())).ok);
    while (service->commitPhase() != site_map::CommitPhase::kStage) {
        commands->serviceOnboardRequests(cmdtlm::Mode::kStandby);
    }
    (void)test::drainEventsWithId(events, site_map::events::kCommitRefused);
    commands->serviceOnboardRequests(cmdtlm::Mode::kAutonomous);
    DOUBLES_EQUAL(0, field("commit_phase"), 0.0);   // told at once
    DOUBLES_EQUAL(static_cast<double>(UploadRefusal::kDriving), field("last_refusal"), 0.0);
    DOUBLES_EQUAL(1, field("commits_refused"), 0.0);
    LONGS_EQUAL(1, test::drainEventsWithId(events, site_map::events::kCommitRefused));
    for (int i = 0; i < 20; ++i) {
        commands->serviceOnboardRequests(cmdtlm::Mode::kSafe);
    }
    LONGS_EQUAL(revision, service->map().revision());
    LONGS_EQUAL(100, service->map().rockCount());
    // Nothing under way, nothing refused: driving with no commit says nothing.
    commands->serviceOnboardRequests(cmdtlm::Mode::kManual);
    LONGS_EQUAL(0, test::drainEventsWithId(events, site_map::events::kCommitRefused));
    // The upload is open again as it was: back in STANDBY the same commit
    // goes in force; RESET_COUNTERS on the way leaves the commits' own counts.
    DOUBLES_EQUAL(1, field("upload_open"), 0.0);
    commands->resetCounters();
    CHECK_TRUE(commit(big).ok);
    LONGS_EQUAL(5000, service->map().rockCount());
    DOUBLES_EQUAL(3, field("commits_started"), 0.0);   // the small map's, the refused one, this one
    DOUBLES_EQUAL(0, field("commits_refused"), 0.0);   // zeroed by the reset
}
