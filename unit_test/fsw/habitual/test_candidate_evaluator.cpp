// A leg's constraints (fsw/habitual/candidate_evaluator.hpp): the figures of a
// path against what remains of the leg's length, energy and power bounds, the
// violated bound named by the larger relative excess (power first), the power
// check that no path changes, and the least violating candidate of a session.
// Figures with e_m = 60 J/m, e_r = 40 J/rad, margins 10 % (length) and 20 %
// (energy and power), cruise 0.25 m/s: straight driving draws 15 W per unit
// of mean power factor. The table's margins are floats: figures within 1e-5.
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/rover_model/power_model.hpp"
#include "unit_test/fsw/habitual/habitual_parts.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using geometry::Point2;
using habitual::CandidateEvaluator;
using habitual::Evaluation;
using habitual::LegProgress;
using msg::LegConstraint;

namespace {

tables::HabitualTable pinnedTable() {
    tables::HabitualTable t = test::defaultTable<tables::HabitualTable>();
    t.drive_energy_j_per_m = 60.0F;
    t.turn_energy_j_per_rad = 40.0F;
    t.distance_margin_frac = 0.1F;
    t.power_margin_frac = 0.2F;
    t.cruise_speed_m_s = 0.25F;
    return t;
}

msg::LegCommandMsg leg(double maxLengthM, double maxEnergyJ, double maxPowerW = 0.0) {
    msg::LegCommandMsg l{};
    l.legId = 4;
    l.goalXM = 10.0;
    l.maxPathLengthM = maxLengthM;
    l.maxEnergyJ = maxEnergyJ;
    l.maxPowerW = maxPowerW;
    return l;
}

const Point2 kStraight[] = {{0.0, 0.0}, {10.0, 0.0}};          // 10 m, no turn: 600 J at factor 1
const Point2 kDogLeg[] = {{0.0, 0.0}, {5.0, 0.0}, {5.0, 5.0}};  // 10 m and a quarter turn

}  // namespace

TEST_GROUP(CandidateEvaluator) {
    tables::HabitualTable table = pinnedTable();
    CandidateEvaluator evaluator{table};
    LegProgress fresh{0.0, 0.0, 1.0};
};

TEST(CandidateEvaluator, ANewLegsFiguresAreItsWholeAllowedBoundsWithNothingPredicted) {
    evaluator.beginLeg(leg(20.0, 1000.0, 50.0));
    const Evaluation& e = evaluator.inForce();
    DOUBLES_EQUAL(0.0, e.lengthM, 0.0);
    DOUBLES_EQUAL(0.0, e.energyJ, 0.0);
    DOUBLES_EQUAL(18.0, e.allowedLengthM, 1e-5);
    DOUBLES_EQUAL(800.0, e.allowedEnergyJ, 1e-5);
    DOUBLES_EQUAL(40.0, e.allowedPowerW, 1e-5);
    CHECK(LegConstraint::kNone == e.violated);
    CHECK_FALSE(evaluator.haveCandidate());
}

TEST(CandidateEvaluator, APathWithinBothBoundsViolatesNothing) {
    evaluator.beginLeg(leg(20.0, 1000.0));
    const Evaluation e = evaluator.evaluate(kStraight, 2, 0.0, fresh);
    DOUBLES_EQUAL(10.0, e.lengthM, 1e-5);
    DOUBLES_EQUAL(600.0, e.energyJ, 1e-5);
    CHECK(LegConstraint::kNone == e.violated);
    DOUBLES_EQUAL(0.0, e.excess, 0.0);
    // The larger relative excess (both negative): length (10 - 18) / 20, energy (600 - 800) / 1000.
    DOUBLES_EQUAL(-0.2, e.score, 1e-5);
    DOUBLES_EQUAL(15.0, e.powerW, 1e-5);  // reported even without a power bound
    DOUBLES_EQUAL(0.0, e.allowedPowerW, 0.0);
}

TEST(CandidateEvaluator, WhatWasDrivenComesOffTheAllowedFigures) {
    evaluator.beginLeg(leg(20.0, 1000.0));
    const Evaluation e = evaluator.evaluate(kStraight, 2, 0.0, LegProgress{5.0, 300.0, 1.0});
    DOUBLES_EQUAL(13.5, e.allowedLengthM, 1e-5);  // (20 - 5) * 0.9
    DOUBLES_EQUAL(560.0, e.allowedEnergyJ, 1e-5);  // (1000 - 300) * 0.8
    CHECK(LegConstraint::kEnergy == e.violated);
    DOUBLES_EQUAL(40.0, e.excess, 1e-5);
}

TEST(CandidateEvaluator, TheLargerRelativeExcessNamesTheViolatedBound) {
    evaluator.beginLeg(leg(10.0, 1000.0));  // allowed 9 m: 1 m over (0.1); energy within
    Evaluation e = evaluator.evaluate(kStraight, 2, 0.0, fresh);
    CHECK(LegConstraint::kPathLength == e.violated);
    DOUBLES_EQUAL(1.0, e.excess, 1e-5);
    DOUBLES_EQUAL(0.1, e.score, 1e-5);
    // Both over: length 1 m of 10 (0.1), energy (600 + 40 pi/2) - 400 of 500 (0.53): energy.
    evaluator.beginLeg(leg(10.0, 500.0));
    e = evaluator.evaluate(kDogLeg, 3, 0.0, fresh);
    const double energy = 600.0 + 40.0 * 1.5707963267948966;
    DOUBLES_EQUAL(energy, e.energyJ, 1e-5);
    CHECK(LegConstraint::kEnergy == e.violated);
    DOUBLES_EQUAL(energy - 400.0, e.excess, 1e-5);
    DOUBLES_EQUAL((energy - 400.0) / 500.0, e.score, 1e-5);
}

TEST(CandidateEvaluator, TheMeanPowerFactorScalesEnergyAndPower) {
    evaluator.beginLeg(leg(20.0, 1000.0));
    const Evaluation e = evaluator.evaluate(kStraight, 2, 0.0, LegProgress{0.0, 0.0, 1.5});
    DOUBLES_EQUAL(900.0, e.energyJ, 1e-5);
    DOUBLES_EQUAL(22.5, e.powerW, 1e-5);
    CHECK(LegConstraint::kEnergy == e.violated);
}

TEST(CandidateEvaluator, AViolatedPowerBoundWinsWhateverThePath) {
    evaluator.beginLeg(leg(20.0, 1000.0, 20.0));  // allowed 16 W
    const Evaluation holds = evaluator.evaluate(kStraight, 2, 0.0, fresh);
    CHECK(LegConstraint::kNone == holds.violated);
    DOUBLES_EQUAL(16.0, holds.allowedPowerW, 1e-5);
    const Evaluation over = evaluator.evaluate(kStraight, 2, 0.0, LegProgress{0.0, 0.0, 1.2});  // 18 W
    CHECK(LegConstraint::kPower == over.violated);
    DOUBLES_EQUAL(2.0, over.excess, 1e-5);
    DOUBLES_EQUAL(0.1, over.score, 1e-5);  // 2 W of the 20 W bound
}

TEST(CandidateEvaluator, ThePowerCheckRefreshesTheFiguresInForce) {
    evaluator.beginLeg(leg(20.0, 1000.0, 20.0));
    Evaluation plan = evaluator.evaluate(kStraight, 2, 0.0, fresh);
    evaluator.setInForce(plan);
    Evaluation check = evaluator.powerCheck(1.2);
    CHECK(LegConstraint::kPower == check.violated);
    DOUBLES_EQUAL(18.0, check.powerW, 1e-5);
    DOUBLES_EQUAL(plan.lengthM, check.lengthM, 0.0);  // the path's figures kept
    // A fail-up's kPower in force is lifted when the factors fall again.
    evaluator.setInForce(check);
    check = evaluator.powerCheck(1.0);
    CHECK(LegConstraint::kNone == check.violated);
    DOUBLES_EQUAL(0.0, check.excess, 0.0);
    // No bound: never violated.
    evaluator.beginLeg(leg(20.0, 1000.0, 0.0));
    CHECK(LegConstraint::kNone == evaluator.powerCheck(50.0).violated);
}

TEST(CandidateEvaluator, NoPathGivesTheAllowedFiguresAndNoPath) {
    evaluator.beginLeg(leg(20.0, 1000.0));
    const Evaluation e = evaluator.noPath(LegProgress{2.0, 100.0, 1.0});
    CHECK(LegConstraint::kNoPath == e.violated);
    DOUBLES_EQUAL(0.0, e.lengthM, 0.0);
    DOUBLES_EQUAL(0.0, e.excess, 0.0);
    DOUBLES_EQUAL(16.2, e.allowedLengthM, 1e-5);
    DOUBLES_EQUAL(720.0, e.allowedEnergyJ, 1e-5);
}

TEST(CandidateEvaluator, KeepsTheLeastViolatingCandidate) {
    evaluator.beginLeg(leg(10.0, 1000.0));
    const Evaluation dogLeg = evaluator.evaluate(kDogLeg, 3, 0.0, fresh);   // 1 m over
    const Point2 longer[] = {{0.0, 0.0}, {6.0, 3.0}, {12.0, 0.0}};
    const Evaluation worse = evaluator.evaluate(longer, 3, 0.0, fresh);    // 4.4 m over
    evaluator.keepCandidate(longer, 3, worse);
    CHECK_TRUE(evaluator.haveCandidate());
    DOUBLES_EQUAL(worse.score, evaluator.candidate().score, 0.0);
    evaluator.keepCandidate(kDogLeg, 3, dogLeg);
    DOUBLES_EQUAL(dogLeg.score, evaluator.candidate().score, 0.0);
    LONGS_EQUAL(3, evaluator.candidateCount());
    DOUBLES_EQUAL(5.0, evaluator.candidatePath()[2].y, 0.0);
    evaluator.keepCandidate(longer, 3, worse);  // a worse one does not replace it
    DOUBLES_EQUAL(dogLeg.score, evaluator.candidate().score, 0.0);
    // A path longer than a trajectory is never kept.
    Evaluation best = dogLeg;
    best.score = -1.0;
    evaluator.keepCandidate(kStraight, msg::kMaxTrajectoryPoints + 1, best);
    DOUBLES_EQUAL(dogLeg.score, evaluator.candidate().score, 0.0);
    evaluator.clearCandidate();
    CHECK_FALSE(evaluator.haveCandidate());
    LONGS_EQUAL(0, evaluator.candidateCount());
}

TEST(CandidateEvaluator, ConstraintNamesAreTheEventsWords) {
    STRCMP_EQUAL("path length", habitual::constraintName(LegConstraint::kPathLength));
    STRCMP_EQUAL("energy", habitual::constraintName(LegConstraint::kEnergy));
    STRCMP_EQUAL("power", habitual::constraintName(LegConstraint::kPower));
    STRCMP_EQUAL("no path", habitual::constraintName(LegConstraint::kNoPath));
    STRCMP_EQUAL("cannot follow", habitual::constraintName(LegConstraint::kCannotFollow));
}
