#include "fsw/habitual/habitual_outputs.hpp"

namespace rse::habitual {

using geometry::Point2;

void HabitualOutputs::beginTrajectory(std::uint32_t legId, core::TimeNs now) {
    trajectory_ = msg::TrajectoryMsg{};
    trajectory_.timeNs = now;
    trajectory_.trajectoryId = nextTrajectoryId_++;
    if (nextTrajectoryId_ == 0) {
        nextTrajectoryId_ = 1;
    }
    trajectory_.legId = legId;
}

void HabitualOutputs::sendStop(std::uint32_t legId, core::TimeNs now) {
    escaping_ = false;
    beginTrajectory(legId, now);
    trajectory_.count = 0;
    (void)bus_.publish(trajectory_);
    ++counters_.stopsSent;
}

void HabitualOutputs::sendPath(std::uint32_t legId, const Point2* path, std::size_t count, core::TimeNs now) {
    beginTrajectory(legId, now);
    trajectory_.speedMS = static_cast<double>(habitual_.cruise_speed_m_s);
    const std::size_t n = count < msg::kMaxTrajectoryPoints ? count : msg::kMaxTrajectoryPoints;
    trajectory_.count = static_cast<std::uint8_t>(n);
    for (std::size_t i = 0; i < n; ++i) {
        trajectory_.points[i] = msg::TrajectoryPoint{path[i].x, path[i].y};
    }
    (void)bus_.publish(trajectory_);
    escaping_ = false;
    ++counters_.plansSent;
}

void HabitualOutputs::sendEscape(std::uint32_t legId, Point2 from, Point2 to, core::TimeNs now) {
    beginTrajectory(legId, now);
    trajectory_.speedMS = static_cast<double>(habitual_.cruise_speed_m_s);
    trajectory_.count = 2;
    trajectory_.points[0] = msg::TrajectoryPoint{from.x, from.y};
    trajectory_.points[1] = msg::TrajectoryPoint{to.x, to.y};
    (void)bus_.publish(trajectory_);
    escaping_ = true;
}

void HabitualOutputs::setFailUp(msg::LegConstraint reason, double excess) {
    reportViolated_ = reason;
    reportExcess_ = excess;
}

void HabitualOutputs::publishReport(core::TimeNs now, std::uint32_t legId, msg::HabitualState state,
                                    const Evaluation& figures, const ReportCounts& counts) {
    msg::LegReportMsg r{};
    r.timeNs = now;
    r.legId = legId;
    r.state = state;
    const bool failed = state == msg::HabitualState::kFailedUp;
    r.violated = failed ? reportViolated_ : msg::LegConstraint::kNone;
    r.predictedLengthM = figures.lengthM;
    r.allowedLengthM = figures.allowedLengthM;
    r.predictedEnergyJ = figures.energyJ;
    r.allowedEnergyJ = figures.allowedEnergyJ;
    r.predictedPowerW = figures.powerW;
    r.allowedPowerW = figures.allowedPowerW;
    r.excess = failed ? reportExcess_ : 0.0;
    r.legsAchieved = counts.legsAchieved;
    r.failUps = counts.failUps;
    r.replans = counts.replans;
    r.minorAnomalies = counts.minorAnomalies;
    (void)bus_.publish(r);
    report_ = r;
}

void HabitualOutputs::publishRefusal(core::TimeNs now, std::uint32_t legId, const ReportCounts& counts) {
    msg::LegReportMsg r{};
    r.timeNs = now;
    r.legId = legId;
    r.state = msg::HabitualState::kIdle;
    r.violated = msg::LegConstraint::kBadLeg;
    r.legsAchieved = counts.legsAchieved;
    r.failUps = counts.failUps;
    r.replans = counts.replans;
    r.minorAnomalies = counts.minorAnomalies;
    (void)bus_.publish(r);
    report_ = r;
}

void HabitualOutputs::publishHazards(core::TimeNs now, const HazardMemory& memory) {
    msg::KnownHazardsMsg m{};
    memory.fillKnownHazards(now, &m);
    (void)bus_.publish(m);
    ++counters_.hazardMapsSent;
    hazardsRevision_ = m.revision;
}

}  // namespace rse::habitual
