#include "fsw/habitual/planning_session.hpp"

#include <cmath>

#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/habitual/escape_search.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/habitual/path_shortcut.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"

namespace rse::habitual {

using geometry::Point2;

namespace {

std::uint64_t querySeed(std::uint32_t legId, std::uint32_t query) {
    // splitmix64 finaliser: every (leg, query) pair gets an unrelated seed.
    std::uint64_t z = (static_cast<std::uint64_t>(legId) << 32U) ^ query ^ 0x9E3779B97F4A7C15ULL;
    z = (z ^ (z >> 30U)) * 0xBF58476D1CE4E5B9ULL;
    z = (z ^ (z >> 27U)) * 0x94D049BB133111EBULL;
    return z ^ (z >> 31U);
}

Point2 legEnd(const msg::LegCommandMsg& leg) { return Point2{leg.goalXM, leg.goalYM}; }

}  // namespace

const char* triggerName(PlanTrigger trigger) {
    switch (trigger) {
        case PlanTrigger::kNewLeg:
            return "new leg";
        case PlanTrigger::kPathBlocked:
            return "path blocked";
        case PlanTrigger::kEnergy:
            return "energy";
        case PlanTrigger::kCannotFollow:
            return "cannot follow";
    }
    return "?";
}

double legArrivalM(const tables::HabitualTable& habitual, const msg::LegCommandMsg& leg) {
    return msg::arrivalRadiusM(static_cast<double>(habitual.goal_tolerance_m), leg.arriveWithinM);
}

double legStopShortM(const tables::HabitualTable& habitual, const msg::LegCommandMsg& leg) {
    return legArrivalM(habitual, leg) - static_cast<double>(habitual.goal_tolerance_m);
}

void PlanningSession::begin(PlanTrigger trigger, std::uint8_t firstAttempt) {
    trigger_ = trigger;
    attempt_ = firstAttempt;
    lastAttempt_ = habitual_.repair_attempts;
    queryActive_ = false;
    bareFootprint_ = false;
    restWaitRuns_ = 0;
}

bool PlanningSession::settling(const msg::PoseEstimateMsg& pose) const {
    const bool atRest = std::fabs(pose.speedMS) < kAtRestSpeedMS && std::fabs(pose.yawRateRadS) < kAtRestYawRateRadS;
    return !atRest && restWaitRuns_ < kMaxRestWaitRuns;
}

double PlanningSession::footprintM() const { return geometry::clearanceRadiusM(geometry_); }

std::uint32_t PlanningSession::queryBudget() const {
    if (trigger_ == PlanTrigger::kNewLeg && attempt_ == 0) {
        return habitual_.rrt_iterations;
    }
    // A local replan (the rover stopped mid-leg, or a repair) is bounded in time
    // as well: the table's milliseconds as iterations at the calibrated rate.
    const std::uint32_t timed = static_cast<std::uint32_t>(habitual_.replan_budget_ms) * kRrtIterationsPerMs;
    return timed < habitual_.rrt_iterations ? timed : habitual_.rrt_iterations;
}

PlanStep PlanningSession::start(const msg::LegCommandMsg& leg, const msg::PoseEstimateMsg& pose) {
    const double footprint = footprintM();
    queryStart_ = Point2{pose.xM, pose.yM};
    queryHeading_ = pose.headingRad;
    const Point2 goal = legEnd(leg);
    lastQuery_ = PlannerQueryStats{};
    lastQuery_.attempt = attempt_;
    lastQuery_.rawCostM = INFINITY;
    if (!buildPlanMap(leg, goal, footprint)) {
        return completePlan(0, leg);
    }
    if (needsEscape(footprint)) {
        ++escapesThisLeg_;
        ++counters_.escapes;
        return PlanStep::kEscape;
    }
    if (planMap_.segmentFree(queryStart_, goal)) {
        // The shortest path there is: nothing to sample.
        rawPath_[0] = queryStart_;
        rawPath_[1] = goal;
        lastQuery_.straightLine = true;
        lastQuery_.rawCostM = distance(queryStart_, goal);
        return completePlan(2, leg);
    }
    return startRrt(leg, goal);
}

bool PlanningSession::buildPlanMap(const msg::LegCommandMsg& leg, Point2 goal, double footprint) {
    // A path planned at the bare footprint leaves pure pursuit no room, so the
    // margin is given up no further than the start and goal need: first only
    // for the seen hazards they lie in; then by halves for everything.
    bool mapOk = false;
    if (!bareFootprint_) {
        mapOk = memory_.build(&planMap_, footprint + kPlanMarginM, leg);
        if (mapOk && (!planMap_.pointFree(queryStart_) || !planMap_.pointFree(goal))) {
            const MapRelief relief{{queryStart_, goal}, 2, kPlanMarginM};
            mapOk = memory_.build(&planMap_, footprint + kPlanMarginM, leg, &relief);
            lastQuery_.marginDropped = true;
        }
    }
    const double margins[] = {0.5 * kPlanMarginM, 0.0};
    for (double margin : margins) {
        if (mapOk && !bareFootprint_ && planMap_.pointFree(queryStart_) && planMap_.pointFree(goal)) {
            break;
        }
        if (bareFootprint_ && margin > 0.0) {
            continue;
        }
        mapOk = memory_.build(&planMap_, footprint + margin, leg);
        lastQuery_.marginDropped = true;
    }
    lastQuery_.marginDropped = lastQuery_.marginDropped || bareFootprint_;
    return mapOk;
}

bool PlanningSession::needsEscape(double footprint) {
    if (planMap_.pointFree(queryStart_) || escapesThisLeg_ >= kMaxEscapesPerLeg) {
        return false;
    }
    const EscapeSearch search(planMap_, memory_.builder(), coarse_, footprint, kPlanMarginM);
    escapeOffSite_ = search.offSite(queryStart_);
    return escapeOffSite_ ? search.findReentry(queryStart_, &escapeExit_)
                          : search.findEscape(queryStart_, queryHeading_, &escapeExit_);
}

PlanStep PlanningSession::startRrt(const msg::LegCommandMsg& leg, Point2 goal) {
    // A node within the leg's arrival radius that sees the point solves the
    // query (the path still runs to the point; completePlan cuts it).
    const RrtStarParams params{static_cast<double>(habitual_.rrt_step_m), static_cast<double>(habitual_.rrt_goal_bias),
                               legArrivalM(habitual_, leg), habitual_.rrt_k_cap};
    ++queryCount_;
    const core::Status status = rrt_.start(planMap_, queryStart_, goal, params, querySeed(leg.legId, queryCount_));
    if (!core::isOk(status)) {
        ++counters_.plannerRefused;
        if (core::isReportableOccurrence(counters_.plannerRefused)) {
            events_.report(events::kPlannerRefused, core::Severity::kWarning,
                           "habitual: leg %u: RRT* refused (%s): start %s, goal %s (%u so far)",
                           static_cast<unsigned>(leg.legId), core::toString(status),
                           planMap_.pointFree(queryStart_) ? "free" : "blocked",
                           planMap_.pointFree(goal) ? "free" : "blocked",
                           static_cast<unsigned>(counters_.plannerRefused));
        }
        return completePlan(0, leg);
    }
    queryActive_ = true;
    return PlanStep::kQuerying;
}

PlanStep PlanningSession::iterate(const msg::LegCommandMsg& leg) {
    const std::uint32_t budget = queryBudget();
    const std::uint32_t done = rrt_.iterations();
    const std::uint32_t remaining = budget > done ? budget - done : 0;
    const std::uint32_t slice = remaining < kRrtIterationsPerRun ? remaining : kRrtIterationsPerRun;
    const std::uint32_t ran = rrt_.iterate(slice);
    ++lastQuery_.taskRuns;
    const double straight = distance(queryStart_, legEnd(leg));
    const bool early = rrt_.solved() && rrt_.bestCost() <= kEarlyStopCostRatio * straight;
    if (rrt_.iterations() >= budget || ran < slice || early) {
        lastQuery_.earlyStop = early;
        return finishQuery(leg);
    }
    return PlanStep::kQuerying;
}

PlanStep PlanningSession::finishQuery(const msg::LegCommandMsg& leg) {
    queryActive_ = false;
    lastQuery_.iterations = rrt_.iterations();
    lastQuery_.nodes = rrt_.nodeCount();
    lastQuery_.poolFull = rrt_.poolFull();
    lastQuery_.rawCostM = rrt_.bestCost();
    return completePlan(rrt_.bestPath(rawPath_, kMaxRawPathPoints), leg);
}

PlanStep PlanningSession::completePlan(std::size_t count, const msg::LegCommandMsg& leg) {
    ++counters_.planningRuns;
    const Point2 goal = legEnd(leg);
    if (count >= 2) {
        count = shortcutPath(planMap_, rawPath_, count);
        const Point2 last = rawPath_[count - 1];
        const bool atGoal = last.x == goal.x && last.y == goal.y;
        if (!atGoal && distance(last, goal) <= legArrivalM(habitual_, leg) && planMap_.segmentFree(last, goal) &&
            count < kMaxRawPathPoints) {
            rawPath_[count++] = goal;
        }
        // A region: the path ends where it enters it (stopShortM from the point).
        count = cutPathAtDisc(rawPath_, count, goal, legStopShortM(habitual_, leg));
        if (count > msg::kMaxTrajectoryPoints) {
            count = 0;
        }
    }
    if (count >= 2) {
        // Sightings may have come in while the query ran on its frozen map.
        memory_.refreshCheckMap(footprintM(), leg);
        for (std::size_t i = 0; i + 1 < count; ++i) {
            if (!memory_.checkMap().segmentFree(rawPath_[i], rawPath_[i + 1])) {
                count = 0;
                break;
            }
        }
    }
    lastQuery_.points = count;
    lastQuery_.lengthM = count >= 2 ? pathLength(rawPath_, count) : 0.0;
    if (count < 2) {
        ++counters_.noPathRuns;
        bareFootprint_ = true;  // perhaps a passage only the bare footprint fits through
        count = 0;
    }
    pathCount_ = count;
    return PlanStep::kFinished;
}

}  // namespace rse::habitual
