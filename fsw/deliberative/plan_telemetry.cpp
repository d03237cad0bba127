#include "fsw/deliberative/plan_telemetry.hpp"

namespace rse::deliberative {

core::Status PlanTelemetry::routeInputs(core::InputPipe& pipe) {
    core::Status status = pipe.route<&PlanTelemetry::takeGoals>(this);
    if (core::isOk(status)) {
        status = pipe.route<&PlanTelemetry::takePlanStatus>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&PlanTelemetry::takePlanPath>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&PlanTelemetry::takeRouteChunk>(this);
    }
    return status;
}

void PlanTelemetry::takeGoals(const msg::GoalListMsg& goals) {
    goals_ = goals;
    changed_ = true;
}

void PlanTelemetry::takePlanStatus(const msg::PlanStatusMsg& status) {
    // Published at 1 Hz and on change; PLAN goes out when what it shows changes.
    const msg::PlanStatusMsg& before = planStatus_;
    changed_ = changed_ || status.state != before.state || status.legIndex != before.legIndex ||
               status.plansMade != before.plansMade || status.callHomes != before.callHomes ||
               status.currentLegId != before.currentLegId || status.riskInForce != before.riskInForce ||
               status.horizonsReached != before.horizonsReached || status.routesFound != before.routesFound ||
               status.routesFailed != before.routesFailed;
    planStatus_ = status;
}

core::Status PlanTelemetry::takePlanPath(const msg::PlanPathMsg& m) {
    if (m.steps >= msg::kPlanPathMeans) {
        return core::Status::kInvalidArgument;  // more means than the message holds
    }
    // News every time: one PLAN_PATH per plan made, sent at once.
    planPath_ = cmdtlm::PLAN_PATH_Tlm{};
    cmdtlm::PLAN_PATH_Tlm& t = planPath_;
    t.plan_number = m.planNumber;
    t.plan_time = static_cast<double>(m.timeNs) / static_cast<double>(core::kNsPerSec);
    t.status = m.status;
    static_assert(sizeof t.mean_x / sizeof t.mean_x[0] == msg::kPlanPathMeans, "PLAN_PATH holds every mean");
    const std::size_t steps = m.steps;
    t.steps = static_cast<std::uint8_t>(steps);
    t.risk_bound = m.riskBound;
    t.risk_used = m.riskUsed;
    t.risk_left_out = m.riskLeftOut;
    t.obstacles_in_problem = m.obstaclesInProblem;
    t.obstacles_left_out = m.obstaclesLeftOut;
    t.length = static_cast<float>(m.lengthM);
    t.process_sigma = static_cast<float>(m.processSigmaM);
    for (std::size_t i = 0; i < 4; ++i) {
        t.start_cov[i] = static_cast<float>(m.startCov[i]);
    }
    t.goal_x = static_cast<float>(m.goalX);
    t.goal_y = static_cast<float>(m.goalY);
    for (std::size_t i = 0; i <= steps; ++i) {
        t.mean_x[i] = static_cast<float>(m.meanX[i]);
        t.mean_y[i] = static_cast<float>(m.meanY[i]);
    }
    sink_.send(t);
    ++planPathsSent_;
    return core::Status::kOk;
}

core::Status PlanTelemetry::takeRouteChunk(const msg::RouteChunkMsg& m) {
    if (m.count == 0 || m.count > msg::kRouteChunkPoints || m.chunkIndex >= m.chunkCount) {
        return core::Status::kInvalidArgument;
    }
    route_ = cmdtlm::ROUTE_Tlm{};
    cmdtlm::ROUTE_Tlm& t = route_;
    static_assert(sizeof t.x / sizeof t.x[0] == msg::kRouteChunkPoints, "ROUTE holds a chunk");
    t.route_number = m.routeNumber;
    t.route_time = static_cast<double>(m.timeNs) / static_cast<double>(core::kNsPerSec);
    t.point_count = m.pointCount;
    t.chunk_index = m.chunkIndex;
    t.chunk_count = m.chunkCount;
    t.goal_index = m.goalIndex;
    t.count = m.count;
    t.length = static_cast<float>(m.lengthM);
    t.goal_x = static_cast<float>(m.goalX);
    t.goal_y = static_cast<float>(m.goalY);
    for (std::size_t i = 0; i < m.count; ++i) {
        t.x[i] = m.x[i];
        t.y[i] = m.y[i];
    }
    sink_.send(t);
    ++routeChunksSent_;
    return core::Status::kOk;
}

void PlanTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (changed_ || frame.frame % kPlanPeriodFrames == 0) {
        changed_ = false;
        sendPlan(sink);
    }
}

void PlanTelemetry::sendPlan(cmdtlm::TelemetrySink& sink) {
    plan_ = cmdtlm::PLAN_Tlm{};
    const msg::PlanStatusMsg& p = planStatus_;
    plan_.status = static_cast<std::uint8_t>(p.state);
    plan_.plan_status = p.planStatus;
    plan_.call_home = static_cast<std::uint8_t>(p.callHome);
    plan_.goal_count = goals_.count;
    plan_.goal_index = p.goalIndex;
    plan_.leg_count = p.legCount;
    plan_.leg_index = p.legIndex;
    plan_.waypoint_count = p.shownLegs;
    plan_.risk_bound = goals_.riskBound;
    plan_.risk_in_force = p.riskInForce;
    plan_.risk_used = p.riskUsed;
    plan_.plan_length = static_cast<float>(p.planLengthM);
    plan_.plan_gap = static_cast<float>(p.planGap);
    plan_.current_leg_id = p.currentLegId;
    plan_.replans = p.replans;
    plan_.risk_relaxations = p.riskRelaxations;
    plan_.bound_relaxations = p.boundRelaxations;
    plan_.call_homes = p.callHomes;
    plan_.site_mode = p.siteMode;
    plan_.routes_found = p.routesFound;
    plan_.routes_failed = p.routesFailed;
    plan_.horizons_reached = p.horizonsReached;
    plan_.horizons_driven_through = p.horizonsDrivenThrough;
    plan_.horizon_stops = p.horizonStops;
    plan_.look_aheads_started = p.lookAheadsStarted;
    plan_.look_aheads_dropped = p.lookAheadsDropped;
    for (std::size_t i = 0; i < goals_.count && i < msg::kMaxGoals; ++i) {
        plan_.goal_x[i] = static_cast<float>(goals_.goals[i].xM);
        plan_.goal_y[i] = static_cast<float>(goals_.goals[i].yM);
        plan_.priority[i] = goals_.goals[i].priority;
    }
    for (std::size_t i = 0; i < p.shownLegs && i < msg::kPlanStatusLegs; ++i) {
        plan_.waypoint_x[i] = static_cast<float>(p.legs[i].xM);
        plan_.waypoint_y[i] = static_cast<float>(p.legs[i].yM);
        plan_.leg_risk[i] = static_cast<float>(p.legs[i].risk);
        plan_.leg_length_bound[i] = static_cast<float>(p.legs[i].lengthM);
        plan_.leg_energy_bound[i] = static_cast<float>(p.legs[i].energyJ / 3600.0);
    }
    sink.send(plan_);
}

}  // namespace rse::deliberative
