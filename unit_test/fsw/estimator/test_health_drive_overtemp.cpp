// Drive over-temperature (faults 40..45): a reported motor temperature above
// FAULT_RESPONSE.drive_overtemp_c held fault_persist_ms raises the wheel's
// fault; it clears 15 degC below, held as long; an unreported temperature is no
// evidence.
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_image.hpp"
#include "unit_test/fsw/estimator/health_test_rig.hpp"
#include "unit_test/support/table_loader.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using test::HealthRig;
namespace ev = estimator::events;
namespace fault = msg::fault;

namespace {
constexpr core::TimeNs kFrame = HealthRig::kFrame;
}  // namespace

TEST_GROUP(HealthDriveOvertemp) {
    HealthRig rig;
    core::TimeNs persist = 0;
    float limitC = 0.0F;
    void setup() override {
        CHECK(rig.init());
        persist = static_cast<core::TimeNs>(rig.tables.faultResponse().fault_persist_ms) * core::kNsPerMs;
        limitC = static_cast<float>(rig.tables.faultResponse().drive_overtemp_c);
        for (msg::WheelStatus& w : rig.feed.drives.wheels) {
            w.temperatureValid = 1;
            w.temperatureC = 40.0F;
        }
        rig.steps(15);
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }
};

TEST(HealthDriveOvertemp, RaisesAfterPersistenceAndClearsFifteenDegreesBelow) {
    const std::uint8_t id = fault::kDriveOvertemp + 2;  // wheel RL
    rig.feed.drives.wheels[2].temperatureC = limitC + 1.0F;
    const core::TimeNs firstSample = rig.now() + kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(id, true, 100);
    CHECK(raisedAt > 0);
    CHECK(raisedAt - firstSample >= persist);
    CHECK(raisedAt - firstSample <= persist + kFrame);
    CHECK(rig.health.status().activeMask == (std::uint64_t{1} << id));
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveOvertemp));
    STRCMP_CONTAINS("fault 42: drive RL motor 81.0 degC > 80.0 degC", rig.event(ev::kHealthDriveOvertemp).lastText);

    // Cooler, but within 15 degC of the limit: stays raised.
    rig.feed.drives.wheels[2].temperatureC = limitC - 14.0F;
    rig.steps(200);
    CHECK(rig.health.active(id));
    rig.feed.drives.wheels[2].temperatureC = limitC - 16.0F;
    const core::TimeNs clearStart = rig.now() + kFrame;
    const core::TimeNs clearedAt = rig.stepUntil(id, false, 100);
    CHECK(clearedAt - clearStart >= persist);
    CHECK(clearedAt - clearStart <= persist + kFrame);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthDriveOvertempCleared));
    STRCMP_CONTAINS("fault 42 cleared: drive RL motor 64.0 degC < 65.0 degC",
                    rig.event(ev::kHealthDriveOvertempCleared).lastText);
}

TEST(HealthDriveOvertemp, AnUnreportedTemperatureIsNoEvidence) {
    rig.feed.drives.wheels[0].temperatureValid = 0;
    rig.feed.drives.wheels[0].temperatureC = 500.0F;
    rig.steps(100);
    LONGS_EQUAL(0, rig.health.status().activeMask);
}

TEST(HealthDriveOvertemp, TheLimitIsTheTablesDriveOvertempC) {
    tables::FaultResponseTable t = rig.tables.faultResponse();
    t.drive_overtemp_c = 60;
    CHECK_TRUE(test::activateTable(rig.tables, tables::TableId::kFaultResponse, t, 2));
    rig.feed.drives.wheels[5].temperatureC = 65.0F;  // below the shipped 80, above 60
    CHECK(rig.stepUntil(fault::kDriveOvertemp + 5, true, 100) > 0);
}
