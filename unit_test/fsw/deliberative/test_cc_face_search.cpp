// The branch and bound over faces alone (cc_face_search.hpp), with no seed:
// exhausted, it finds the least cost over every face assignment of a tiny
// problem; the presolve proves "no plan" with no LP; a node abandoned leaves
// the search incomplete with its parent's bound; the guide's face is tried
// first.
#include <cmath>

#include "fsw/deliberative/cc_face_search.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_plan_checks.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::core::Status;
using rse::test::fillFaces;
using rse::test::kBoxBottom;
using rse::test::kBoxTop;
using rse::test::boxAboveTheWay;
using rse::test::makeBox;
using rse::test::prepareWorkspace;
using rse::test::randomInstance;
using rse::test::solveFaces;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // static storage
CcFaceSearch search;
CcFaceTable faces;

void startSearch(const CcProblem& p, const CcPlannerParams& params) {
    CHECK(prepareWorkspace(ws, p, params));
    search.resetCounts();
    search.prepare(ws.lp.variables());
}

// The search until no node is left, then the root's and the search's
// units in order; the units run.
std::uint32_t searchToEnd(const CcFaceTable* guide) {
    std::uint32_t units = 0;
    while (units < 1000000 && search.searchUnit(ws, guide)) {
        ++units;
    }
    search.stopExhausted();
    return units;
}

std::uint32_t runSearch(const CcFaceTable* guide) {
    std::uint32_t units = 0;
    while (units < 1000000 && !search.rootUnit(ws, guide)) {
        ++units;
    }
    return units + searchToEnd(guide);
}

// The least cost over every face assignment, each its fixed-face LP.
double bruteForce(const CcProblem& p) {
    std::size_t combos = 1;
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            combos *= p.obstacles[i].faceCount;
        }
    }
    double best = INFINITY;
    for (std::size_t c = 0; c < combos; ++c) {
        std::size_t rest = c;
        for (std::size_t t = 0; t < p.steps; ++t) {
            for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                faces[t][i] = static_cast<std::uint8_t>(rest % p.obstacles[i].faceCount);
                rest /= p.obstacles[i].faceCount;
            }
        }
        if (solveFaces(ws, faces) == LpStatus::kOptimal && ws.lp.cost() < best) {
            best = ws.lp.cost();
        }
    }
    return best;
}

}  // namespace

TEST_GROUP(CcFaceSearch){};

TEST(CcFaceSearch, ExhaustedItFindsTheLeastCostOverEveryAssignment) {
    CcPlannerParams params;
    params.relativeGap = 0.0;
    for (std::uint64_t seed = 0; seed < 3; ++seed) {
        const CcProblem p = randomInstance(77 + seed, 3, 2, 0.01);
        CHECK(prepareWorkspace(ws, p, params));
        const double best = bruteForce(p);
        startSearch(p, params);
        (void)runSearch(nullptr);
        CHECK(search.exhausted());
        CHECK(search.nodes() > 0);
        if (!std::isfinite(best)) {
            CHECK(ws.incumbent.best().status == CcStatus::kNoPlan);
            continue;
        }
        DOUBLES_EQUAL(best, ws.incumbent.evenCost(), 1e-6);
        CHECK(checkPlan(p, ws.incumbent.best()) == Status::kOk);
        DOUBLES_EQUAL(ws.incumbent.evenCost(), search.lowerBound(ws.incumbent.evenCost(), 0.0), 0.0);
    }
}

TEST(CcFaceSearch, ThePresolveProvesNoPlanWithoutAnLp) {
    CcProblem p = wallWithGap(10);
    p.obstacles[1] = makeBox(1, 18.0, 21.0, 3.0, 7.0);  // covers the goal (20, 5)
    startSearch(p, CcPlannerParams{});
    CHECK(search.rootUnit(ws, nullptr));  // at once
    CHECK_FALSE(ws.run.running());
    CHECK_FALSE(search.searchUnit(ws, nullptr));
    search.stopExhausted();
    CHECK(search.exhausted());
    LONGS_EQUAL(0, search.nodes());
    LONGS_EQUAL(0, ws.lp.solver().iterations());
    CHECK(ws.incumbent.best().status == CcStatus::kNoPlan);
}

TEST(CcFaceSearch, AnAbandonedNodeLeavesTheSearchIncomplete) {
    startSearch(wallWithGap(10), CcPlannerParams{});
    CHECK_FALSE(search.rootUnit(ws, nullptr));  // the presolve; the root's LP started
    CHECK(ws.run.running());
    search.abandonNode(ws.run);
    CHECK_FALSE(ws.run.running());
    search.stopExhausted();
    CHECK_FALSE(search.exhausted());
    CHECK(search.incomplete());
    // Nothing below the abandoned root is bounded: its bound is 0.
    DOUBLES_EQUAL(0.0, search.lowerBound(INFINITY, 0.002), 0.0);
}

TEST(CcFaceSearch, TheGuidesFaceIsTriedFirst) {
    // A box across the straight line: a guide over its top makes the first
    // dive's plan go over, a guide under its bottom under; every search,
    // guided either way or not, ends at the same optimum.
    CcProblem p = boxAboveTheWay(6);
    p.obstacles[0] = makeBox(0, 3.0, 5.0, -1.0, 2.0);
    CcPlannerParams params;
    params.relativeGap = 0.0;
    double optimum[3] = {};
    double firstHighest[3] = {};  // the first incumbent's highest and lowest means
    double firstLowest[3] = {};
    CcFaceTable guides[2];
    fillFaces(guides[0], kBoxTop);
    fillFaces(guides[1], kBoxBottom);
    for (std::size_t run = 0; run < 3; ++run) {
        const CcFaceTable* guide = run < 2 ? &guides[run] : nullptr;
        startSearch(p, params);
        std::uint32_t units = 0;
        while (units < 100000 && !search.rootUnit(ws, guide)) {
            ++units;
        }
        while (units < 100000 && ws.incumbent.improvements() == 0 && search.searchUnit(ws, guide)) {
            ++units;
        }
        const CcPlan& first = ws.incumbent.best();
        firstHighest[run] = -INFINITY;
        firstLowest[run] = INFINITY;
        for (std::size_t tau = 0; tau <= p.steps; ++tau) {
            firstHighest[run] = first.meanY[tau] > firstHighest[run] ? first.meanY[tau] : firstHighest[run];
            firstLowest[run] = first.meanY[tau] < firstLowest[run] ? first.meanY[tau] : firstLowest[run];
        }
        (void)searchToEnd(guide);
        CHECK(search.exhausted());
        CHECK(search.maxDepth() > 0);
        optimum[run] = ws.incumbent.evenCost();
    }
    CHECK(firstHighest[0] > 2.0 && firstLowest[0] > -1.0);  // over the box
    CHECK(firstLowest[1] < -1.0 && firstHighest[1] < 2.0);  // under it
    DOUBLES_EQUAL(optimum[2], optimum[0], 1e-9);
    DOUBLES_EQUAL(optimum[2], optimum[1], 1e-9);
}
