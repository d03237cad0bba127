// A leg's constraints (step 3 of the RSE policy) and the figures the habitual
// task reports about them: a path judged against what remains of the leg's
// not-to-exceed length, energy and power, the figures in force (LegReportMsg's
// predicted and allowed values), and the least violating candidate of a
// planning session (what a fail-up reports).
//
// Re-evaluated for the remaining leg:
//   allowed length = (maxPathLengthM - driven length) * (1 - distance_margin_frac)
//   allowed energy = (maxEnergyJ - driven energy) * (1 - power_margin_frac)
//   allowed power  = maxPowerW * (1 - power_margin_frac)   (0: no power bound)
// Predicted energy: the power model (fsw/rover_model/power_model.hpp) on the
// path with the power factors of the moment; power: the drives' power at the
// cruise speed, which no path changes. A violated power bound wins over the
// others (no repair mends it); else the larger relative excess names the
// violated bound. Excesses are relative to the whole leg's bounds (validated
// positive), so length and energy compare and the least violating candidate is
// well defined.
//
// No bus, no events: pure figures on the HABITUAL table (read at every call:
// the table may change between runs). No heap; loops bounded by the trajectory's
// kMaxTrajectoryPoints.
#pragma once

#include <cstddef>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

struct Evaluation {
    double lengthM;
    double energyJ;
    double allowedLengthM;
    double allowedEnergyJ;
    msg::LegConstraint violated;  // kNone when every bound holds
    double excess;                // of the violated one
    double score;                 // largest relative excess (<= 0: every bound holds)
    double powerW;                // the drives' power at the cruise speed, now
    double allowedPowerW;         // 0: the leg has no power bound
};

// What the figures depend on beside the path: how far the leg has come, and the
// drives' mean power factor now (rover_model::meanPowerFactor).
struct LegProgress {
    double drivenLengthM;
    double drivenEnergyJ;
    double powerFactor;
};

// "path length", "energy", ...: the words of the events.
const char* constraintName(msg::LegConstraint constraint);

class CandidateEvaluator {
public:
    explicit CandidateEvaluator(const tables::HabitualTable& habitual) : habitual_(habitual) {}

    // A new leg: its bounds; the figures in force are its whole allowed length,
    // energy and power with nothing predicted; no candidate.
    void beginLeg(const msg::LegCommandMsg& leg);

    // path[0..count) from the rover (count 0: only the allowed figures).
    Evaluation evaluate(const geometry::Point2* path, std::size_t count, double headingRad,
                        const LegProgress& progress) const;
    // The leg's power bound against the drives' power at the cruise speed with
    // powerFactor (no path involved): the figures in force with the power
    // figures refreshed; violated kPower when the bound no longer holds (and no
    // longer kPower when it holds again).
    Evaluation powerCheck(double powerFactor) const;
    // The figures of a session that found no path: the allowed ones, kNoPath.
    Evaluation noPath(const LegProgress& progress) const;

    // The figures in force: the leg's bounds, then the plan being driven, its
    // re-evaluation while driving, or the fail-up's.
    const Evaluation& inForce() const { return inForce_; }
    void setInForce(const Evaluation& evaluation) { inForce_ = evaluation; }

    // A planning session keeps the least violating of its failed attempts
    // (smallest score; a path longer than a trajectory is not kept).
    void clearCandidate();
    void keepCandidate(const geometry::Point2* path, std::size_t count, const Evaluation& evaluation);
    bool haveCandidate() const { return haveCandidate_; }
    const Evaluation& candidate() const { return candidate_; }
    const geometry::Point2* candidatePath() const { return candidatePath_; }
    std::size_t candidateCount() const { return candidateCount_; }

private:
    const tables::HabitualTable& habitual_;
    double maxPathLengthM_ = 0.0;
    double maxEnergyJ_ = 0.0;
    double maxPowerW_ = 0.0;
    Evaluation inForce_{};
    bool haveCandidate_ = false;
    Evaluation candidate_{};
    geometry::Point2 candidatePath_[msg::kMaxTrajectoryPoints] = {};
    std::size_t candidateCount_ = 0;
};

}  // namespace rse::habitual
