// The benchmark's instance generator (unit_test/bench/cc_instances.hpp):
// determinism, and every instance of every set well formed, with its start and
// goal free, convex obstacles with unit normals inside the site, the on-line
// obstacles across the straight path and the others off it.
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "unit_test/bench/cc_common.hpp"
#include "unit_test/bench/cc_instances.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::test::cc;

namespace {

bool sameObstacle(const PlanObstacle& a, const PlanObstacle& b) {
    if (a.id != b.id || a.faceCount != b.faceCount) {
        return false;
    }
    for (std::size_t j = 0; j < a.faceCount; ++j) {
        if (a.normalX[j] != b.normalX[j] || a.normalY[j] != b.normalY[j] || a.offset[j] != b.offset[j]) {
            return false;
        }
    }
    return true;
}

bool sameProblem(const CcProblem& a, const CcProblem& b) {
    if (a.steps != b.steps || a.startX != b.startX || a.startY != b.startY || a.goalX != b.goalX ||
        a.goalY != b.goalY || a.xMin != b.xMin || a.xMax != b.xMax || a.yMin != b.yMin || a.yMax != b.yMax ||
        a.riskBound != b.riskBound || a.processSigmaM != b.processSigmaM || a.obstacleCount != b.obstacleCount ||
        std::memcmp(a.startCov, b.startCov, sizeof a.startCov) != 0) {
        return false;
    }
    for (std::size_t i = 0; i < a.obstacleCount; ++i) {
        if (!sameObstacle(a.obstacles[i], b.obstacles[i])) {
            return false;
        }
    }
    return true;
}

double distanceToStraightPath(const CcProblem& p, double x, double y) {
    const double lx = p.goalX - p.startX, ly = p.goalY - p.startY;
    const double len = std::hypot(lx, ly);
    const double s = std::clamp(((x - p.startX) * lx + (y - p.startY) * ly) / len, 0.0, len);
    return std::hypot(x - (p.startX + s * lx / len), y - (p.startY + s * ly / len));
}

// Every property the generator promises, for one instance.
void checkInstance(const CcProblem& p, const InstanceParams& params, std::size_t onLine) {
    STRCMP_EQUAL("", validateProblem(p).c_str());
    LONGS_EQUAL(params.steps, p.steps);
    LONGS_EQUAL(params.obstacles, p.obstacleCount);
    DOUBLES_EQUAL(params.riskBound, p.riskBound, 0.0);
    DOUBLES_EQUAL(params.startVarM2, p.startCov[0], 0.0);
    DOUBLES_EQUAL(params.startVarM2, p.startCov[3], 0.0);
    DOUBLES_EQUAL(0.0, p.startCov[1], 0.0);
    DOUBLES_EQUAL(params.processSigmaM, p.processSigmaM, 0.0);
    CHECK(p.startX >= 1.0 && p.startX <= 1.0 + params.endBandM);
    CHECK(p.goalX >= params.siteLengthM - 1.0 - params.endBandM && p.goalX <= params.siteLengthM - 1.0);
    for (std::size_t i = 0; i < p.obstacleCount; ++i) {
        const PlanObstacle& o = p.obstacles[i];
        LONGS_EQUAL(i + 1, o.id);
        CHECK(o.faceCount >= params.minFaces && o.faceCount <= params.maxFaces);
        const std::vector<Point> v = obstacleVertices(o);
        LONGS_EQUAL(o.faceCount, v.size());  // closed, convex, counter-clockwise
        double area2 = 0.0;
        for (std::size_t k = 0; k < v.size(); ++k) {
            const Point& a = v[k];
            const Point& b = v[(k + 1) % v.size()];
            area2 += a.x * b.y - b.x * a.y;
            // Inside the site with the clearance; every vertex on every face's inner side.
            CHECK(a.x >= params.edgeClearanceM - 1e-9 && a.x <= params.siteLengthM - params.edgeClearanceM + 1e-9);
            CHECK(a.y >= params.edgeClearanceM - 1e-9 && a.y <= params.siteWidthM - params.edgeClearanceM + 1e-9);
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                CHECK(o.normalX[j] * a.x + o.normalY[j] * a.y <= o.offset[j] + 1e-9);
            }
            // Every edge turns left (strictly convex).
            const Point& c = v[(k + 2) % v.size()];
            CHECK((b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x) > 0.0);
        }
        CHECK(area2 > 0.0);
        for (std::size_t j = 0; j < o.faceCount; ++j) {
            DOUBLES_EQUAL(1.0, std::hypot(o.normalX[j], o.normalY[j]), 1e-12);
        }
        // Start and goal free with the clearance, i.e. some face holds them by that much.
        CHECK(obstacleSlack(o, p.startX, p.startY) >= params.clearanceM);
        CHECK(obstacleSlack(o, p.goalX, p.goalY) >= params.clearanceM);
        const bool blocks = segmentIntersectsObstacle(o, p.startX, p.startY, p.goalX, p.goalY);
        if (i < onLine) {
            CHECK(blocks);
        } else if (params.offLineClearanceM >= 0.0) {
            CHECK(!blocks);
            for (const Point& a : v) {
                CHECK(distanceToStraightPath(p, a.x, a.y) >= params.offLineClearanceM);
            }
        }
    }
}

}  // namespace

TEST_GROUP(CcInstances){};

TEST(CcInstances, SameSeedSameInstanceOtherSeedOther) {
    InstanceParams params;
    const CcProblem a = generateInstance(42, params);
    const CcProblem b = generateInstance(42, params);
    const CcProblem c = generateInstance(43, params);
    CHECK(sameProblem(a, b));
    CHECK(!sameProblem(a, c));
    CHECK(a.startX != c.startX);
    params.obstacles = 6;
    CHECK(!sameProblem(a, generateInstance(42, params)));
}

TEST(CcInstances, ProvableSetIsFiftyValidInstancesEachBlockingTheStraightPath) {
    const std::vector<CcProblem> set = provableSet(0.05);
    LONGS_EQUAL(50, set.size());
    InstanceParams params;
    params.steps = 10;
    params.obstacles = 4;
    params.riskBound = 0.05;
    for (std::size_t k = 0; k < set.size(); ++k) {
        checkInstance(set[k], params, 1);
        CHECK(sameProblem(set[k], generateInstance(kProvableSeedBase + k, params)));
    }
    // The set at another Delta is the same geometry.
    const std::vector<CcProblem> strict = provableSet(1e-3);
    for (std::size_t k = 0; k < set.size(); ++k) {
        CcProblem same = strict[k];
        same.riskBound = 0.05;
        CHECK(sameProblem(set[k], same));
    }
}

TEST(CcInstances, EightObstacleAndLargeSetsAreValid) {
    InstanceParams eight;
    eight.steps = 10;
    eight.obstacles = 8;
    eight.riskBound = 1e-3;
    for (const CcProblem& p : provableSet(1e-3, 12, 8)) {
        checkInstance(p, eight, 1);
    }
    InstanceParams large;
    large.steps = 20;
    large.obstacles = 8;
    large.riskBound = 0.05;
    large.offLineClearanceM = -1.0;
    for (const CcProblem& p : largeSet(0.05, 12)) {
        checkInstance(p, large, 4);
    }
}

TEST(CcInstances, FewerStepsGiveTheSameScenes) {
    InstanceParams shorter;
    shorter.steps = 8;
    shorter.obstacles = 4;
    shorter.riskBound = 0.05;
    const std::vector<CcProblem> eight = provableSet(0.05, 12, 4, 8);
    const std::vector<CcProblem> ten = provableSet(0.05, 12);
    LONGS_EQUAL(12, eight.size());
    for (std::size_t k = 0; k < eight.size(); ++k) {
        checkInstance(eight[k], shorter, 1);
        LONGS_EQUAL(8, eight[k].steps);
        LONGS_EQUAL(ten[k].obstacleCount, eight[k].obstacleCount);
        DOUBLES_EQUAL(ten[k].goalX, eight[k].goalX, 0.0);
        DOUBLES_EQUAL(ten[k].goalY, eight[k].goalY, 0.0);
        for (std::size_t i = 0; i < ten[k].obstacleCount; ++i) {
            DOUBLES_EQUAL(ten[k].obstacles[i].offset[0], eight[k].obstacles[i].offset[0], 0.0);
        }
    }
}

TEST(CcInstances, DiagonalBoxCornerCrossesTheDiagonal) {
    const CcProblem p = diagonalBoxInstance(0.05);
    STRCMP_EQUAL("", validateProblem(p).c_str());
    LONGS_EQUAL(1, p.obstacleCount);
    // The straight step start -> goal cuts the box; the corner (2, 4) lies
    // 1.41 m across the diagonal, and start and goal are clear of the box.
    CHECK(segmentIntersectsObstacle(p.obstacles[0], p.startX, p.startY, p.goalX, p.goalY));
    CHECK(segmentIntersectsObstacle(p.obstacles[0], 2.01, 2.01, 3.99, 3.99));
    CHECK(!pointInObstacle(p.obstacles[0], 1.99, 1.99));
    CHECK(!pointInObstacle(p.obstacles[0], 4.01, 4.01));
    CHECK(obstacleSlack(p.obstacles[0], p.startX, p.startY) >= 2.0);
    CHECK(obstacleSlack(p.obstacles[0], p.goalX, p.goalY) >= 6.0);
}
