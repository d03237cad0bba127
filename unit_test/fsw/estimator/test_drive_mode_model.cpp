// The hidden Markov model alone: transition rows, likelihood table, the filter's
// prediction, correction, floor, declaration and power factor.
#include <cmath>

#include "fsw/estimator/drive_mode_estimator.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using estimator::CurrentReading;
using estimator::DriveModeFilter;
using estimator::DriveObservation;
using estimator::FaultReading;
using estimator::observationLikelihood;
using estimator::transitionProbability;
using estimator::TrackReading;
using msg::DriveMode;

namespace {

constexpr DriveMode kModes[] = {DriveMode::kNominal, DriveMode::kDegraded, DriveMode::kFailed, DriveMode::kUnknown};

tables::DriveHealthModelTable defaultModel() {
    tables::DriveHealthModelTable model{};
    for (std::size_t i = 0; i < tables::kDefaultTableImageCount; ++i) {
        const tables::TableImageRef& ref = tables::kDefaultTableImages[i];
        if (tables::decodeTable(ref.data, ref.length, &model).ok()) {
            return model;
        }
    }
    FAIL("no default DRIVE_HEALTH_MODEL image");
    return model;
}

DriveObservation observation(TrackReading track, CurrentReading current, FaultReading fault, double ratio = 1.0) {
    DriveObservation o;
    o.track = track;
    o.current = current;
    o.fault = fault;
    o.currentRatio = ratio;
    o.ratioMeasured = current != CurrentReading::kNone;
    return o;
}

double p(const DriveModeFilter& f, DriveMode m) { return f.probability(m); }

}  // namespace

TEST_GROUP(DriveModeModel) {
    tables::DriveHealthModelTable model = defaultModel();
};

TEST(DriveModeModel, DefaultTableIsTheDocumentedOne) {
    DOUBLES_EQUAL(0.0001, model.p_degrade, 1e-9);
    DOUBLES_EQUAL(0.9, model.declare_probability, 1e-6);
    DOUBLES_EQUAL(1.25, model.current_ratio_high, 1e-6);
}

TEST(DriveModeModel, TransitionRowsHoldTheTableValuesAndSumToOne) {
    DOUBLES_EQUAL(model.p_degrade, transitionProbability(DriveMode::kNominal, DriveMode::kDegraded, model), 1e-12);
    DOUBLES_EQUAL(model.p_fail_nominal, transitionProbability(DriveMode::kNominal, DriveMode::kFailed, model), 1e-12);
    DOUBLES_EQUAL(model.p_unknown, transitionProbability(DriveMode::kNominal, DriveMode::kUnknown, model), 1e-12);
    DOUBLES_EQUAL(model.p_recover, transitionProbability(DriveMode::kDegraded, DriveMode::kNominal, model), 1e-12);
    DOUBLES_EQUAL(model.p_fail_degraded, transitionProbability(DriveMode::kDegraded, DriveMode::kFailed, model), 1e-12);
    DOUBLES_EQUAL(model.p_unknown, transitionProbability(DriveMode::kFailed, DriveMode::kUnknown, model), 1e-12);
    DOUBLES_EQUAL(model.p_leave_unknown, transitionProbability(DriveMode::kUnknown, DriveMode::kNominal, model), 1e-12);
    // Failed is absorbing but for unknown; unknown only leaves to nominal.
    DOUBLES_EQUAL(0.0, transitionProbability(DriveMode::kFailed, DriveMode::kNominal, model), 0.0);
    DOUBLES_EQUAL(0.0, transitionProbability(DriveMode::kFailed, DriveMode::kDegraded, model), 0.0);
    DOUBLES_EQUAL(0.0, transitionProbability(DriveMode::kUnknown, DriveMode::kFailed, model), 0.0);
    DOUBLES_EQUAL(0.0, transitionProbability(DriveMode::kUnknown, DriveMode::kDegraded, model), 0.0);

    tables::DriveHealthModelTable extreme = model;  // every leaving probability at its 0.5 maximum
    extreme.p_degrade = extreme.p_recover = extreme.p_fail_nominal = 0.5F;
    extreme.p_fail_degraded = extreme.p_unknown = extreme.p_leave_unknown = 0.5F;
    for (const tables::DriveHealthModelTable* m : {&model, &extreme}) {
        for (DriveMode from : kModes) {
            double sum = 0.0;
            for (DriveMode to : kModes) {
                const double t = transitionProbability(from, to, *m);
                CHECK(t >= 0.0 && t <= 1.0);
                sum += t;
            }
            DOUBLES_EQUAL(1.0, sum, 1e-12);
        }
    }
    // Rows beyond 1 are scaled whole: nominal leaves to three modes at 0.5 each.
    DOUBLES_EQUAL(1.0 / 3.0, transitionProbability(DriveMode::kNominal, DriveMode::kDegraded, extreme), 1e-9);
    DOUBLES_EQUAL(0.0, transitionProbability(DriveMode::kNominal, DriveMode::kNominal, extreme), 1e-12);
}

TEST(DriveModeModel, LikelihoodsComeFromTheTableAndUnknownIsUniform) {
    const DriveObservation bad = observation(TrackReading::kStall, CurrentReading::kHigh, FaultReading::kYes);
    DOUBLES_EQUAL(static_cast<double>(model.p_stall_nominal) * model.p_high_current_nominal * model.p_fault_report_nominal,
                  observationLikelihood(DriveMode::kNominal, bad, model), 1e-15);
    DOUBLES_EQUAL(static_cast<double>(model.p_stall_degraded) * model.p_high_current_degraded *
                      model.p_fault_report_degraded,
                  observationLikelihood(DriveMode::kDegraded, bad, model), 1e-15);
    DOUBLES_EQUAL(static_cast<double>(model.p_stall_failed) * estimator::kHighCurrentGivenFailed *
                      model.p_fault_report_failed,
                  observationLikelihood(DriveMode::kFailed, bad, model), 1e-12);
    DOUBLES_EQUAL(0.125, observationLikelihood(DriveMode::kUnknown, bad, model), 1e-15);

    const DriveObservation good = observation(TrackReading::kTracking, CurrentReading::kNormal, FaultReading::kNo);
    DOUBLES_EQUAL((1.0 - model.p_stall_nominal) * (1.0 - model.p_high_current_nominal) *
                      (1.0 - model.p_fault_report_nominal),
                  observationLikelihood(DriveMode::kNominal, good, model), 1e-12);
    DOUBLES_EQUAL(0.125, observationLikelihood(DriveMode::kUnknown, good, model), 1e-15);

    const DriveObservation none;  // no evidence at all
    for (DriveMode m : kModes) {
        DOUBLES_EQUAL(1.0, observationLikelihood(m, none, model), 0.0);
    }
}

TEST(DriveModeModel, StartsNominalWithPowerFactorOne) {
    DriveModeFilter f;
    CHECK(DriveMode::kNominal == f.declared());
    CHECK(p(f, DriveMode::kNominal) > 1.0 - 1e-8);
    for (DriveMode m : {DriveMode::kDegraded, DriveMode::kFailed, DriveMode::kUnknown}) {
        DOUBLES_EQUAL(estimator::kProbabilityFloor, p(f, m), 1e-15);
    }
    DOUBLES_EQUAL(1.0, f.powerFactor(), 0.0);
}

TEST(DriveModeModel, WithoutEvidenceTheBeliefMovesByTheTransitionModelOnly) {
    DriveModeFilter f;
    const DriveObservation none;
    for (int update = 0; update < 50; ++update) {
        double predicted[4] = {};
        for (DriveMode from : kModes) {
            for (DriveMode to : kModes) {
                predicted[static_cast<int>(to)] += p(f, from) * transitionProbability(from, to, model);
            }
        }
        const estimator::ModeChange change = f.update(none, model);
        CHECK_FALSE(change.changed);
        for (DriveMode m : kModes) {
            DOUBLES_EQUAL(predicted[static_cast<int>(m)], p(f, m), 1e-12);
        }
    }
    DOUBLES_EQUAL(1.0, f.powerFactor(), 0.0);  // no current reading, no power-factor update
    CHECK(p(f, DriveMode::kDegraded) > 40 * model.p_degrade);  // it did move
}

TEST(DriveModeModel, NominalEvidenceKeepsEveryModePossibleAboveTheFloor) {
    DriveModeFilter f;
    const DriveObservation good = observation(TrackReading::kTracking, CurrentReading::kNormal, FaultReading::kNo);
    for (int update = 0; update < 2000; ++update) {
        (void)f.update(good, model);
    }
    double sum = 0.0;
    for (DriveMode m : kModes) {
        CHECK(p(f, m) >= estimator::kProbabilityFloor * 0.999);
        sum += p(f, m);
    }
    DOUBLES_EQUAL(1.0, sum, 1e-12);
    CHECK(DriveMode::kNominal == f.declared());
    CHECK(p(f, DriveMode::kNominal) > 0.9999);
}

TEST(DriveModeModel, HighCurrentWhileTrackingIsDegradationAndFeedsThePowerFactor) {
    DriveModeFilter f;
    const DriveObservation high = observation(TrackReading::kTracking, CurrentReading::kHigh, FaultReading::kNo, 1.5);
    int updates = 0;
    estimator::ModeChange change;
    double expectedFactor = 1.0;
    while (!change.changed && updates < 20) {
        change = f.update(high, model);
        expectedFactor += model.power_factor_gain * (1.5 - expectedFactor);
        ++updates;
    }
    CHECK(change.changed);
    CHECK(DriveMode::kNominal == change.from);
    CHECK(DriveMode::kDegraded == change.to);
    CHECK(change.probability >= model.declare_probability);
    CHECK(updates >= 2 && updates <= 4);  // several readings, not one, but within 0.4 s
    DOUBLES_EQUAL(expectedFactor, f.powerFactor(), 1e-6);
    for (int i = 0; i < 60; ++i) {
        (void)f.update(high, model);
    }
    DOUBLES_EQUAL(1.5, f.powerFactor(), 0.01);
    CHECK(DriveMode::kDegraded == f.declared());
}

TEST(DriveModeModel, OneHighReadingIsNoAlarm) {
    DriveModeFilter f;
    const DriveObservation good = observation(TrackReading::kTracking, CurrentReading::kNormal, FaultReading::kNo);
    const DriveObservation high = observation(TrackReading::kTracking, CurrentReading::kHigh, FaultReading::kNo, 1.3);
    for (int i = 0; i < 100; ++i) {
        CHECK_FALSE(f.update(i % 10 == 0 ? high : good, model).changed);
    }
    CHECK(DriveMode::kNominal == f.declared());
}

TEST(DriveModeModel, FaultReportsAloneDeclareFailed) {
    DriveModeFilter f;
    const DriveObservation fault = observation(TrackReading::kNone, CurrentReading::kNone, FaultReading::kYes);
    int updates = 0;
    estimator::ModeChange change;
    while (!change.changed && updates < 20) {
        change = f.update(fault, model);
        ++updates;
    }
    CHECK(DriveMode::kFailed == change.to);
    CHECK(updates <= 4);
    CHECK(p(f, DriveMode::kFailed) > p(f, DriveMode::kUnknown));
}

TEST(DriveModeModel, EvidenceThatFitsNoModelledModeIsUnknown) {
    DriveModeFilter f;
    const DriveObservation odd = observation(TrackReading::kStall, CurrentReading::kHigh, FaultReading::kNo, 2.0);
    for (int i = 0; i < 30; ++i) {
        (void)f.update(odd, model);
    }
    CHECK(DriveMode::kUnknown == f.declared());
    CHECK(p(f, DriveMode::kUnknown) > 0.99);
}

TEST(DriveModeModel, DeclaredModeHoldsUntilTheThresholdIsReached) {
    tables::DriveHealthModelTable strict = model;
    strict.declare_probability = 0.9999F;
    DriveModeFilter f;
    const DriveObservation high = observation(TrackReading::kTracking, CurrentReading::kHigh, FaultReading::kNo, 1.5);
    (void)f.update(high, strict);
    (void)f.update(high, strict);
    (void)f.update(high, strict);
    CHECK(DriveMode::kDegraded == f.mostProbable());
    CHECK(p(f, DriveMode::kDegraded) < 0.9999);
    CHECK(DriveMode::kNominal == f.declared());  // most probable, not yet sure enough
    int more = 0;
    while (f.declared() != DriveMode::kDegraded && more < 10) {
        (void)f.update(high, strict);
        ++more;
    }
    CHECK(DriveMode::kDegraded == f.declared());
    CHECK(more >= 1);
}

TEST(DriveModeModel, AFailedDriveThatWorksAgainComesBackThroughUnknown) {
    DriveModeFilter f;
    const DriveObservation fault = observation(TrackReading::kNone, CurrentReading::kNone, FaultReading::kYes);
    const DriveObservation good = observation(TrackReading::kTracking, CurrentReading::kNormal, FaultReading::kNo);
    for (int i = 0; i < 10; ++i) {
        (void)f.update(fault, model);
    }
    CHECK(DriveMode::kFailed == f.declared());
    bool sawUnknown = false;
    for (int i = 0; i < 200 && f.declared() != DriveMode::kNominal; ++i) {
        (void)f.update(good, model);
        sawUnknown = sawUnknown || f.declared() == DriveMode::kUnknown;
    }
    CHECK(sawUnknown);
    CHECK(DriveMode::kNominal == f.declared());
}
