// The numbers the deliberative layer's events carry (fsw/cmdtlm/dictionary.def,
// "Event data"): each RSE_EVENT_DATA of its events names the flight constant
// of that event (checked at compile time), and the call sites fill every value
// by name as the event's text says it (the ground decides on these numbers,
// never on the text).
#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/leg_sequencer.hpp"
#include "unit_test/fsw/deliberative/event_record.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
namespace ev = rse::deliberative::events;
namespace evd = rse::cmdtlm::event_data;

template <typename Layout>
constexpr bool isTheEvent(core::EventId id) {
    return Layout::kFirstId == id && Layout::kLastId == id;
}
static_assert(isTheEvent<evd::LEG_SENT>(ev::kLegSent), "905");
static_assert(isTheEvent<evd::LEG_REACHED>(ev::kLegAchieved), "906");
static_assert(isTheEvent<evd::BOUND_RELAXED>(ev::kBoundRelaxed), "910");
static_assert(isTheEvent<evd::CALL_HOME>(ev::kCallHome), "912");
static_assert(isTheEvent<evd::FAILED_DRIVE_MODEL>(ev::kFailedDriveModel), "990");

namespace {

// A straight plan (0, 0) -> (18, 0) in 3 steps: legs of 6 m.
deliberative::CcPlan straightPlan() {
    deliberative::CcPlan p{};
    p.status = deliberative::CcStatus::kOptimal;
    p.steps = 3;
    for (std::size_t t = 0; t <= 3; ++t) {
        p.meanX[t] = 6.0 * static_cast<double>(t);
    }
    for (std::size_t t = 0; t < 3; ++t) {
        p.segmentRisk[t] = 1e-4;
        p.riskUsed += 1e-4;
    }
    return p;
}

deliberative::LegParams params() {
    deliberative::LegParams lp;
    lp.spacingM = 6.0;
    lp.power = rover_model::PowerModel{940.0, 1370.0, 4.5};
    lp.meanPowerFactor = 1.0;
    return lp;
}

}  // namespace

TEST_GROUP(DeliberativeEventData) {
    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    test::EventRecord seen{events};
    deliberative::Publisher out{bus, events};
    deliberative::LegSequencer legs{events, out};
    tables::CoarseMapTable map{};
    msg::KnownHazardsMsg hazards{};
    deliberative::LegEndClearance clear{map, 0.6, hazards};
    void setup() override {
        map.x_min_m = -50.0F;
        map.x_max_m = 50.0F;
        map.y_min_m = -50.0F;
        map.y_max_m = 50.0F;
        CHECK_TRUE(legs.split(straightPlan(), params()));
        legs.begin();
    }
};

TEST(DeliberativeEventData, ALegSentReachedAndRelaxedCarryTheirNumbers) {
    legs.send(100, false, 0.0, clear);
    const msg::PlanLeg& first = legs.legs().legs[0];
    evd::LEG_SENT sent;
    CHECK_TRUE(seen.data(ev::kLegSent, &sent));
    DOUBLES_EQUAL(1.0, sent.leg_id, 0.0);
    DOUBLES_EQUAL(1.0, sent.index, 0.0);
    DOUBLES_EQUAL(3.0, sent.count, 0.0);
    DOUBLES_EQUAL(first.xM, sent.x, 0.0);
    DOUBLES_EQUAL(first.yM, sent.y, 0.0);
    DOUBLES_EQUAL(first.lengthM, sent.length_bound, 0.0);
    DOUBLES_EQUAL(first.energyJ, sent.energy_bound, 0.0);
    DOUBLES_EQUAL(first.powerW, sent.power_bound, 0.0);

    deliberative::FailUpAnswer power;
    power.action = deliberative::FailUpAnswer::Action::kRelaxPower;
    power.needed = 1.1;
    power.grown = 1.1;
    power.limit = 1.5;
    legs.relax(power, msg::LegConstraint::kPower);
    evd::BOUND_RELAXED relaxed;
    CHECK_TRUE(seen.data(ev::kBoundRelaxed, &relaxed));
    DOUBLES_EQUAL(1.0, relaxed.leg_id, 0.0);
    DOUBLES_EQUAL(static_cast<double>(msg::LegConstraint::kPower), relaxed.bound, 0.0);
    DOUBLES_EQUAL(1.1, relaxed.factor, 0.0);
    DOUBLES_EQUAL(first.powerW, relaxed.from, 1e-9);
    DOUBLES_EQUAL(first.powerW * 1.1, relaxed.to, 1e-9);
    DOUBLES_EQUAL(1.5, relaxed.limit, 0.0);

    deliberative::FailUpAnswer energy;
    energy.action = deliberative::FailUpAnswer::Action::kRelaxBound;
    energy.needed = 1.2;
    energy.grown = 1.2;
    energy.limit = 1.5;
    const double before = first.energyJ;
    legs.relax(energy, msg::LegConstraint::kEnergy);
    CHECK_TRUE(seen.data(ev::kBoundRelaxed, &relaxed));
    DOUBLES_EQUAL(static_cast<double>(msg::LegConstraint::kEnergy), relaxed.bound, 0.0);
    DOUBLES_EQUAL(before, relaxed.from, 0.0);
    DOUBLES_EQUAL(before * 1.2, relaxed.to, 1e-9);

    CHECK_TRUE(legs.achieved());
    evd::LEG_REACHED reached;
    CHECK_TRUE(seen.data(ev::kLegAchieved, &reached));
    DOUBLES_EQUAL(1.0, reached.leg_id, 0.0);
    DOUBLES_EQUAL(1.0, reached.index, 0.0);
    DOUBLES_EQUAL(3.0, reached.count, 0.0);
}

TEST(DeliberativeEventData, ABackUpLegIsNoLegOfThePlan) {
    legs.send(100, false, 0.0, clear);
    msg::PlanLeg target{};
    target.xM = -2.0;
    msg::PoseEstimateMsg pose{};
    pose.initialised = 1;
    legs.sendBackUp(200, false, &target, pose, params());
    evd::LEG_SENT sent;
    CHECK_TRUE(seen.data(ev::kLegSent, &sent));
    DOUBLES_EQUAL(2.0, sent.leg_id, 0.0);
    DOUBLES_EQUAL(0.0, sent.index, 0.0);
    DOUBLES_EQUAL(0.0, sent.count, 0.0);
    DOUBLES_EQUAL(-2.0, sent.x, 0.0);
    DOUBLES_EQUAL(target.lengthM, sent.length_bound, 0.0);
    DOUBLES_EQUAL(legs.legs().legs[0].powerW, sent.power_bound, 0.0);  // the plan's, as sent
}
