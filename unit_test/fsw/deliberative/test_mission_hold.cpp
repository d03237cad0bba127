// Fault protection's mission hold as the deliberative layer keeps it
// (mission_hold.hpp): held while any reason is set, released by reasons 0
// whatever the resume count says, each change evented once.
#include "fsw/core/clock.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/mission_hold.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using deliberative::MissionHold;
namespace ev = rse::deliberative::events;

namespace {

msg::MissionHoldMsg holdMsg(std::uint32_t reasons, std::uint32_t resumeCount, std::uint8_t estop = 0) {
    msg::MissionHoldMsg h{};
    h.reasons = reasons;
    h.resumeCount = resumeCount;
    h.estop = estop;
    return h;
}

}  // namespace

TEST_GROUP(MissionHold) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    test::EventRecord seen{events};
    MissionHold hold{events};
};

TEST(MissionHold, AnyReasonHoldsOnceAndReasonsZeroReleases) {
    CHECK(MissionHold::Change::kHeld == hold.take(holdMsg(0x1, 0, 1), 7, true));
    CHECK_TRUE(hold.held());
    STRCMP_EQUAL("deliberative: mission held (reasons 0x1, e-stop): no new legs, leg 7 kept", seen.text(ev::kMissionHeld));
    CHECK(MissionHold::Change::kNone == hold.take(holdMsg(0x3, 0), 7, true));
    LONGS_EQUAL(0x3, hold.reasons());
    LONGS_EQUAL(1, hold.holds());
    LONGS_EQUAL(1, seen.count(ev::kMissionHeld));
    CHECK(MissionHold::Change::kReleased == hold.take(holdMsg(0, 1), 7, true));
    CHECK_FALSE(hold.held());
    LONGS_EQUAL(1, hold.resumes());
    LONGS_EQUAL(1, hold.resumeCount());
    STRCMP_EQUAL("deliberative: hold released (resume 1): current leg re-sent from the current pose",
                 seen.text(ev::kMissionResumed));
}

TEST(MissionHold, AReleaseWithoutAHoldChangesNothingAndALostCountStillReleases) {
    CHECK(MissionHold::Change::kNone == hold.take(holdMsg(0, 5), 0, false));
    LONGS_EQUAL(0, seen.total());
    CHECK(MissionHold::Change::kHeld == hold.take(holdMsg(0x2, 5), 0, false));
    // The resume count did not move: reasons 0 releases all the same.
    CHECK(MissionHold::Change::kReleased == hold.take(holdMsg(0, 5), 0, false));
    CHECK_TRUE(seen.textHas(ev::kMissionResumed, "nothing to re-send"));
    LONGS_EQUAL(0, hold.reasons());
}
