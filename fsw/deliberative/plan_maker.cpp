#include "fsw/deliberative/plan_maker.hpp"

#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/deliberative/drive_health.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "fsw/geometry/site_bounds.hpp"
#include "fsw/msg/deliberative_msgs.hpp"

namespace rse::deliberative {

static_assert(msg::kPlanPathMeans == kMaxPlanSteps + 1, "PlanPathMsg holds mu_0 .. mu_N of the longest plan");

bool PlanMaker::start(const PlanStart& s, const char** refusal) {
    site_ = s.site;
    siteRevision_ = site_.map != nullptr ? site_.map->revision() : 0;
    PlanRequest request;
    request.startX = s.xM;
    request.startY = s.yM;
    for (std::size_t i = 0; i < 4; ++i) {
        request.startCov[i] = s.cov[i];
    }
    planFromReentry(&request);
    request.hazards = s.hazards->hazards;
    request.hazardCount = s.hazards->count;
    request.goalX = s.goalX;
    request.goalY = s.goalY;
    request.riskBound = s.riskBound;
    request.site = s.site;
    far_ = FarRockBound{};
    // The motor loss in the state estimate: a drive the mode estimator
    // declares failed (or cannot tell) is planned as failed - its power factor
    // in the legs' bounds (the task's LegParams) and, once the declaration has
    // lasted PLANNER.failed_drive_confirm_s, a rover that tracks its path worse.
    request.noiseFactor =
        s.failedDrives != 0U ? static_cast<double>(tables_.planner().failed_drive_noise_factor) : 1.0;
    MapProblemReport report;
    wideSearch_ = false;
    refusedByWholeMap_ = false;
    if (!buildProblem(s, request, &report, refusal)) {
        return false;
    }
    seedFromLastPlan();
    ++counters_.plansStarted;
    slices_ = 0;
    noteFailedDrives(s);
    events_.report(events::kPlanStarted, core::Severity::kInfo,
                   "deliberative: plan goal %u (%.2f, %.2f) from (%.2f, %.2f), risk %.3g, %u obstacles, %u seen%s",
                   static_cast<unsigned>(s.goalNumber), s.goalX, s.goalY, request.startX, request.startY,
                   request.riskBound, static_cast<unsigned>(problem_.obstacleCount),
                   static_cast<unsigned>(report.hazardsUsed), report.startInObstacle ? ", start inside one" : "");
    return true;
}

void PlanMaker::planFromReentry(PlanRequest* request) {
    // A start off the planning site (off the map, or pushed against its edge)
    // has no plan: plan from the nearest point well on it instead; the
    // habitual layer drives the rover there on the first leg.
    const double radius = rse::geometry::clearanceRadiusM(tables_.roverGeometry());
    const geometry::SiteBox planSite = siteFor(tables_.coarseMap(), site_.map, radius);
    const geometry::SiteBox reentrySite = siteFor(tables_.coarseMap(), site_.map, radius + kReentryInsetM);
    double inX = request->startX;
    double inY = request->startY;
    fromReentry_ = geometry::outsideBy(planSite, request->startX, request->startY) > 0.0 &&
                   geometry::nearestInside(reentrySite, request->startX, request->startY, &inX, &inY);
    if (fromReentry_) {
        ++counters_.reentryPlans;
        events_.report(events::kPlannedFromReentry, core::Severity::kWarning,
                       "deliberative: start (%.2f, %.2f) off the site: planned from (%.2f, %.2f) (%.2f m)",
                       request->startX, request->startY, inX, inY,
                       std::hypot(inX - request->startX, inY - request->startY));
        request->startX = inX;
        request->startY = inY;
    }
}

bool PlanMaker::buildProblem(const PlanStart& s, const PlanRequest& request, MapProblemReport* report,
                             const char** refusal) {
    const tables::PlannerTable& planner = tables_.planner();
    if (!core::isOk(buildMapProblem(tables_.coarseMap(), planner, tables_.roverGeometry(), request, &problem_,
                                    report, &obstacles_))) {
        ++counters_.problemsRefused;
        events_.report(events::kProblemRefused, core::Severity::kError,
                       "deliberative: goal %u (%.2f, %.2f) from (%.2f, %.2f): %s",
                       static_cast<unsigned>(s.goalNumber), s.goalX, s.goalY, request.startX, request.startY,
                       toString(report->error));
        *refusal = toString(report->error);
        return false;
    }
    if (report->obstaclesDropped > 0) {
        ++counters_.obstaclesDropped;
        events_.report(events::kDroppedObstacles, core::Severity::kWarning,
                       "deliberative: %u of %u coarse-map obstacles left out of the problem (farthest from the "
                       "line): the plan's risk is checked against them",
                       static_cast<unsigned>(report->obstaclesDropped), static_cast<unsigned>(report->obstaclesOnMap));
    }
    // The whole map (whole_map_check.hpp): obstacles left out keep a share
    // of the bound for their risk.
    riskBound_ = request.riskBound;
    leftOutCount_ = obstacles_.leftOut();
    leftOutRisk_ = 0.0;
    wholeMapRounds_ = 0;
    // Site mode: the rocks far from the plan always take a share.
    if (leftOutCount_ > 0 || site_.map != nullptr) {
        problem_.riskBound = riskBound_ * (1.0 - kLeftOutShare);
    }
    phase_ = Phase::kPlanning;
    if (!core::isOk(planner_.start(problem_, plannerParams()))) {
        ++counters_.problemsRefused;
        events_.report(events::kProblemRefused, core::Severity::kError,
                       "deliberative: planner refused the problem of goal %u", static_cast<unsigned>(s.goalNumber));
        *refusal = "planner refused the problem";
        return false;
    }
    return true;
}

void PlanMaker::seedFromLastPlan() {
    // The last plan found is a seed for this one when it went to the same goal
    // among the same obstacles: a replan, or the operator's bound changed
    // (issue 15 item 5: a tighter bound's search cut short by the budget gave
    // a route 1 m longer than the looser bound's). The planner re-solves its
    // faces at this problem's margins and keeps it only if it verifies.
    bool seeded = last_.valid && last_.goalX == problem_.goalX && last_.goalY == problem_.goalY &&
                  last_.obstacleCount == problem_.obstacleCount;
    for (std::size_t i = 0; i < problem_.obstacleCount && seeded; ++i) {
        seeded = problem_.obstacles[i].id == last_.obstacleIds[i];
    }
    seeded = seeded && core::isOk(planner_.setSeedHint(last_.plan));
    counters_.seededPlans += seeded ? 1U : 0U;
    seededPlan_ = seeded;
}

void PlanMaker::noteFailedDrives(const PlanStart& s) {
    if (s.failedDrives == plannedFailedMask_) {
        return;
    }
    plannedFailedMask_ = s.failedDrives;
    ++counters_.failedDriveModels;
    char names[32];
    wheelNames(s.failedDrives, names, sizeof names);
    cmdtlm::event_data::FAILED_DRIVE_MODEL data;
    data.failed_drives = s.failedDrives;
    data.power_factor = s.meanPowerFactor;
    data.noise = problem_.processSigmaM;
    events_.report(events::kFailedDriveModel, core::Severity::kWarning, data.pack(),
                   "deliberative: drive estimate: %s%s: plans at power factor %.2f, noise %.3f m/step",
                   s.failedDrives != 0U ? names : "every drive", s.failedDrives != 0U ? " failed" : " back",
                   s.meanPowerFactor, problem_.processSigmaM);
}

CcPlannerParams PlanMaker::plannerParams() const {
    const tables::PlannerTable& planner = tables_.planner();
    CcPlannerParams params;
    params.nodeBudget = planner.node_budget;
    params.workBudget = static_cast<std::uint32_t>(planner.time_budget_ms) * kWorkKUnitsPerMs;
    params.searchRiskScale = wideSearch_ ? kWideSearchScale : params.searchRiskScale;
    return params;
}

bool PlanMaker::step() {
    const std::uint64_t work0 = work();
    std::uint32_t units = 0;
    while (phase_ != Phase::kDone && units < kMaxUnitsPerRun && work() - work0 < kSliceWork) {
        stepUnit();
        ++units;
    }
    const std::uint64_t runWork = work() - work0;
    counters_.maxRunWork = runWork > counters_.maxRunWork ? runWork : counters_.maxRunWork;
    counters_.maxRunUnits = units > counters_.maxRunUnits ? units : counters_.maxRunUnits;
    ++counters_.planningRuns;
    ++slices_;
    return phase_ == Phase::kDone;
}

void PlanMaker::stepUnit() {
    // A unit is one of the planner's, one obstacle of the whole-map check or
    // the restart of the planner with obstacles forced in: each within
    // CcPlanner::kMaxUnitWork, each counted in work_.
    if (phase_ == Phase::kPlanning) {
        if (!planner_.finished()) {
            const std::uint64_t before = planner_.work();
            (void)planner_.step(1);
            work_ += planner_.work() - before;
        }
        if (planner_.finished()) {
            onPlannerFinished();
        }
    } else if (phase_ == Phase::kChecking) {
        if (check_.unit(&work_)) {
            onCheckDone();
        }
    } else if (phase_ == Phase::kReplanning) {
        replanWithForced();
    }
}

void PlanMaker::onPlannerFinished() {
    candidate_ = planner_.plan();
    const bool hasPath = candidate_.status == CcStatus::kOptimal || candidate_.status == CcStatus::kFeasible;
    if (hasPath && site_.map != nullptr && !topUpSiteRocks()) {
        return;
    }
    if (!hasPath || obstacles_.leftOut() == 0) {
        candidate_.riskUsed += far_.risk;
        leftOutRisk_ = far_.risk;
        phase_ = Phase::kDone;
        return;
    }
    ++counters_.wholeMapChecks;
    check_.start(problem_, candidate_, obstacles_);
    phase_ = Phase::kChecking;
}

void PlanMaker::onCheckDone() {
    const double allowed = kLeftOutShare * riskBound_ - far_.risk;
    if (check_.leftOutRisk() <= allowed) {
        // Certified against the whole map: the problem's obstacles within
        // (1 - kLeftOutShare) Delta, the rest (and in site mode the rocks
        // far from the plan) within the share.
        leftOutRisk_ = check_.leftOutRisk() + far_.risk;
        candidate_.riskUsed += leftOutRisk_;
        phase_ = Phase::kDone;
        return;
    }
    const double risk = check_.leftOutRisk();
    const double floor = allowed / static_cast<double>(MapObstacles::kCapacity);
    if (wholeMapRounds_ < kMaxWholeMapRounds && check_.force(&obstacles_, floor) > 0) {
        ++wholeMapRounds_;
        ++counters_.wholeMapReplans;
        events_.report(events::kWholeMapReplan, core::Severity::kWarning,
                       "deliberative: left-out obstacles near the plan (risk %.3g > %.3g): round %u with them in",
                       risk, allowed, static_cast<unsigned>(wholeMapRounds_));
        phase_ = Phase::kReplanning;
        return;
    }
    refuseCandidate(risk);
}

bool PlanMaker::topUpSiteRocks() {
    // Every rock near enough the plan to matter becomes a candidate, so the
    // check bounds it; the rest are the far rocks' bound (whole_map_check.hpp).
    const std::size_t steps = candidate_.steps <= kMaxPlanSteps ? candidate_.steps : kMaxPlanSteps;
    far_ = farRockBound(problem_, steps, rse::geometry::clearanceRadiusM(tables_.roverGeometry()),
                        kFarRockShare * kLeftOutShare * riskBound_);
    // The candidates came from the map the plan was started on: a map put in
    // force since (its rock ids mean other rocks) cannot certify it.
    const char* why = nullptr;
    if (site_.map->revision() != siteRevision_) {
        why = "the site map changed while it was planned";
    } else if (keepOutNearPath(*site_.map, candidate_.meanX, candidate_.meanY, steps + 1, far_.reachM)) {
        // The chance-constrained problem holds rocks, not keep-out zones (up
        // to 16 vertices): a plan that comes within the far reach of one is
        // not certified against it, so it is not taken (the route keeps off
        // zones with the rover's clearance; a horizon near one calls home).
        why = "a keep-out zone lies within its far reach";
    } else {
        std::size_t added = 0;
        const bool fits = addRocksNearPath(site_, tables_.roverGeometry(), problem_, candidate_.meanX,
                                           candidate_.meanY, steps + 1, far_.reachM, &obstacles_, &added);
        counters_.siteRocksAdded += static_cast<std::uint32_t>(added);
        leftOutCount_ = obstacles_.leftOut();
        if (fits) {
            return true;
        }
        why = "more site-map rocks near it than the candidates hold (64)";
    }
    ++counters_.siteCrowdedRefusals;
    ++counters_.wholeMapRefusals;
    refusedByWholeMap_ = true;
    events_.report(events::kWholeMapRefused, core::Severity::kWarning,
                   "deliberative: plan not taken: %s (far reach %.2f m): cannot certify", why, far_.reachM);
    candidate_ = CcPlan{};
    candidate_.status = CcStatus::kNoPlan;
    phase_ = Phase::kDone;
    return false;
}

void PlanMaker::refuseCandidate(double leftOutRisk) {
    ++counters_.wholeMapRefusals;
    refusedByWholeMap_ = true;
    events_.report(events::kWholeMapRefused, core::Severity::kWarning,
                   "deliberative: plan not taken: left-out obstacles carry risk %.3g > %.3g (%u rounds)",
                   leftOutRisk, kLeftOutShare * riskBound_, static_cast<unsigned>(wholeMapRounds_));
    candidate_ = CcPlan{};
    candidate_.status = CcStatus::kNoPlan;
    phase_ = Phase::kDone;
}

void PlanMaker::replanWithForced() {
    seededPlan_ = false;  // the last plan's faces belong to another set of obstacles
    MapProblemReport report;
    selectObstacles(&obstacles_, &problem_, &report);
    leftOutCount_ = obstacles_.leftOut();
    problem_.riskBound = riskBound_ * (leftOutCount_ > 0 || site_.map != nullptr ? 1.0 - kLeftOutShare : 1.0);
    if (!core::isOk(planner_.start(problem_, plannerParams()))) {
        refuseCandidate(check_.leftOutRisk());
        return;
    }
    work_ += planner_.work();  // what start did (the fixed ends' margins)
    phase_ = Phase::kPlanning;
}

bool PlanMaker::finish() {
    plan_ = candidate_;
    planGap_ = 1.0;
    const bool hasPath = plan_.status == CcStatus::kOptimal || plan_.status == CcStatus::kFeasible;
    if (hasPath) {
        last_.valid = true;
        last_.plan = plan_;
        last_.goalX = problem_.goalX;
        last_.goalY = problem_.goalY;
        last_.obstacleCount = problem_.obstacleCount;
        for (std::size_t i = 0; i < problem_.obstacleCount; ++i) {
            last_.obstacleIds[i] = problem_.obstacles[i].id;
        }
    }
    return hasPath;
}

void PlanMaker::countPlanFound(core::TimeNs now) {
    ++counters_.plansFound;
    msg::PlanPathMsg m{};
    m.timeNs = now;
    m.planNumber = counters_.plansFound;
    m.status = static_cast<std::uint8_t>(plan_.status);
    const std::size_t steps = plan_.steps <= kMaxPlanSteps ? plan_.steps : kMaxPlanSteps;
    m.steps = static_cast<std::uint8_t>(steps);
    m.riskBound = riskBound_;
    m.riskUsed = plan_.riskUsed;
    m.riskLeftOut = leftOutRisk_;
    m.obstaclesInProblem = problem_.obstacleCount;
    m.obstaclesLeftOut = static_cast<std::uint8_t>(leftOutCount_);
    m.lengthM = plan_.euclideanLengthM;
    m.processSigmaM = problem_.processSigmaM;
    for (std::size_t i = 0; i < 4; ++i) {
        m.startCov[i] = problem_.startCov[i];
    }
    m.goalX = problem_.goalX;
    m.goalY = problem_.goalY;
    for (std::size_t t = 0; t <= steps; ++t) {
        m.meanX[t] = plan_.meanX[t];
        m.meanY[t] = plan_.meanY[t];
    }
    out_.publish(m, "plan path");
}

void PlanMaker::reportPlanFound(std::size_t legCount) {
    // A budget plan is not an optimum: say how far it may be off
    // (issue 15 item 5), from the search's proven lower bound.
    const double best = planner_.evenSplitCost();
    const double gap = std::isfinite(best) && best > 0.0 ? (best - planner_.lowerBound()) / best : 1.0;
    planGap_ = gap < 0.0 ? 0.0 : (gap > 1.0 ? 1.0 : gap);
    const bool budget = plan_.status != CcStatus::kOptimal;
    counters_.budgetPlans += budget ? 1U : 0U;
    counters_.wideSearchPlans += wideSearch_ ? 1U : 0U;
    // Most important first: kEventTextSize keeps 95 characters.
    events_.report(events::kPlanFound, core::Severity::kInfo,
                   "deliberative: %s plan%s, gap %.1f%%: %.2f m, risk %.3g/%.3g, %u legs, %u nodes",
                   budget ? "BUDGET" : "optimal", seededPlan_ ? ", seeded" : "", 100.0 * planGap_,
                   plan_.euclideanLengthM, plan_.riskUsed, riskBound_, static_cast<unsigned>(legCount),
                   static_cast<unsigned>(planner_.nodes()));
}

bool PlanMaker::startWideSearch() {
    // Not after a whole-map refusal: a plan was found, its left-out obstacles
    // were the trouble, and the rounds are spent.
    if (wideSearch_ || refusedByWholeMap_ || problem_.allocation != RiskAllocation::kOptimised ||
        problem_.obstacleCount == 0) {
        return false;
    }
    // Boole's even split refused it; a plan may still certify within the
    // bound (cc_planner.hpp, "Risk allocation"): one wider search first.
    const bool proven = planner_.searchExhausted();
    wideSearch_ = true;
    if (!core::isOk(planner_.start(problem_, plannerParams()))) {
        wideSearch_ = false;
        return false;
    }
    phase_ = Phase::kPlanning;
    ++counters_.wideSearches;
    events_.report(events::kWideSearch, core::Severity::kInfo,
                   "deliberative: no plan within Boole's bound at %.3g (%s): search x%.0f, certify at %.3g",
                   riskBound_, proven ? "proven" : "budget spent", kWideSearchScale, riskBound_);
    return true;
}

void PlanMaker::reportNoPlan(std::size_t goalNumber) {
    ++counters_.noPlans;
    events_.report(events::kNoPlan, core::Severity::kWarning,
                   "deliberative: no plan for goal %u within risk %.3g (%s, %u nodes)",
                   static_cast<unsigned>(goalNumber), riskBound_,
                   planner_.searchExhausted() ? "proven" : "budget spent", static_cast<unsigned>(planner_.nodes()));
}

void PlanMaker::forgetPlan() {
    plan_ = CcPlan{};
    planGap_ = 1.0;
}

}  // namespace rse::deliberative
