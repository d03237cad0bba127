#include "fsw/habitual/candidate_evaluator.hpp"

#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/rover_model/power_model.hpp"

namespace rse::habitual {

using geometry::Point2;
using rover_model::pathEnergyJ;
using rover_model::powerModelFrom;

const char* constraintName(msg::LegConstraint constraint) {
    switch (constraint) {
        case msg::LegConstraint::kNone:
            return "none";
        case msg::LegConstraint::kPathLength:
            return "path length";
        case msg::LegConstraint::kEnergy:
            return "energy";
        case msg::LegConstraint::kNoPath:
            return "no path";
        case msg::LegConstraint::kCannotFollow:
            return "cannot follow";
        case msg::LegConstraint::kBadLeg:
            return "bad leg";
        case msg::LegConstraint::kPower:
            return "power";
    }
    return "?";
}

void CandidateEvaluator::beginLeg(const msg::LegCommandMsg& leg) {
    maxPathLengthM_ = leg.maxPathLengthM;
    maxEnergyJ_ = leg.maxEnergyJ;
    maxPowerW_ = leg.maxPowerW;
    const tables::HabitualTable& hab = habitual_;
    const double lengthKept = 1.0 - static_cast<double>(hab.distance_margin_frac);
    const double energyKept = 1.0 - static_cast<double>(hab.power_margin_frac);
    inForce_ = Evaluation{0.0, 0.0, leg.maxPathLengthM * lengthKept, leg.maxEnergyJ * energyKept,
                          msg::LegConstraint::kNone, 0.0, 0.0, 0.0, leg.maxPowerW * energyKept};
}

Evaluation CandidateEvaluator::evaluate(const Point2* path, std::size_t count, double headingRad,
                                        const LegProgress& progress) const {
    const tables::HabitualTable& hab = habitual_;
    Evaluation e{};
    e.lengthM = pathLength(path, count);
    e.energyJ = pathEnergyJ(powerModelFrom(hab), path, count, headingRad, progress.powerFactor);
    e.allowedLengthM =
        (maxPathLengthM_ - progress.drivenLengthM) * (1.0 - static_cast<double>(hab.distance_margin_frac));
    e.allowedEnergyJ = (maxEnergyJ_ - progress.drivenEnergyJ) * (1.0 - static_cast<double>(hab.power_margin_frac));
    const double lengthExcess = e.lengthM - e.allowedLengthM;
    const double energyExcess = e.energyJ - e.allowedEnergyJ;
    // Relative to the whole leg's bounds (validated positive), so the two
    // compare and the least violating plan is well defined.
    const double relativeLength = lengthExcess / maxPathLengthM_;
    const double relativeEnergy = energyExcess / maxEnergyJ_;
    e.score = relativeLength > relativeEnergy ? relativeLength : relativeEnergy;
    const Evaluation power = powerCheck(progress.powerFactor);
    e.powerW = power.powerW;
    e.allowedPowerW = power.allowedPowerW;
    if (power.violated == msg::LegConstraint::kPower) {
        // Whatever the path: the power bound is the drives', and no repair mends it.
        e.violated = msg::LegConstraint::kPower;
        e.excess = power.excess;
        e.score = power.score > e.score ? power.score : e.score;
    } else if (lengthExcess <= 0.0 && energyExcess <= 0.0) {
        e.violated = msg::LegConstraint::kNone;
        e.excess = 0.0;
    } else if (lengthExcess > 0.0 && (energyExcess <= 0.0 || relativeLength >= relativeEnergy)) {
        e.violated = msg::LegConstraint::kPathLength;
        e.excess = lengthExcess;
    } else {
        e.violated = msg::LegConstraint::kEnergy;
        e.excess = energyExcess;
    }
    return e;
}

Evaluation CandidateEvaluator::powerCheck(double powerFactor) const {
    const tables::HabitualTable& hab = habitual_;
    Evaluation e = inForce_;
    e.powerW = rover_model::cruisePowerW(powerModelFrom(hab), static_cast<double>(hab.cruise_speed_m_s), powerFactor);
    e.allowedPowerW = maxPowerW_ * (1.0 - static_cast<double>(hab.power_margin_frac));
    const bool bounded = maxPowerW_ > 0.0;
    if (bounded && e.powerW > e.allowedPowerW) {
        e.violated = msg::LegConstraint::kPower;
        e.excess = e.powerW - e.allowedPowerW;
        e.score = e.excess / maxPowerW_;
    } else if (e.violated == msg::LegConstraint::kPower) {
        e.violated = msg::LegConstraint::kNone;
        e.excess = 0.0;
    }
    return e;
}

Evaluation CandidateEvaluator::noPath(const LegProgress& progress) const {
    Evaluation none = evaluate(nullptr, 0, 0.0, progress);
    none.violated = msg::LegConstraint::kNoPath;
    none.excess = 0.0;
    return none;
}

void CandidateEvaluator::clearCandidate() {
    haveCandidate_ = false;
    candidateCount_ = 0;
}

void CandidateEvaluator::keepCandidate(const Point2* path, std::size_t count, const Evaluation& evaluation) {
    if (count > msg::kMaxTrajectoryPoints || (haveCandidate_ && evaluation.score >= candidate_.score)) {
        return;
    }
    for (std::size_t i = 0; i < count; ++i) {
        candidatePath_[i] = path[i];
    }
    candidateCount_ = count;
    candidate_ = evaluation;
    haveCandidate_ = true;
}

}  // namespace rse::habitual
