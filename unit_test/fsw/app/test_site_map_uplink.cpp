// The site map over the ground link, through the whole flight application
// (ground_station_rig.hpp): a generated field's image sent as MAP_LOAD chunks
// the way rse-ground sends them (ground/map_transfer.hpp), committed in SAFE
// and in force when its slices end, a few command-task runs later; a commit
// while AUTONOMOUS refused by its mode; a bad CRC found in the commit's
// slices and refused by the service with SITE_MAP's reason, the map in force
// kept.
#include <vector>

#include "fsw/cmdtlm/command_verdict.hpp"
#include "fsw/core/crc32.hpp"
#include "fsw/site_map/site_map_events.hpp"
#include "fsw/site_map/site_map_upload.hpp"
#include "ground/map_transfer.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/app/ground_station_rig.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"

using namespace rse;
using namespace rse::cmdtlm;
using namespace rse::test::ground;

TEST_GROUP_BASE(SiteMapUplink, GroundStation) {
    // Every chunk, one a frame (rse-ground waits for each acknowledgement).
    void uploadChunks(const std::vector<std::uint8_t>& image) {
        for (const std::vector<std::uint8_t>& chunk : rse::ground::mapLoadChunks(image)) {
            send("MAP_LOAD", chunk);
            runFrames(1);
            expectAccepted("MAP_LOAD");
        }
    }
    // Frames until a SITE_MAP says the commit under way ended: the frames.
    int runUntilCommitEnds() {
        for (int frames = 1; frames <= 100; ++frames) {
            runFrames(1);
            if (field(last("SITE_MAP"), "commit_phase") == 0.0) {
                return frames;
            }
        }
        FAIL("no SITE_MAP told the commit's end in 100 frames");
        return 0;
    }
};

TEST(SiteMapUplink, AGeneratedFieldSentInChunksIsInForceAndACommitWhileDrivingIsRefused) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(300, 100.0F, 1));
    uploadChunks(image);
    // AUTONOMOUS: the rover does not change maps while driving (the command's modes).
    send("SET_MODE", {2});
    send("MAP_COMMIT", rse::ground::mapCommitArgs(image));
    runFrames(2);
    const Packet& refused = last("CMD_ACK");
    LONGS_EQUAL(findCommand("MAP_COMMIT")->apid, static_cast<long>(field(refused, "apid")));
    LONGS_EQUAL(static_cast<long>(CommandReject::kWrongMode), static_cast<long>(field(refused, "reason")));
    CHECK_FALSE(fsw.siteMap().map().loaded());
    // SAFE: taken, and in force.
    send("SET_MODE", {0});
    send("MAP_COMMIT", rse::ground::mapCommitArgs(image));
    runFrames(1);
    expectAccepted("MAP_COMMIT");
    LONGS_EQUAL(1, static_cast<long>(field(last("SITE_MAP"), "commit_phase")));  // under way: the CRC-32 first
    CHECK_FALSE(fsw.siteMap().map().loaded());
    CHECK(runUntilCommitEnds() >= 2);   // CRC, check, load: a slice a frame
    CHECK_TRUE(fsw.siteMap().map().loaded());
    LONGS_EQUAL(300, fsw.siteMap().map().rockCount());
    const Packet& status = last("SITE_MAP");
    LONGS_EQUAL(300, static_cast<long>(field(status, "rocks")));
    LONGS_EQUAL(1, static_cast<long>(field(status, "revision")));
    // As doubles: a u32 CRC does not fit a 32-bit long (armhf).
    DOUBLES_EQUAL(static_cast<double>(core::crc32(image.data(), image.size())), field(status, "map_crc32"), 0.0);
    CHECK(eventCount(site_map::events::kMapLoaded) == 1);
}

TEST(SiteMapUplink, ABadCrcIsRefusedWithItsReasonAndTheMapInForceKept) {
    const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(rse::test::randomField(50, 100.0F, 2));
    uploadChunks(image);
    std::vector<std::uint8_t> commit = rse::ground::mapCommitArgs(image);
    commit.back() ^= 0x01U;  // the CRC's last byte
    send("MAP_COMMIT", commit);
    runFrames(1);
    expectAccepted("MAP_COMMIT");   // the length is right: started
    (void)runUntilCommitEnds();
    LONGS_EQUAL(static_cast<long>(site_map::UploadRefusal::kBadCrc),
                static_cast<long>(field(last("SITE_MAP"), "last_refusal")));
    LONGS_EQUAL(1, static_cast<long>(field(last("SITE_MAP"), "commits_refused")));
    CHECK_FALSE(fsw.siteMap().map().loaded());
    CHECK(eventCount(site_map::events::kCommitRefused) == 1);
}
