// What the habitual task says on the bus, and what it last said:
//   TrajectoryMsg   a plan, a back-out (two points), or count 0 = stop; every
//                   one with a new trajectory id (never 0), the leg's id and,
//                   but for a stop, HABITUAL.cruise_speed_m_s
//   LegReportMsg    the leg's state, the figures in force (candidate_evaluator.hpp)
//                   and, when failed up, the violated constraint and its excess;
//                   or a one-off answer about a refused leg (kIdle + kBadLeg)
//   KnownHazardsMsg the remembered seen discs (hazard_memory.hpp)
// The task decides when; this part fills and publishes the messages, keeps
// the trajectory in force (the drive supervisor follows it) and counts what
// went out. No heap; loops bounded by kMaxTrajectoryPoints.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/software_bus.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/candidate_evaluator.hpp"
#include "fsw/habitual/hazard_memory.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// The leg counters every LegReportMsg carries.
struct ReportCounts {
    std::uint32_t legsAchieved;
    std::uint32_t failUps;
    std::uint32_t replans;
    std::uint32_t minorAnomalies;
};

struct OutputCounters {
    std::uint32_t plansSent = 0;
    std::uint32_t stopsSent = 0;
    std::uint32_t hazardMapsSent = 0;
};

class HabitualOutputs {
public:
    HabitualOutputs(core::SoftwareBus& bus, const tables::HabitualTable& habitual) : bus_(bus), habitual_(habitual) {}

    // ---- TrajectoryMsg -------------------------------------------------------
    void sendStop(std::uint32_t legId, core::TimeNs now);
    // A plan: path[0..count), count 2..kMaxTrajectoryPoints.
    void sendPath(std::uint32_t legId, const geometry::Point2* path, std::size_t count, core::TimeNs now);
    // A back-out: straight from `from` to `to`. The trajectory in force is an
    // escape until the next one, or escapeEnded().
    void sendEscape(std::uint32_t legId, geometry::Point2 from, geometry::Point2 to, core::TimeNs now);
    void escapeEnded() { escaping_ = false; }
    bool escaping() const { return escaping_; }
    // The trajectory last sent (count 0 after a stop).
    const msg::TrajectoryMsg& trajectory() const { return trajectory_; }

    // ---- LegReportMsg --------------------------------------------------------
    // What a kFailedUp report says: the reason and, for a bound (length,
    // energy, power), its excess. clearFailUp: nothing violated.
    void setFailUp(msg::LegConstraint reason, double excess);
    void clearFailUp() { setFailUp(msg::LegConstraint::kNone, 0.0); }
    void publishReport(core::TimeNs now, std::uint32_t legId, msg::HabitualState state, const Evaluation& figures,
                       const ReportCounts& counts);
    // A one-off answer about a refused leg; the leg in force (if any) goes on
    // and the next periodic report is about it again.
    void publishRefusal(core::TimeNs now, std::uint32_t legId, const ReportCounts& counts);
    const msg::LegReportMsg& latestReport() const { return report_; }

    // ---- KnownHazardsMsg -----------------------------------------------------
    // The memory changed since it was last published.
    bool hazardsChanged(const HazardMemory& memory) const { return memory.revision() != hazardsRevision_; }
    void publishHazards(core::TimeNs now, const HazardMemory& memory);

    const OutputCounters& counters() const { return counters_; }

private:
    // A fresh trajectory_ for legId: a new id, the time; no points, no speed yet.
    void beginTrajectory(std::uint32_t legId, core::TimeNs now);

    core::SoftwareBus& bus_;
    const tables::HabitualTable& habitual_;
    msg::TrajectoryMsg trajectory_{};
    std::uint32_t nextTrajectoryId_ = 1;
    bool escaping_ = false;
    msg::LegReportMsg report_{};
    msg::LegConstraint reportViolated_ = msg::LegConstraint::kNone;
    double reportExcess_ = 0.0;
    std::uint32_t hazardsRevision_ = 0;  // memory revision last published in KnownHazardsMsg
    OutputCounters counters_{};
};

}  // namespace rse::habitual
