// `rse-ground map load` (ground/map_transfer.hpp) against a fake rover that
// runs the flight's own site map service (ground_test_support.hpp): the
// commit is accepted at once and runs in slices on board, so the ground's
// verdict is the SITE_MAP that tells the commit's end, never the CMD_ACK
// alone: in force (exit 0), or refused with the image's reason and rock
// (exit 3), the map in force kept.
#include <algorithm>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/site_map/site_map_service.hpp"
#include "ground/map_transfer.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/site_map/site_map_fields.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_GROUP(GroundMapTransfer){};

// 6 000 rocks on a square kilometre: 1 250 chunks, then a commit of about
// ten command-task runs; the second map of a session is judged by its own end.
// (Small enough for the qemu targets: each chunk is a command with its MAC.)
TEST(GroundMapTransfer, ALargeMapIsInForceWhenItsSlicedCommitEndsAndASecondOneToo) {
    test::SessionRig rig;
    const std::vector<std::uint8_t> big = ground::encodeSiteMap(test::randomField(6000, 1000.0F, 5));
    LONGS_EQUAL(0, ground::loadSiteMap(rig.session, big, rig.out, rig.err));
    STRCMP_EQUAL("", rig.err.str().c_str());
    const site_map::SiteMapService* service = rig.rover.siteMapService();
    CHECK(service != nullptr);
    LONGS_EQUAL(6000, service->map().rockCount());
    CHECK(rig.rover.siteMapCommitRuns >= 6);  // sliced, not one run
    CHECK_TEXT(contains(rig.out.str(), "checked in " + std::to_string(rig.rover.siteMapCommitRuns) +
                                           " command-task runs: map 1 in force, 6000 rocks"),
               rig.out.str().c_str());
    const std::vector<std::uint8_t> small = ground::encodeSiteMap(test::randomField(300, 200.0F, 6));
    LONGS_EQUAL(0, ground::loadSiteMap(rig.session, small, rig.out, rig.err));
    CHECK_TRUE(contains(rig.out.str(), "map 2 in force, 300 rocks"));
    LONGS_EQUAL(300, service->map().rockCount());
}

// The commit is accepted (its length is right); the check, slices later,
// finds rock 1 234 clockwise: exit 3 with the reason and the rock, from SITE_MAP.
TEST(GroundMapTransfer, AnImageRefusedInItsSlicesIsExitThreeWithTheReasonAndTheRock) {
    test::SessionRig rig;
    const std::vector<std::uint8_t> good = ground::encodeSiteMap(test::randomField(300, 200.0F, 7));
    LONGS_EQUAL(0, ground::loadSiteMap(rig.session, good, rig.out, rig.err));
    ground::SiteMapSpec spec = test::randomField(2000, 500.0F, 8);
    std::reverse(spec.rocks[1234].begin(), spec.rocks[1234].end());
    LONGS_EQUAL(3, ground::loadSiteMap(rig.session, ground::encodeSiteMap(spec), rig.out, rig.err));
    CHECK_TEXT(contains(rig.err.str(), "the rover refused the map: polygon clockwise (item 1234); the map in force is kept"),
               rig.err.str().c_str());
    LONGS_EQUAL(300, rig.rover.siteMapService()->map().rockCount());
    // The MAP_COMMIT itself was accepted: the refusal came with the commit's end.
    CHECK(rig.rover.verdicts.back().reason == cmdtlm::CommandReject::kAccepted);
}

// An image of one chunk (the empty map: 32 bytes): the acknowledgement comes
// before the chunk's SITE_MAP (it goes at a higher priority, and the fake
// rover sends it first), so the counts the commit's end is told against are
// the chunk's answer's, waited for, never an earlier packet's.
TEST(GroundMapTransfer, AOneChunkImageIsJudgedByItsOwnCommitsEnd) {
    test::SessionRig rig;
    ground::SiteMapSpec empty;
    empty.site = {0.0F, 0.0F, 100.0F, 100.0F};
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(empty);
    LONGS_EQUAL(32, image.size());
    LONGS_EQUAL(0, ground::loadSiteMap(rig.session, image, rig.out, rig.err));
    STRCMP_EQUAL("", rig.err.str().c_str());
    CHECK_TEXT(contains(rig.out.str(), "map 1 in force, 0 rocks"), rig.out.str().c_str());
    LONGS_EQUAL(0, ground::loadSiteMap(rig.session, image, rig.out, rig.err));
    CHECK_TEXT(contains(rig.out.str(), "map 2 in force, 0 rocks"), rig.out.str().c_str());
}
