#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "hal/canopen/le_codec.hpp"
#include "hal/devices/hazard_detector.hpp"
#include "sim_stub/devices/hazard_detector_emulator.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;
using hal::CanFrame;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;

Obstacle box(std::uint16_t id, bool known, double x0, double y0, double x1, double y1) {
    Obstacle o;
    o.id = id;
    o.known = known;
    o.shape.v[0] = {x0, y0};
    o.shape.v[1] = {x1, y0};
    o.shape.v[2] = {x1, y1};
    o.shape.v[3] = {x0, y1};
    o.shape.n = 4;
    return o;
}

HazardDetectorParams noiseless() {
    HazardDetectorParams p;
    p.rangeSigmaM = 0.0;
    p.bearingSigmaRad = 0.0;
    return p;
}

struct Report {
    double rangeM;
    double bearingRad;
    double halfWidthM;
    std::uint8_t id;
    std::uint8_t counter;
    core::TimeNs time;
};

}  // namespace

TEST_GROUP(SimHazard) {
    core::VirtualClock clock;
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* flight = nullptr;
    hal::MemoryCanEndpoint* simPort = nullptr;
    World* world = nullptr;
    HazardDetectorEmulator* detector = nullptr;
    core::TimeNs t = 0;
    std::vector<Report> reports;

    void setup() override {
        flight = wire.attach("flight");
        simPort = wire.attach("sim");
    }
    void teardown() override {
        delete detector;
        delete world;
    }
    void build(const std::vector<Obstacle>& obstacles, const Pose2& pose,
               const HazardDetectorParams& params = noiseless()) {
        WorldConfig c;
        c.obstacles = obstacles;
        c.start = pose;
        world = new World(c);
        detector = new HazardDetectorEmulator(*simPort, *world, params, 77);
    }
    void runUntil(core::TimeNs until) {
        for (; t <= until; t += kMs) {
            clock.sleepUntil(t);
            world->advance(t, WheelArray{}, WheelArray{});
            detector->step(t);
            CanFrame f;
            while (core::isOk(flight->receive(&f))) {
                if (f.id == 0x6A2) {
                    LONGS_EQUAL(8, f.dlc);
                    reports.push_back(Report{hal::le::getI16(&f.data[0]) * 0.01, hal::le::getI16(&f.data[2]) * 1e-3,
                                             hal::le::getI16(&f.data[4]) * 0.01, f.data[6], f.data[7], f.timestamp});
                }
            }
        }
    }
    std::size_t countId(std::uint8_t id) const {
        std::size_t n = 0;
        for (const Report& r : reports) {
            n += r.id == id ? 1U : 0U;
        }
        return n;
    }
};

TEST(SimHazard, GeometryOfAnObstacleStraightAhead) {
    HazardView v;
    CHECK_TRUE(observeObstacle(Pose2{}, box(3, false, 2.0, -0.5, 3.0, 0.5), noiseless(), &v));
    LONGS_EQUAL(3, v.obstacleId);
    DOUBLES_EQUAL(2.0, v.rangeM, 1e-12);
    DOUBLES_EQUAL(0.0, v.bearingRad, 1e-12);
    DOUBLES_EQUAL(0.5, v.halfWidthM, 1e-12);
}

TEST(SimHazard, GeometryOfAnOffAxisObstacle) {
    HazardView v;
    CHECK_TRUE(observeObstacle(Pose2{}, box(5, true, 2.0, 1.0, 3.0, 2.0), noiseless(), &v));
    DOUBLES_EQUAL(std::sqrt(5.0), v.rangeM, 1e-12);       // nearest corner (2, 1)
    DOUBLES_EQUAL(std::atan2(1.0, 2.0), v.bearingRad, 1e-12);  // left is positive
    DOUBLES_EQUAL(0.5 * (0.894427191 + 0.447213595), v.halfWidthM, 1e-8);
    // Seen from a rover facing +y at (2.5, -1): the box is 2 m ahead.
    CHECK_TRUE(observeObstacle(Pose2{2.5, -1.0, kPi / 2.0}, box(5, true, 2.0, 1.0, 3.0, 2.0), noiseless(), &v));
    DOUBLES_EQUAL(2.0, v.rangeM, 1e-12);
    DOUBLES_EQUAL(0.0, v.bearingRad, 1e-12);
    DOUBLES_EQUAL(0.5, v.halfWidthM, 1e-12);
}

TEST(SimHazard, ObstaclesBehindOutOfRangeOrOutsideTheFieldOfViewAreNotSeen) {
    HazardView v;
    CHECK_FALSE(observeObstacle(Pose2{}, box(1, true, -3.0, -0.5, -2.0, 0.5), noiseless(), &v));  // behind
    CHECK_FALSE(observeObstacle(Pose2{}, box(1, true, 3.2, -0.5, 4.0, 0.5), noiseless(), &v));    // 3.2 m > 3 m
    CHECK_FALSE(observeObstacle(Pose2{}, box(1, true, -0.5, 2.0, 0.5, 3.0), noiseless(), &v));    // 76-104 deg left
    // Straddling the edge of the field of view: only the part inside counts, its
    // nearest point lies on the 60 degree ray.
    CHECK_TRUE(observeObstacle(Pose2{}, box(1, true, 0.5, 2.0, 1.5, 3.0), noiseless(), &v));
    DOUBLES_EQUAL(kPi / 3.0, v.bearingRad, 1e-9);
    DOUBLES_EQUAL(2.0 / std::sin(kPi / 3.0), v.rangeM, 1e-9);
}

TEST(SimHazard, AHiddenObstacleAheadIsReportedOnTheBusFiveTimesASecond) {
    build({box(3, false, 2.0, -0.5, 3.0, 0.5)}, Pose2{});
    runUntil(core::kNsPerSec);
    LONGS_EQUAL(5, reports.size());
    for (std::size_t i = 0; i < reports.size(); ++i) {
        const Report& r = reports[i];
        LONGS_EQUAL(3, r.id);
        DOUBLES_EQUAL(2.0, r.rangeM, 1e-9);
        DOUBLES_EQUAL(0.0, r.bearingRad, 1e-9);
        DOUBLES_EQUAL(0.5, r.halfWidthM, 1e-9);
        LONGS_EQUAL(i, r.counter);
        CHECK_EQUAL(static_cast<core::TimeNs>(i + 1) * 200 * kMs, r.time);
    }
}

TEST(SimHazard, NoisyReportsStayWithinTheStatedSigma) {
    HazardDetectorParams params;  // defaults: 2 cm, 10 mrad
    build({box(3, false, 2.0, -0.5, 3.0, 0.5)}, Pose2{}, params);
    runUntil(20 * core::kNsPerSec);
    LONGS_EQUAL(100, reports.size());
    double sumR = 0.0, sumB = 0.0;
    for (const Report& r : reports) {
        DOUBLES_EQUAL(2.0, r.rangeM, 5.0 * params.rangeSigmaM + 0.005);
        DOUBLES_EQUAL(0.0, r.bearingRad, 5.0 * params.bearingSigmaRad + 0.0005);
        sumR += r.rangeM;
        sumB += r.bearingRad;
    }
    DOUBLES_EQUAL(2.0, sumR / 100.0, 3.0 * params.rangeSigmaM / 10.0 + 0.005);
    DOUBLES_EQUAL(0.0, sumB / 100.0, 3.0 * params.bearingSigmaRad / 10.0 + 0.0005);
}

TEST(SimHazard, TwoObstaclesAreReportedNearestFirstEachLook) {
    build({box(8, true, 2.5, 0.5, 3.5, 1.0), box(4, false, 1.5, -0.6, 2.0, -0.2)}, Pose2{});
    runUntil(core::kNsPerSec);
    LONGS_EQUAL(10, reports.size());
    LONGS_EQUAL(5, countId(4));
    LONGS_EQUAL(5, countId(8));
    LONGS_EQUAL(0, countId(0));
    for (std::size_t i = 0; i < reports.size(); i += 2) {
        LONGS_EQUAL(4, reports[i].id);
        LONGS_EQUAL(8, reports[i + 1].id);
        CHECK(reports[i].rangeM < reports[i + 1].rangeM);
    }
}

TEST(SimHazard, NothingInViewGivesAClearReportOnceASecond) {
    build({box(1, true, -3.0, -0.5, -2.0, 0.5), box(2, false, 6.0, -0.5, 7.0, 0.5)}, Pose2{});
    runUntil(3 * core::kNsPerSec);
    LONGS_EQUAL(3, reports.size());
    const core::TimeNs expected[] = {200 * kMs, 1200 * kMs, 2200 * kMs};
    for (std::size_t i = 0; i < 3; ++i) {
        LONGS_EQUAL(0, reports[i].id);
        DOUBLES_EQUAL(0.0, reports[i].rangeM, 0.0);
        DOUBLES_EQUAL(0.0, reports[i].bearingRad, 0.0);
        DOUBLES_EQUAL(0.0, reports[i].halfWidthM, 0.0);
        LONGS_EQUAL(i, reports[i].counter);
        CHECK_EQUAL(expected[i], reports[i].time);
    }
}

TEST(SimHazard, AnObstacleLeavingTheViewIsFollowedByAClearReportAtOnce) {
    build({box(3, false, 2.0, -0.5, 3.0, 0.5)}, Pose2{});
    runUntil(500 * kMs);
    LONGS_EQUAL(2, countId(3));
    world->placeRover(Pose2{0.0, 0.0, kPi});  // turn around
    reports.clear();
    runUntil(600 * kMs);
    LONGS_EQUAL(1, reports.size());
    LONGS_EQUAL(0, reports[0].id);
    CHECK_EQUAL(600 * kMs, reports[0].time);
}

TEST(SimHazard, TheFlightClientAcceptsTheReports) {
    core::EventLog events{clock};
    hal::HazardDetector client(events);
    HazardDetectorParams params;
    build({box(3, false, 2.0, -0.5, 3.0, 0.5), box(9, true, 1.0, 1.0, 2.0, 1.5)}, Pose2{}, params);
    for (; t <= 2 * core::kNsPerSec; t += kMs) {
        clock.sleepUntil(t);
        world->advance(t, WheelArray{}, WheelArray{});
        detector->step(t);
        CanFrame f;
        while (core::isOk(flight->receive(&f))) {
            client.onFrame(f, t);
        }
    }
    LONGS_EQUAL(20, client.frameStats().accepted);
    LONGS_EQUAL(0, client.frameStats().badValue);
    LONGS_EQUAL(0, client.frameStats().gaps);
    LONGS_EQUAL(2, client.sightings().size());
}

// A world whose ids pass 255 (a generated field): the detector reports track
// numbers of its own, one per rock in view, kept while the rock is seen.
TEST(SimHazard, ObstacleIdsAbove255AreReportedAsTrackNumbersOneARock) {
    build({box(300, false, 2.0, -1.5, 2.4, -0.9), box(1000, false, 2.0, 0.9, 2.4, 1.5)}, Pose2{});
    runUntil(core::kNsPerSec);
    CHECK(reports.size() >= 10);
    std::vector<std::uint8_t> ids;
    for (const Report& r : reports) {
        CHECK(r.id >= 1);
        bool listed = false;
        for (std::uint8_t id : ids) {
            listed = listed || id == r.id;
        }
        if (!listed) {
            ids.push_back(r.id);
        }
    }
    LONGS_EQUAL(2, ids.size());   // two rocks, two tracks, the same all along
    CHECK(ids[0] != ids[1]);
    // Each track keeps its rock: the right one (bearing < 0) always the same number.
    for (const Report& r : reports) {
        const bool right = r.bearingRad < 0.0;
        for (const Report& q : reports) {
            if ((q.bearingRad < 0.0) == right) {
                LONGS_EQUAL(r.id, q.id);
            }
        }
    }
}

// Seeing goes through the terrain's index: a field of 400 rocks gives the
// same views as looking at every rock.
TEST(SimHazard, TheIndexSeesWhatAScanOfEveryRockSees) {
    std::vector<Obstacle> rocks;
    for (int i = 0; i < 400; ++i) {
        const double x = -40.0 + 4.0 * (i % 20) + 0.3 * (i % 7);
        const double y = -40.0 + 4.0 * (i / 20) + 0.2 * (i % 5);
        rocks.push_back(box(static_cast<std::uint16_t>(i + 1), false, x, y, x + 0.8, y + 0.6));
    }
    WorldConfig c;
    c.map = MapBounds{-50.0, 50.0, -50.0, 50.0};
    c.obstacles = rocks;
    const World w(c);
    for (int k = 0; k < 50; ++k) {
        const Pose2 pose{-30.0 + 1.3 * k, -25.0 + 1.1 * k, 0.37 * k};
        HazardView views[kMaxHazardReports];
        const std::size_t n = observeTerrain(pose, w.terrain(), noiseless(), views, kMaxHazardReports);
        std::vector<HazardView> all;
        for (const Obstacle& o : rocks) {
            HazardView v;
            if (observeObstacle(pose, o, noiseless(), &v)) {
                all.push_back(v);
            }
        }
        LONGS_EQUAL(std::min(all.size(), kMaxHazardReports), n);
        for (std::size_t i = 0; i < n; ++i) {
            bool found = false;
            for (const HazardView& v : all) {
                found = found || (v.obstacleId == views[i].obstacleId && v.rangeM == views[i].rangeM);
            }
            CHECK_TRUE(found);
        }
    }
}
