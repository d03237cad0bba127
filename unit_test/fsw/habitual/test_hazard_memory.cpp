// The habitual layer's hazard memory (fsw/habitual/hazard_memory.hpp):
// sightings placed and remembered with their events, a rejected sighting
// counted without losing the message's others, the maps built for a leg (its
// end against the seen disc), the check map and when it is stale, and the
// seen discs told to the deliberative layer.
#include <cmath>
#include <limits>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/hazard_memory.hpp"
#include "ground/site_map_encoder.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::HazardMemory;
namespace ev = habitual::events;

namespace {

msg::HazardMsg hazards(std::initializer_list<msg::HazardSightingTlm> sightings) {
    msg::HazardMsg m{};
    for (const msg::HazardSightingTlm& s : sightings) {
        m.sightings[m.count++] = s;
    }
    return m;
}

}  // namespace

TEST_GROUP(HazardMemory) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventReader seen{events};
    tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    HazardMemory memory{events, coarse};
    msg::LegCommandMsg noLeg{};
};

TEST(HazardMemory, AFirstSightingIsRememberedAndEventedOnce) {
    // Rover at (18, -6) facing +x: a rock 1.6 m ahead, 0.8 m wide: centre (20, -6).
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);
    LONGS_EQUAL(1, memory.builder().rememberedCount());
    seen.take();
    LONGS_EQUAL(1, seen.count(ev::kHazardRemembered));
    STRCMP_EQUAL("habitual: hazard 7 seen at (20.00, -6.00), radius 0.89 m: on the map", seen.text(ev::kHazardRemembered));
    cmdtlm::event_data::HAZARD_REMEMBERED disc;  // what the ground reads
    CHECK_TRUE(seen.data(ev::kHazardRemembered, &disc));
    DOUBLES_EQUAL(7.0, disc.hazard, 0.0);
    DOUBLES_EQUAL(20.0, disc.x, 1e-9);
    DOUBLES_EQUAL(-6.0, disc.y, 1e-9);
    DOUBLES_EQUAL(memory.builder().slot(0).radiusM, disc.radius, 0.0);
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);
    seen.take();
    LONGS_EQUAL(0, seen.count(ev::kHazardRemembered));
}

TEST(HazardMemory, ASightingOfAMappedRockIsNotAdded) {
    // Rock 0 (x 5..6.5, y 1.8..3.2) seen from (3, 2.5): its face at x 5.
    memory.remember(hazards({test::sighting(1, 2.0, 0.0, 0.7)}), Point2{3.0, 2.5}, 0.0);
    LONGS_EQUAL(0, memory.builder().rememberedCount());
    seen.take();
    CHECK_TRUE(seen.says(ev::kHazardKnown, "habitual: hazard 1 is on the coarse map: not added (1 so far)"));
    CHECK(core::Severity::kDebug == seen.severity(ev::kHazardKnown));
}

TEST(HazardMemory, ARejectedSightingIsCountedAndTheOthersArePlaced) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    memory.remember(hazards({test::sighting(4, nan, 0.0, 0.4), test::sighting(7, 1.6, 0.0, 0.4)}),
                    Point2{18.0, -6.0}, 0.0);
    LONGS_EQUAL(1, memory.rejectedSightings());
    LONGS_EQUAL(1, memory.builder().rememberedCount());
    seen.take();
    STRCMP_EQUAL("habitual: malformed hazard sighting (msg 0x0123) ignored (1 so far)", seen.text(ev::kMalformedInput));
    memory.remember(hazards({test::sighting(0, 1.0, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);  // id 0: "clear"
    memory.remember(hazards({test::sighting(5, -1.0, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);
    LONGS_EQUAL(3, memory.rejectedSightings());
    seen.take();
    LONGS_EQUAL(1, seen.count(ev::kMalformedInput));  // the 2nd; not the 3rd
}

TEST(HazardMemory, ALegsEndInsideACoverIsPlannedToAgainstTheSeenDisc) {
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);  // centre (20, -6)
    const habitual::RememberedHazard& h = memory.builder().slot(0);
    const double clearance = 0.6;
    // 1.3 m from the centre: inside the cover grown by the clearance, outside the seen disc grown by it.
    const Point2 end{21.3, -6.0};
    CHECK(h.radiusM + clearance > 1.3);
    CHECK(h.seenRadiusM + clearance < 1.3);
    habitual::LocalMap map;
    CHECK_TRUE(memory.build(&map, clearance, noLeg));
    CHECK_FALSE(map.pointFree(end));
    msg::LegCommandMsg leg{};
    leg.legId = 3;
    leg.goalXM = end.x;
    leg.goalYM = end.y;
    CHECK_TRUE(memory.build(&map, clearance, leg));
    CHECK_TRUE(map.pointFree(end));
    LONGS_EQUAL(0, memory.mapRefused());
}

TEST(HazardMemory, ARefusedMapIsCountedAndEvented) {
    habitual::LocalMap map;
    CHECK_FALSE(memory.build(&map, -1.0, noLeg));  // a negative clearance: the map refuses its bounds
    LONGS_EQUAL(1, memory.mapRefused());
    seen.take();
    CHECK_TRUE(seen.says(ev::kMapRefused, "habitual: local map refused an obstacle ("));
    CHECK_TRUE(seen.says(ev::kMapRefused, ") (1 so far)"));
}

TEST(HazardMemory, TheCheckMapIsStaleWhenTheMemoryChanged) {
    CHECK_FALSE(memory.checkMapStale());
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);
    CHECK_TRUE(memory.checkMapStale());
    memory.refreshCheckMap(0.6, noLeg);
    CHECK_FALSE(memory.checkMapStale());
    CHECK_FALSE(memory.checkMap().pointFree(Point2{20.0, -6.0}));
    DOUBLES_EQUAL(0.6, memory.checkMap().clearance(), 0.0);
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4)}), Point2{18.0, -6.0}, 0.0);  // nothing new
    CHECK_FALSE(memory.checkMapStale());
}

TEST(HazardMemory, TheDeliberativeLayerIsToldTheSeenDiscs) {
    memory.remember(hazards({test::sighting(7, 1.6, 0.0, 0.4), test::sighting(8, 1.0, 1.5707963267948966, 0.2)}),
                    Point2{18.0, -6.0}, 0.0);
    msg::KnownHazardsMsg m{};
    memory.fillKnownHazards(1234, &m);
    LONGS_EQUAL(1234, m.timeNs);
    LONGS_EQUAL(memory.revision(), m.revision);
    LONGS_EQUAL(2, m.count);
    LONGS_EQUAL(7, m.hazards[0].obstacleId);
    DOUBLES_EQUAL(20.0, m.hazards[0].xM, 1e-5);
    DOUBLES_EQUAL(0.6, m.hazards[0].radiusM, 1e-5);  // 1.5 half widths, not the cover
    LONGS_EQUAL(8, m.hazards[1].obstacleId);
    DOUBLES_EQUAL(-4.8, m.hazards[1].yM, 1e-5);
}

// Site mode: the site map's rocks near a leg join its maps, and a sighting of
// one is known, not remembered.
TEST_GROUP(HazardMemorySiteMode) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    tables::CoarseMapTable coarse = test::defaultTable<tables::CoarseMapTable>();
    site_map::SiteMap* site = nullptr;
    void setup() override {
        // As site mode flies: COARSE_MAP's bounds cover the site, its rocks are the site map's.
        coarse.x_min_m = -20.0F;
        coarse.x_max_m = 120.0F;
        coarse.y_min_m = -20.0F;
        coarse.y_max_m = 20.0F;
        for (auto& n : coarse.vertex_count) {
            n = 0;
        }
        static site_map::SiteMap storage;   // ~1 MB: static, as in flight
        site = &storage;
        ground::SiteMapSpec spec;
        spec.site = {-20.0F, -20.0F, 120.0F, 20.0F};
        // Rock 0 near the leg (x 60..61, y -0.5..0.5), rock 1 far from it (x 100..101).
        spec.rocks.push_back({{60.0F, -0.5F}, {61.0F, -0.5F}, {61.0F, 0.5F}, {60.0F, 0.5F}});
        spec.rocks.push_back({{100.0F, -0.5F}, {101.0F, -0.5F}, {101.0F, 0.5F}, {100.0F, 0.5F}});
        const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
        site_map::SiteMapCheck check;
        CHECK(site->load(image.data(), image.size(), &check) == core::Status::kOk);
    }
};

TEST(HazardMemorySiteMode, TheSiteRocksInALegsWindowJoinItsMapAndTheOthersDoNot) {
    HazardMemory* memory = nullptr;
    HazardMemory storage(events, coarse, site);
    memory = &storage;
    msg::LegCommandMsg leg{};
    leg.legId = 3;
    leg.goalXM = 64.0;
    leg.goalYM = 0.0;
    leg.maxPathLengthM = 6.0;
    habitual::LocalMap map;
    CHECK_TRUE(memory->build(&map, 0.6, leg));
    // Rock 0 (3 m from the goal); not rock 1 (36 m).
    LONGS_EQUAL(1, map.polygonCount());
    CHECK_FALSE(map.pointFree(Point2{60.5, 0.0}));
    CHECK_FALSE(map.pointFree(Point2{61.4, 0.0}));   // within the clearance
    CHECK_TRUE(map.pointFree(Point2{100.5, 0.0}));   // not in this leg's window
    // No leg: no window, no site rocks.
    habitual::LocalMap bare;
    CHECK_TRUE(memory->build(&bare, 0.6, msg::LegCommandMsg{}));
    LONGS_EQUAL(0, bare.polygonCount());
    // A sighting of rock 0 (its face at x 60, seen from (58, 0)) is known.
    memory->remember(hazards({test::sighting(5, 2.0, 0.0, 0.5)}), Point2{58.0, 0.0}, 0.0);
    LONGS_EQUAL(0, memory->builder().rememberedCount());
    LONGS_EQUAL(1, memory->builder().knownObstacles());
}

// More site rocks in a leg's window than the local map holds: the map is not
// used (it would hide rocks), never used in part.
TEST(HazardMemorySiteMode, AWindowWithMoreRocksThanTheMapHoldsIsNotUsable) {
    ground::SiteMapSpec spec;
    spec.site = {-20.0F, -20.0F, 120.0F, 20.0F};
    for (int i = 0; i < 60; ++i) {
        const float x = 50.0F + 2.0F * static_cast<float>(i % 10);
        const float y = -6.0F + 2.0F * static_cast<float>(i / 10);
        spec.rocks.push_back({{x, y}, {x + 0.5F, y}, {x + 0.5F, y + 0.5F}, {x, y + 0.5F}});
    }
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(spec);
    site_map::SiteMapCheck check;
    CHECK(site->load(image.data(), image.size(), &check) == core::Status::kOk);
    HazardMemory memory(events, coarse, site);
    msg::LegCommandMsg leg{};
    leg.legId = 4;
    leg.goalXM = 60.0;
    leg.goalYM = 0.0;
    leg.maxPathLengthM = 20.0;
    habitual::LocalMap map;
    CHECK_FALSE(memory.build(&map, 0.6, leg));
    LONGS_EQUAL(1, memory.mapRefused());
    // A leg whose paths reach past the window (over 40 m) is not usable either.
    leg.goalXM = 0.0;
    leg.maxPathLengthM = 45.0;
    CHECK_FALSE(memory.build(&map, 0.6, leg));
}
