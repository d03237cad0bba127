// The search's factor ring (cc_factor_ring.hpp): a level saved and restored
// from its slot needs no refactorisation and no pivot; a level whose slot a
// deeper one took is refactorised from its basis, to the same optimum.
#include <cmath>

#include "fsw/deliberative/cc_factor_ring.hpp"
#include "fsw/deliberative/cc_lp.hpp"
#include "fsw/deliberative/cc_workspace.hpp"
#include "unit_test/fsw/deliberative/cc_parts_rig.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::deliberative;
using rse::test::kBoxLeft;
using rse::test::prepareWorkspace;
using rse::test::wallWithGap;

namespace {

CcWorkspace ws;  // static storage
CcFactorRing ring;
LpBasis levels[3];

void pushPair(std::size_t t, std::size_t i, std::size_t j) {
    bool feasible = false;
    CHECK(ws.lp.addPair(t, i, j, ws.margins.margin(t, i, j), ws.margins.margin(t + 1, i, j), &feasible) ==
          rse::core::Status::kOk);
    CHECK(feasible);
}

}  // namespace

TEST_GROUP(CcFactorRing){};

TEST(CcFactorRing, SlotsFitThePool) {
    CHECK(prepareWorkspace(ws, wallWithGap(10)));
    ring.reset(ws.lp.variables());
    const std::size_t fit = CcFactorRing::kPoolDoubles / LpSolver::factorDoubles(ws.lp.variables());
    LONGS_EQUAL(fit < CcFactorRing::kMaxSlots ? fit : CcFactorRing::kMaxSlots, ring.slots());
    CHECK(ring.slots() > 1);
    LONGS_EQUAL(0, ring.restores());
}

TEST(CcFactorRing, ALevelComesBackFromItsSlot) {
    CHECK(prepareWorkspace(ws, wallWithGap(10)));
    ring.reset(ws.lp.variables());
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);  // the root: no pairs
    const double rootCost = ws.lp.cost();
    ring.save(ws.lp.solver(), 0, &levels[0]);
    // Segments 4 and 5 left of the wall: the straight line's mu_5 and mu_6
    // are not, so these rows enter the basis.
    pushPair(4, 0, kBoxLeft);
    pushPair(5, 0, kBoxLeft);
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);
    (void)ws.lp.popPairs(0);
    CHECK_FALSE(ws.lp.solver().basisValid());  // the basis used the dropped rows
    const std::uint32_t refactors = ws.lp.solver().refactorizations();
    ring.restore(ws.lp.solver(), 0, &levels[0]);
    LONGS_EQUAL(1, ring.restores());
    LONGS_EQUAL(refactors, ws.lp.solver().refactorizations());
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);
    LONGS_EQUAL(0, ws.lp.solver().lastIterations());
    DOUBLES_EQUAL(rootCost, ws.lp.cost(), 1e-9);
}

TEST(CcFactorRing, ALevelWhoseSlotWasTakenIsRefactorised) {
    CHECK(prepareWorkspace(ws, wallWithGap(10)));
    ring.reset(ws.lp.variables());
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);
    const double rootCost = ws.lp.cost();
    ring.save(ws.lp.solver(), 0, &levels[0]);
    pushPair(4, 0, kBoxLeft);
    pushPair(5, 0, kBoxLeft);
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);
    ring.save(ws.lp.solver(), ring.slots(), &levels[1]);  // the same slot as level 0
    (void)ws.lp.popPairs(0);
    ring.restore(ws.lp.solver(), 0, &levels[0]);
    LONGS_EQUAL(0, ring.restores());
    CHECK(ws.lp.solver().basisValid());
    CHECK(ws.lp.solve(10000) == LpStatus::kOptimal);
    DOUBLES_EQUAL(rootCost, ws.lp.cost(), 1e-9);
    // Restored, level 0 took its slot back: the next restore copies it.
    (void)ws.lp.popPairs(0);
    ws.lp.solver().invalidateBasis();
    ring.restore(ws.lp.solver(), 0, &levels[0]);
    LONGS_EQUAL(1, ring.restores());
}
