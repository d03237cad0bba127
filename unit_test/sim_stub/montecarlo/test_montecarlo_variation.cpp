// What a Monte Carlo seed varies (sim_stub/montecarlo/campaign.hpp,
// docs/montecarlo.md "What a seed varies"): the sensor noise seed, the hidden
// rocks' placement within their limits (off the start and the goal, inside the
// map) and the fault times within their windows; the same seed gives the same
// scenario, and the random stream is pinned so old campaigns stay reproducible.
#include <cmath>
#include <cstdint>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "sim_stub/montecarlo/campaign.hpp"
#include "sim_stub/scenario/field_rocks.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::sim;
using namespace rse::sim::mc;

namespace {

constexpr double kGoalX = 20.0;
constexpr double kGoalY = 0.0;

Scenario demo() { return loadScenarioFile(kDefaultMissionScenario); }

double seconds(rse::core::TimeNs t) { return 1e-9 * static_cast<double>(t); }

bool sameShape(const ConvexPolygon& a, const ConvexPolygon& b) {
    if (a.n != b.n) {
        return false;
    }
    for (std::size_t i = 0; i < a.n; ++i) {
        if (a.v[i].x != b.v[i].x || a.v[i].y != b.v[i].y) {
            return false;
        }
    }
    return true;
}

}  // namespace

TEST_GROUP(MonteCarloVariation) {};

TEST(MonteCarloVariation, TheStreamIsPinned) {
    // SplitMix64 from (seed, purpose): these numbers are what every machine
    // draws; a change here changes every campaign (bump kVariationVersion).
    SeedStream a(1, 0x726f636b);
    const std::uint64_t first = a.next();
    const std::uint64_t second = a.next();
    SeedStream b(1, 0x726f636b);
    CHECK(first == b.next());
    CHECK(second == b.next());
    CHECK(first != second);
    SeedStream other(2, 0x726f636b);
    CHECK(first != other.next());
    // Seed 7, purpose 1: state 7 x 0x9e3779b97f4a7c15 XOR 3, then SplitMix64
    // (these two values computed apart from this code, from the published algorithm).
    SeedStream pinned(7, 1);
    CHECK(pinned.next() == 0xd7c07017388fa2afULL);
    CHECK(pinned.next() == 0x4f6d6a273422e220ULL);
    for (int i = 0; i < 1000; ++i) {
        const double u = pinned.uniform(-4.0, 4.0);
        CHECK(u >= -4.0 && u < 4.0);
    }
}

TEST(MonteCarloVariation, TheSameSeedGivesTheSameScenario) {
    Scenario a = demo();
    Scenario b = demo();
    const Variation va = varyScenario(&a, 42, kGoalX, kGoalY);
    const Variation vb = varyScenario(&b, 42, kGoalX, kGoalY);
    CHECK(a.seed == b.seed);
    LONGS_EQUAL(a.obstacles.size(), b.obstacles.size());
    for (std::size_t i = 0; i < a.obstacles.size(); ++i) {
        CHECK(sameShape(a.obstacles[i].shape, b.obstacles[i].shape));
    }
    LONGS_EQUAL(a.faults.size(), b.faults.size());
    for (std::size_t i = 0; i < a.faults.size(); ++i) {
        CHECK(a.faults[i].at == b.faults[i].at);
    }
    LONGS_EQUAL(va.rockShifts.size(), vb.rockShifts.size());
    LONGS_EQUAL(va.faultTimesS.size(), vb.faultTimesS.size());
}

TEST(MonteCarloVariation, EachSeedVariesNoiseRocksAndFaultsWithinTheirLimits) {
    const Scenario base = demo();
    std::size_t hidden = 0;
    for (const Obstacle& ob : base.obstacles) {
        hidden += ob.known ? 0 : 1;
    }
    CHECK(hidden >= 1);
    CHECK(!base.faults.empty());
    const double keep = base.rover.radiusM + kRockEndClearanceM;
    std::set<std::pair<double, double>> shifts;
    std::set<double> faultTimes;
    for (std::uint64_t seed = 1; seed <= 60; ++seed) {
        Scenario s = base;
        const Variation v = varyScenario(&s, seed, kGoalX, kGoalY);
        CHECK(s.seed == seed);
        CHECK(v.noiseSeed == seed);
        LONGS_EQUAL(hidden, v.rockShifts.size());
        std::size_t h = 0;
        for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
            const Obstacle& was = base.obstacles[i];
            const Obstacle& now = s.obstacles[i];
            if (was.known) {
                CHECK(sameShape(was.shape, now.shape));  // the orbital map's rocks stay
                continue;
            }
            const Vec2 d = v.rockShifts[h++];
            CHECK(std::fabs(d.x) <= kRockShiftXM && std::fabs(d.y) <= kRockShiftYM);
            shifts.insert({d.x, d.y});
            for (std::size_t k = 0; k < now.shape.n; ++k) {
                DOUBLES_EQUAL(was.shape.v[k].x + d.x, now.shape.v[k].x, 1e-12);
                DOUBLES_EQUAL(was.shape.v[k].y + d.y, now.shape.v[k].y, 1e-12);
                CHECK(s.map.contains(now.shape.v[k]));
            }
            CHECK(distanceToPolygon(Vec2{s.start.x, s.start.y}, now.shape) >= keep);
            CHECK(distanceToPolygon(Vec2{kGoalX, kGoalY}, now.shape) >= keep);
        }
        LONGS_EQUAL(base.faults.size(), v.faultTimesS.size());
        for (std::size_t i = 0; i < base.faults.size(); ++i) {
            const double at = seconds(base.faults[i].at);
            const double drawn = v.faultTimesS[i];
            CHECK(drawn >= std::fmax(at - kFaultWindowS, kEarliestFaultS) && drawn <= at + kFaultWindowS);
            faultTimes.insert(drawn);
        }
        for (std::size_t i = 1; i < s.faults.size(); ++i) {
            CHECK(s.faults[i - 1].at <= s.faults[i].at);  // back in time order
        }
    }
    // Different seeds, different draws (60 seeds: practically all distinct).
    CHECK(shifts.size() >= 58);
    CHECK(faultTimes.size() >= 110);
}

TEST(MonteCarloVariation, FaultsMoveWithTheirEndsAndNeverBeforeTheEarliest) {
    Scenario s = demo();
    s.faults.clear();
    FaultSpec early;
    early.type = FaultType::kSensorDropout;
    early.at = 8 * rse::core::kNsPerSec;
    early.until = 12 * rse::core::kNsPerSec;
    s.faults.push_back(early);
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        Scenario t = s;
        const Variation v = varyScenario(&t, seed, kGoalX, kGoalY);
        const double at = seconds(t.faults[0].at);
        DOUBLES_EQUAL(v.faultTimesS[0], at, 1e-9);
        CHECK(at >= kEarliestFaultS && at <= 8.0 + kFaultWindowS);
        DOUBLES_EQUAL(4.0, seconds(t.faults[0].until - t.faults[0].at), 1e-9);  // the interval keeps its length
    }
}

TEST(MonteCarloVariation, ARockThatCannotMoveStaysPut) {
    // The map is the hidden rock's bounding box: every shift leaves the map.
    Scenario s = demo();
    const Obstacle* rock = nullptr;
    for (const Obstacle& ob : s.obstacles) {
        rock = ob.known ? rock : &ob;
    }
    CHECK(rock != nullptr);
    MapBounds box{1e9, -1e9, 1e9, -1e9};
    for (std::size_t k = 0; k < rock->shape.n; ++k) {
        box.xMin = std::fmin(box.xMin, rock->shape.v[k].x);
        box.xMax = std::fmax(box.xMax, rock->shape.v[k].x);
        box.yMin = std::fmin(box.yMin, rock->shape.v[k].y);
        box.yMax = std::fmax(box.yMax, rock->shape.v[k].y);
    }
    s.map = box;
    const ConvexPolygon before = rock->shape;
    const Variation v = varyScenario(&s, 9, kGoalX, kGoalY);
    LONGS_EQUAL(1, v.rockShifts.size());
    DOUBLES_EQUAL(0.0, v.rockShifts[0].x, 0.0);
    DOUBLES_EQUAL(0.0, v.rockShifts[0].y, 0.0);
    CHECK(sameShape(before, rock->shape));
}

TEST(MonteCarloVariation, ARockIsKeptOffTheGoal) {
    // The goal right beside the hidden rock (0.8 m from it): only the draws
    // that take the rock the footprint and the clearance away from it are kept.
    Scenario base = demo();
    const double keep = base.rover.radiusM + kRockEndClearanceM;
    std::size_t moved = 0;
    for (std::uint64_t seed = 1; seed <= 40; ++seed) {
        Scenario s = base;
        const Variation v = varyScenario(&s, seed, 12.6, 1.5);
        for (const Obstacle& ob : s.obstacles) {
            if (!ob.known) {
                CHECK(distanceToPolygon(Vec2{12.6, 1.5}, ob.shape) >= keep);
            }
        }
        moved += v.rockShifts[0].x != 0.0 || v.rockShifts[0].y != 0.0 ? 1 : 0;
    }
    LONGS_EQUAL(40, moved);  // a fitting draw is always found in kRockDraws
}

// A scenario with a [field]: each seed flies a field of its own, drawn from
// the field's model with a seed of the run seed's stream (recorded), cleared
// round the start and the goal flown; the same seed draws the same field; the
// field's rocks are not shifted (the row lists no thousand shifts), and the
// scenario's own obstacles are kept.
TEST(MonteCarloVariation, AGeneratedFieldIsDrawnAfreshForEachSeed) {
    Scenario base = loadScenarioFile("sim_stub/scenarios/rock_field_100m.toml");
    CHECK(base.field.present);
    const FieldCounts before = fieldCounts(base);
    CHECK(before.rocks > 300);
    // One obstacle of the file's own, hidden, beside the field.
    Obstacle own;
    own.id = 7;
    own.known = false;
    own.shape.n = 4;
    own.shape.v[0] = {50.0, 5.0};
    own.shape.v[1] = {50.5, 5.0};
    own.shape.v[2] = {50.5, 5.5};
    own.shape.v[3] = {50.0, 5.5};
    base.obstacles.insert(base.obstacles.begin(), own);
    const double goalX = 100.0, goalY = 40.0;   // a --goto elsewhere than the scenario's goal
    std::set<std::uint64_t> fieldSeeds;
    std::set<std::size_t> counts;
    for (std::uint64_t seed = 1; seed <= 6; ++seed) {
        Scenario s = base;
        const Variation v = varyScenario(&s, seed, goalX, goalY);
        CHECK_TRUE(v.field);
        CHECK(v.fieldSeed == s.field.rocks.seed);
        fieldSeeds.insert(v.fieldSeed);
        const FieldCounts c = fieldCounts(s);
        counts.insert(c.rocks);
        CHECK(c.rocks > 200);
        CHECK(c.known > 0 && c.known < c.rocks);
        // Only the file's own hidden rock was shifted, and it is still there.
        LONGS_EQUAL(1, v.rockShifts.size());
        LONGS_EQUAL(7, s.obstacles[0].id);
        // No field rock within clear_m of the start or of the goal flown.
        const double reach = s.field.clearM + s.rover.radiusM;
        for (const Obstacle& ob : s.obstacles) {
            if (ob.id < kFirstFieldRockId) {
                continue;
            }
            CHECK(distanceToPolygon(Vec2{s.start.x, s.start.y}, ob.shape) >= reach - 1e-9);
            CHECK(distanceToPolygon(Vec2{goalX, goalY}, ob.shape) >= reach - 1e-9);
        }
        // The same seed, the same field.
        Scenario again = base;
        const Variation w = varyScenario(&again, seed, goalX, goalY);
        CHECK(w.fieldSeed == v.fieldSeed);
        LONGS_EQUAL(s.obstacles.size(), again.obstacles.size());
        for (std::size_t i = 0; i < s.obstacles.size(); ++i) {
            CHECK_TRUE(sameShape(s.obstacles[i].shape, again.obstacles[i].shape));
        }
        // The scenario's own mission is untouched (the goal flown is the campaign's).
        DOUBLES_EQUAL(base.mission.goalX, s.mission.goalX, 0.0);
    }
    LONGS_EQUAL(6, fieldSeeds.size());
    CHECK(counts.size() >= 4);   // different fields, different counts
}
