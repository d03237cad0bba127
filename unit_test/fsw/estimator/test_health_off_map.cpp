// Fault 46, off the map: a trusted pose outside the COARSE_MAP site raises it
// in the second frame that shows it; it clears kOffMapClearMarginM inside; an
// uncertain pose neither raises nor clears it; the site is the active table's.
#include <cmath>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/estimator/health_monitor.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/tables/table_types.hpp"
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

TEST_GROUP(HealthOffMap) {
    HealthRig rig;
    double yMin = 0.0;
    void setup() override {
        CHECK(rig.init());
        yMin = static_cast<double>(rig.tables.coarseMap().y_min_m);
        rig.feed.pose.xM = 0.0;
        rig.feed.pose.yM = yMin + 1.0;
        rig.steps(15);
        LONGS_EQUAL(0, rig.health.status().activeMask);
    }
};

TEST(HealthOffMap, APoseOutsideTheSiteRaisesInTheSecondFrameAndClearsOnlyWellInside) {
    rig.feed.pose.yM = yMin - 0.3;
    const core::TimeNs firstEstimate = rig.now() + kFrame;
    const core::TimeNs raisedAt = rig.stepUntil(fault::kOffMap, true, 20);
    CHECK(raisedAt > firstEstimate);
    CHECK(raisedAt <= firstEstimate + kFrame);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthOffMap));
    STRCMP_CONTAINS("fault 46: off the map, pose (0.00, -10.30) 0.30 m outside the site",
                    rig.event(ev::kHealthOffMap).lastText);

    // Back on, but within the clear margin of the edge: still off.
    rig.feed.pose.yM = yMin + 0.5 * estimator::kOffMapClearMarginM;
    rig.steps(100);
    CHECK(rig.health.active(fault::kOffMap));

    rig.feed.pose.yM = yMin + 2.0 * estimator::kOffMapClearMarginM;
    CHECK(rig.stepUntil(fault::kOffMap, false, 3) > 0);
    LONGS_EQUAL(1, rig.eventCount(ev::kHealthOffMapCleared));
    STRCMP_CONTAINS("back on the map", rig.event(ev::kHealthOffMapCleared).lastText);
}

TEST(HealthOffMap, AnUncertainPoseNeitherRaisesNorClearsIt) {
    const double faultSigma = static_cast<double>(rig.tables.estimatorNoise().pose_fault_sigma_m);
    rig.feed.pose.positionSigmaM = faultSigma + 0.5;
    rig.feed.pose.yM = yMin - 2.0;
    rig.steps(100);
    LONGS_EQUAL(0, rig.health.raisedCount(fault::kOffMap));

    rig.feed.pose.positionSigmaM = 0.1;
    CHECK(rig.stepUntil(fault::kOffMap, true, 3) > 0);
    rig.feed.pose.inconsistent = 1;  // refused fixes: where it stands is not known
    rig.feed.pose.yM = yMin + 5.0;
    rig.steps(100);
    CHECK(rig.health.active(fault::kOffMap));
    rig.feed.pose.inconsistent = 0;
    CHECK(rig.stepUntil(fault::kOffMap, false, 3) > 0);
}

TEST(HealthOffMap, TheSiteIsTheActiveCoarseMapTables) {
    rig.feed.pose.yM = yMin - 1.0;
    CHECK(rig.stepUntil(fault::kOffMap, true, 3) > 0);
    // A larger site uploaded: the same pose is on the map now.
    tables::CoarseMapTable wider = rig.tables.coarseMap();
    wider.y_min_m = static_cast<float>(yMin - 5.0);
    CHECK(test::activateTable(rig.tables, tables::TableId::kCoarseMap, wider, 2));
    CHECK(rig.stepUntil(fault::kOffMap, false, 3) > 0);
}

TEST(HealthOffMap, ANonFinitePositionIsRefusedAndCounted) {
    rig.feed.pose.yM = yMin - 1.0;
    CHECK(rig.stepUntil(fault::kOffMap, true, 3) > 0);
    const std::uint32_t before = rig.health.monitor().nonFiniteInputs();
    rig.feed.pose.yM = std::nan("");
    rig.steps(10);
    CHECK(rig.health.monitor().nonFiniteInputs() > before);
    CHECK(rig.health.active(fault::kOffMap));  // the last good position stands
}
