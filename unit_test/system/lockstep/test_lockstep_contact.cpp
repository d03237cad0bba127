// Never a contact that goes on (issue 31, "Never a contact"): the rover
// drives into a rock its hazard detector cannot see
// (sim_stub/scenarios/contact_unseen_rock.toml). The follower feels it in the
// frame the drives report it (the contact reflex, fsw/reflexive/contact_reflex.hpp),
// zeroes the wheels, backs 0.5 m away (the habitual layer waits for it), the
// habitual layer remembers the rock where the rover touched it and plans
// round it, and the goal is reached: no drive trips its over-current, no
// fault, no call home.
#include <cstdio>
#include <string>

#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "unit_test/support/mission_console.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

TEST_GROUP(LockstepContact){};

TEST(LockstepContact, ARockTheDetectorMissesIsFeltWithinAFrameBackedOffFromAndDrivenRound) {
    sim::MissionOptions o;
    const char* argv[] = {"rse-demo", "--scenario", "sim_stub/scenarios/contact_unseen_rock.toml", "--no-report"};
    std::string error;
    CHECK_TRUE_TEXT(sim::parseMissionArgs(4, argv, &o, &error) == sim::ParseOutcome::kRun, error.c_str());
    std::int64_t touchedNs = -1, feltNs = -1;
    double feltAtX = 0.0, leastXAfter = 1e9;
    bool overCurrent = false, driveNotOperational = false;
    std::uint32_t contacts = 0, backoffs = 0, backoffsCut = 0;
    std::uint32_t tlmContacts = 0;
    o.onFrame = [&](sim::LockstepRig& rig) {
        const std::int64_t now = rig.clock().now();
        const sim::TruthRecord& truth = rig.rover().truth();
        if (truth.inContact && touchedNs < 0) {
            touchedNs = now;
        }
        const reflexive::TrajectoryTaskCounters& c = rig.fsw().follower().counters();
        if (c.contacts > 0 && feltNs < 0) {
            feltNs = now;
            feltAtX = truth.pose.x;
        }
        if (feltNs >= 0) {
            leastXAfter = truth.pose.x < leastXAfter ? truth.pose.x : leastXAfter;
        }
        contacts = c.contacts;
        backoffs = c.backoffs;
        backoffsCut = c.backoffsCut;
        for (const msg::WheelStatus& w : rig.driveStatus().wheels) {
            overCurrent = overCurrent || w.lastEmcyCode == 0x2310;
            driveNotOperational = driveNotOperational || (w.health != msg::DriveHealth::kOperational &&
                                                          rig.driveStatusCount() > 300);
        }
    };
    test::MissionConsole console;
    const sim::MissionSummary s = sim::runMission(o, console.file);
    const std::string out = console.str();
    const std::string tail = out.substr(out.size() > 6000 ? out.size() - 6000 : 0);
    (void)tlmContacts;

    CHECK_TRUE_TEXT(s.outcome == sim::MissionOutcome::kGoalReached, tail.c_str());
    LONGS_EQUAL_TEXT(1, s.collisions, "the one touch, and no second");
    CHECK_TEXT(touchedNs >= 0 && feltNs >= 0, tail.c_str());
    // Felt within a frame of the drives' report: the touch is seen by the
    // drives' currents in the next status (a frame), the follower reads it
    // in the frame after at the latest.
    CHECK_TEXT(feltNs - touchedNs <= 2 * 10 * 1000 * 1000, tail.c_str());
    LONGS_EQUAL(1, contacts);
    CHECK(backoffs >= 1);
    LONGS_EQUAL(0, backoffsCut);            // the whole back-off: the habitual layer waited for it
    CHECK(feltAtX - leastXAfter >= 0.45);   // FOLLOWER.contact_backoff_m (0.5 m) back
    CHECK_FALSE_TEXT(overCurrent, "a drive tripped its over-current");
    CHECK_FALSE_TEXT(driveNotOperational, "a drive left operational");
    CHECK(s.goalDistanceM < 0.5);
    // The rock was remembered where the rover touched it, and the leg replanned.
    CHECK(out.find("EVT 618 WARN  follower: contact driving forwards") != std::string::npos);
    CHECK(out.find("EVT 823 WARN  habitual: contact 1") != std::string::npos);
    CHECK(out.find("EVT 619 INFO  follower: back-off ended (backed off)") != std::string::npos);
    CHECK(out.find("EVT 724 ") == std::string::npos);  // no over-current fault
    CHECK(out.find("EVT 601 ") == std::string::npos);  // the interlock never tripped
}
