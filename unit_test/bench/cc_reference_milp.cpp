#include "unit_test/bench/cc_reference_milp.hpp"

#include <coin/Cbc_C_Interface.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <limits>
#include <string>
#include <vector>

namespace rse::test::cc {

namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kInf = std::numeric_limits<double>::infinity();
constexpr int kNoColumn = -1;

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point begin) {
    return std::chrono::duration<double>(Clock::now() - begin).count();
}

double threadCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

// What a MilpOptions time limit counts: this thread's CPU time or the wall clock.
class LimitClock {
public:
    explicit LimitClock(MilpOptions::TimeBase base)
        : cpu_(base == MilpOptions::TimeBase::kCpu), wall0_(Clock::now()), cpu0_(threadCpuSeconds()) {}
    double elapsed() const { return cpu_ ? threadCpuSeconds() - cpu0_ : secondsSince(wall0_); }

private:
    bool cpu_;
    Clock::time_point wall0_;
    double cpu0_;
};

// One constrained point of a unit: the waypoint index and its delta.
struct End {
    std::size_t w;
    double delta;
};

// The units that choose a face: segments (two ends) or waypoints (one end).
std::size_t unitCount(const CcProblem& p, ConstraintMode mode) {
    return mode == ConstraintMode::kSegment ? p.steps : p.steps + 1u;
}

std::size_t unitEnds(const CcProblem& p, const RiskSplit& split, ConstraintMode mode, std::size_t u,
                     std::size_t i, End ends[2]) {
    if (mode == ConstraintMode::kSegment) {
        ends[0] = {u, split.delta[u][i][0]};
        ends[1] = {u + 1, split.delta[u][i][1]};
        return 2;
    }
    double delta = kInf;
    if (u < p.steps) {
        delta = std::min(delta, split.delta[u][i][0]);
    }
    if (u > 0) {
        delta = std::min(delta, split.delta[u - 1][i][1]);
    }
    ends[0] = {u, delta};
    return 1;
}

class Model {
public:
    Model() : m_(Cbc_newModel()) {}
    ~Model() { Cbc_deleteModel(m_); }
    Model(const Model&) = delete;
    Model& operator=(const Model&) = delete;

    int addColumn(const std::string& name, double lb, double ub, double obj, bool integer) {
        Cbc_addCol(m_, name.c_str(), lb, ub, obj, integer ? 1 : 0, 0, nullptr, nullptr);
        return columns_++;
    }
    void addRow(const std::vector<int>& cols, const std::vector<double>& coefs, char sense, double rhs) {
        Cbc_addRow(m_, "", static_cast<int>(cols.size()), cols.data(), coefs.data(), sense, rhs);
        ++rows_;
    }
    Cbc_Model* get() { return m_; }
    int columns() const { return columns_; }
    int rows() const { return rows_; }

private:
    Cbc_Model* m_;
    int columns_ = 0;
    int rows_ = 0;
};

struct Layout {
    Layout() {
        std::fill(&x[0], &x[0] + kMaxPlanSteps + 1, kNoColumn);
        std::fill(&y[0], &y[0] + kMaxPlanSteps + 1, kNoColumn);
        std::fill(&z[0][0][0], &z[0][0][0] + (kMaxPlanSteps + 1) * kMaxPlanObstacles * kMaxObstacleFaces,
                  kNoColumn);
    }
    int x[kMaxPlanSteps + 1];
    int y[kMaxPlanSteps + 1];
    int z[kMaxPlanSteps + 1][kMaxPlanObstacles][kMaxObstacleFaces];
    int binaries = 0;
};

// Keeps the part of a convex polygon where a . q <= b.
std::vector<Point> clip(const std::vector<Point>& poly, double ax, double ay, double b) {
    std::vector<Point> out;
    const std::size_t n = poly.size();
    for (std::size_t k = 0; k < n; ++k) {
        const Point& c = poly[k];
        const Point& d = poly[(k + 1) % n];
        const double fc = ax * c.x + ay * c.y - b, fd = ax * d.x + ay * d.y - b;
        if (fc <= 0.0) {
            out.push_back(c);
        }
        if ((fc < 0.0 && fd > 0.0) || (fc > 0.0 && fd < 0.0)) {
            const double s = fc / (fc - fd);
            out.push_back({c.x + s * (d.x - c.x), c.y + s * (d.y - c.y)});
        }
    }
    return out;
}

// Where a mean can be on a path of 16-gon length <= bound: the site box cut by
// ||q - start|| + ||goal - q|| <= bound (both norms as maxima over the 16
// directions, so 16 x 16 half-planes).
std::vector<Point> reachableRegion(const CcProblem& p, double bound) {
    std::vector<Point> poly = {{p.xMin, p.yMin}, {p.xMax, p.yMin}, {p.xMax, p.yMax}, {p.xMin, p.yMax}};
    for (std::size_t k = 0; k < kPolygonNormSides && !poly.empty(); ++k) {
        const double ak = 2.0 * kPi * static_cast<double>(k) / kPolygonNormSides;
        for (std::size_t l = 0; l < kPolygonNormSides && !poly.empty(); ++l) {
            if (k == l) {
                continue;
            }
            const double al = 2.0 * kPi * static_cast<double>(l) / kPolygonNormSides;
            const double cx = std::cos(ak) - std::cos(al), cy = std::sin(ak) - std::sin(al);
            const double rhs = bound + std::cos(ak) * p.startX + std::sin(ak) * p.startY -
                               std::cos(al) * p.goalX - std::sin(al) * p.goalY;
            poly = clip(poly, cx, cy, rhs);
        }
    }
    return poly;
}

// Builds the model: MILP when fixedFaces is null, the fixed-face LP otherwise.
// A non-empty region (convex, inside the site, holding every mean of every
// path no longer than the incumbent) gives the free means its bounding box as
// bounds, and the big-M values, impossible faces and irrelevant obstacles are
// judged over it: exact for every path no longer than the incumbent, which is
// all the search under a cutoff at the incumbent can return.
// Means t >= pinnedFrom (t < N) are pinned to the goal (a restriction, for a
// quick first incumbent; pinnedFrom >= N pins nothing).
void build(const CcProblem& p, const RiskSplit& split, ConstraintMode mode,
           const std::uint8_t (*fixedFaces)[kMaxPlanObstacles], const std::vector<Point>& region,
           std::size_t pinnedFrom, Model& model, Layout& lay) {
    const std::size_t n = p.steps;
    double rxMin = p.xMin, rxMax = p.xMax, ryMin = p.yMin, ryMax = p.yMax;
    if (!region.empty()) {
        rxMin = rxMax = region[0].x;
        ryMin = ryMax = region[0].y;
        for (const Point& q : region) {
            rxMin = std::min(rxMin, q.x);
            rxMax = std::max(rxMax, q.x);
            ryMin = std::min(ryMin, q.y);
            ryMax = std::max(ryMax, q.y);
        }
        rxMin = std::max(rxMin, p.xMin);
        rxMax = std::min(rxMax, p.xMax);
        ryMin = std::max(ryMin, p.yMin);
        ryMax = std::min(ryMax, p.yMax);
    }
    const std::vector<Point> box = {{rxMin, ryMin}, {rxMax, ryMin}, {rxMax, ryMax}, {rxMin, ryMax}};
    const std::vector<Point>& hull = region.empty() ? box : region;
    auto least = [&](double ax, double ay) {
        double v = kInf;
        for (const Point& q : hull) {
            v = std::min(v, ax * q.x + ay * q.y);
        }
        return v;
    };
    auto most = [&](double ax, double ay) {
        double v = -kInf;
        for (const Point& q : hull) {
            v = std::max(v, ax * q.x + ay * q.y);
        }
        return v;
    };
    for (std::size_t t = 0; t <= n; ++t) {
        const bool start = t == 0, goal = t == n || (t > 0 && t >= pinnedFrom);
        const double x = start ? p.startX : p.goalX, y = start ? p.startY : p.goalY;
        const std::string tag = std::to_string(t);
        if (start || goal) {
            lay.x[t] = model.addColumn("x" + tag, x, x, 0.0, false);
            lay.y[t] = model.addColumn("y" + tag, y, y, 0.0, false);
        } else {
            lay.x[t] = model.addColumn("x" + tag, rxMin, rxMax, 0.0, false);
            lay.y[t] = model.addColumn("y" + tag, ryMin, ryMax, 0.0, false);
        }
    }
    // The 16-gon epigraph.
    for (std::size_t t = 0; t < n; ++t) {
        const int s = model.addColumn("s" + std::to_string(t), 0.0, kInf, 1.0, false);
        for (std::size_t k = 0; k < kPolygonNormSides; ++k) {
            const double angle = 2.0 * kPi * static_cast<double>(k) / kPolygonNormSides;
            const double c = std::cos(angle), sn = std::sin(angle);
            // s - c.(mu_{t+1} - mu_t) >= 0
            model.addRow({s, lay.x[t + 1], lay.x[t], lay.y[t + 1], lay.y[t]}, {1.0, -c, c, -sn, sn}, 'G',
                         0.0);
        }
    }
    // The obstacle disjunctions.
    const std::size_t units = unitCount(p, mode);
    for (std::size_t u = 0; u < units; ++u) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            const PlanObstacle& o = p.obstacles[i];
            End ends[2];
            const std::size_t endCount = unitEnds(p, split, mode, u, i, ends);
            for (std::size_t j = 0; j < kMaxObstacleFaces; ++j) {
                lay.z[u][i][j] = kNoColumn;
            }
            if (fixedFaces != nullptr) {
                const std::size_t j = fixedFaces[u][i];
                for (std::size_t e = 0; e < endCount; ++e) {
                    const std::size_t w = ends[e].w;
                    const double margin = faceMargin(p, w, o.normalX[j], o.normalY[j], ends[e].delta);
                    model.addRow({lay.x[w], lay.y[w]}, {o.normalX[j], o.normalY[j]}, 'G',
                                 o.offset[j] + margin);
                }
                continue;
            }
            // A face that holds over the whole region at every end makes the
            // obstacle irrelevant here: choose it, no binaries.
            if (!region.empty()) {
                std::size_t always = kMaxObstacleFaces;
                for (std::size_t j = 0; j < o.faceCount && always == kMaxObstacleFaces; ++j) {
                    bool holds = true;
                    for (std::size_t e = 0; e < endCount; ++e) {
                        const std::size_t w = ends[e].w;
                        const double need =
                            o.offset[j] + faceMargin(p, w, o.normalX[j], o.normalY[j], ends[e].delta);
                        if (least(o.normalX[j], o.normalY[j]) < need) {
                            holds = false;
                        }
                        if (w == 0 || w == p.steps) {
                            const double px = w == 0 ? p.startX : p.goalX;
                            const double py = w == 0 ? p.startY : p.goalY;
                            if (o.normalX[j] * px + o.normalY[j] * py < need) {
                                holds = false;
                            }
                        }
                    }
                    if (holds) {
                        always = j;
                    }
                }
                if (always < kMaxObstacleFaces) {
                    for (std::size_t j = 0; j < o.faceCount; ++j) {
                        const double v = j == always ? 1.0 : 0.0;
                        const int z = model.addColumn("z", v, v, 0.0, true);
                        lay.z[u][i][j] = z;
                    }
                    continue;
                }
            }
            std::vector<int> chooseCols;
            std::vector<double> ones;
            for (std::size_t j = 0; j < o.faceCount; ++j) {
                const double ax = o.normalX[j], ay = o.normalY[j];
                const int z = model.addColumn(
                    "z" + std::to_string(u) + "_" + std::to_string(i) + "_" + std::to_string(j), 0.0, 1.0,
                    0.0, true);
                lay.z[u][i][j] = z;
                ++lay.binaries;
                chooseCols.push_back(z);
                ones.push_back(1.0);
                bool possible = true;
                for (std::size_t e = 0; e < endCount; ++e) {
                    const std::size_t w = ends[e].w;
                    const double need = o.offset[j] + faceMargin(p, w, ax, ay, ends[e].delta);
                    if (w == 0 || w == p.steps) {
                        const double px = w == 0 ? p.startX : p.goalX;
                        const double py = w == 0 ? p.startY : p.goalY;
                        if (ax * px + ay * py < need) {
                            possible = false;
                        }
                        continue;
                    }
                    // Least a . mu over the region; big-M makes the row void at z = 0.
                    if (most(ax, ay) < need) {
                        possible = false;
                        continue;
                    }
                    const double bigM = need - least(ax, ay);
                    if (bigM <= 0.0) {
                        continue;  // holds everywhere in the site
                    }
                    // a . mu - M z >= need - M
                    model.addRow({lay.x[w], lay.y[w], z}, {ax, ay, -bigM}, 'G', need - bigM);
                }
                if (!possible) {
                    Cbc_setColUpper(model.get(), z, 0.0);
                }
            }
            model.addRow(chooseCols, ones, 'E', 1.0);
        }
    }
}

bool splitValid(const CcProblem& p, const RiskSplit& split) {
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            for (double d : split.delta[t][i]) {
                if (!(d > 0.0 && d <= 0.5)) {
                    return false;
                }
            }
        }
    }
    return true;
}

void fillPlan(const CcProblem& p, const RiskSplit& split, const double* sol, const Layout& lay,
              MilpResult& r) {
    CcPlan& plan = r.plan;
    plan.steps = p.steps;
    for (std::size_t t = 0; t <= p.steps; ++t) {
        plan.meanX[t] = sol[lay.x[t]];
        plan.meanY[t] = sol[lay.y[t]];
    }
    // The fixed ends exactly (the solver's copy is within its tolerance).
    plan.meanX[0] = p.startX;
    plan.meanY[0] = p.startY;
    plan.meanX[p.steps] = p.goalX;
    plan.meanY[p.steps] = p.goalY;
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            plan.delta[t][i][0] = split.delta[t][i][0];
            plan.delta[t][i][1] = split.delta[t][i][1];
        }
    }
    plan.riskUsed = split.total(p);
    plan.cost = kgonLength(plan.meanX, plan.meanY, p.steps);
    plan.euclideanLengthM = euclideanLength(plan.meanX, plan.meanY, p.steps);
    r.cost = plan.cost;
}

MilpResult badProblem() {
    MilpResult r;
    r.plan.status = deliberative::CcStatus::kBadProblem;
    r.cost = kInf;
    r.gap = kInf;
    return r;
}

// One CBC run.
struct Run {
    Layout lay;
    std::vector<double> solution;  // empty without one
    bool proven = false;
    bool infeasible = false;
    bool timeLimit = false;
    bool solutionLimit = false;
    double bound = -kInf;
    int nodes = 0;
    int binaries = 0, rows = 0, columns = 0;
    double seconds = 0.0;
};

Run runCbc(const CcProblem& p, const RiskSplit& split, const MilpOptions& opt,
           const std::uint8_t (*fixedFaces)[kMaxPlanObstacles], const std::vector<Point>& region,
           double timeLimitS, double cutoff, int maxSolutions, std::size_t pinnedFrom = kMaxPlanSteps + 1) {
    Run run;
    Model model;
    build(p, split, opt.mode, fixedFaces, region, pinnedFrom, model, run.lay);
    run.binaries = run.lay.binaries;
    run.rows = model.rows();
    run.columns = model.columns();
    Cbc_Model* m = model.get();
    Cbc_setLogLevel(m, opt.logLevel);
    Cbc_setParameter(m, "timeMode", opt.timeBase == MilpOptions::TimeBase::kCpu ? "cpu" : "elapsed");
    for (const auto& [name, value] : opt.cbcParameters) {
        Cbc_setParameter(m, name.c_str(), value.c_str());
    }
    Cbc_setMaximumSeconds(m, std::max(0.01, timeLimitS));
    Cbc_setAllowableFractionGap(m, opt.relativeGap);
    Cbc_setAllowableGap(m, opt.absoluteGap);
    if (maxSolutions > 0) {
        Cbc_setMaximumSolutions(m, maxSolutions);
    }
    if (std::isfinite(cutoff)) {
        Cbc_setCutoff(m, cutoff);
    }
    const Clock::time_point begin = Clock::now();
    Cbc_solve(m);
    run.seconds = secondsSince(begin);
    run.nodes = Cbc_getNodeCount(m);
    run.infeasible = Cbc_isProvenInfeasible(m) != 0;
    run.timeLimit = Cbc_isSecondsLimitReached(m) != 0;
    run.solutionLimit = Cbc_isSolutionLimitReached(m) != 0;
    run.proven = Cbc_isProvenOptimal(m) != 0;
    const double* best = run.binaries > 0 ? Cbc_bestSolution(m) : nullptr;
    if (best == nullptr && run.proven) {
        best = Cbc_getColSolution(m);  // an LP (no binaries): the LP solution
    }
    if (best != nullptr && !run.infeasible) {
        run.solution.assign(best, best + run.columns);
    }
    run.bound = run.binaries > 0 ? Cbc_getBestPossibleObjValue(m)
                                 : (run.proven ? Cbc_getObjValue(m) : -kInf);
    return run;
}

double solutionCost(const CcProblem& p, const Run& run) {
    double x[kMaxPlanSteps + 1], y[kMaxPlanSteps + 1];
    for (std::size_t t = 0; t <= p.steps; ++t) {
        x[t] = run.solution[static_cast<std::size_t>(run.lay.x[t])];
        y[t] = run.solution[static_cast<std::size_t>(run.lay.y[t])];
    }
    return kgonLength(x, y, p.steps);
}

// The face of obstacle i whose half-plane holds unit u's ends by the most.
std::size_t bestFace(const CcProblem& p, const RiskSplit& split, ConstraintMode mode, std::size_t u,
                     std::size_t i, const double* meanX, const double* meanY) {
    const PlanObstacle& o = p.obstacles[i];
    End ends[2];
    const std::size_t endCount = unitEnds(p, split, mode, u, i, ends);
    std::size_t arg = 0;
    double top = -kInf;
    for (std::size_t j = 0; j < o.faceCount; ++j) {
        double least = kInf;
        for (std::size_t e = 0; e < endCount; ++e) {
            const std::size_t w = ends[e].w;
            least = std::min(least, o.normalX[j] * meanX[w] + o.normalY[j] * meanY[w] - o.offset[j] -
                                        faceMargin(p, w, o.normalX[j], o.normalY[j], ends[e].delta));
        }
        if (least > top) {
            top = least;
            arg = j;
        }
    }
    return arg;
}

// A given plan is used only if it is a plan of this problem under this split.
bool startPlanValid(const CcProblem& p, const RiskSplit& split, ConstraintMode mode, const CcPlan& plan) {
    if (plan.steps != p.steps || plan.meanX[0] != p.startX || plan.meanY[0] != p.startY ||
        plan.meanX[p.steps] != p.goalX || plan.meanY[p.steps] != p.goalY) {
        return false;
    }
    for (std::size_t t = 0; t <= p.steps; ++t) {
        if (!std::isfinite(plan.meanX[t]) || !std::isfinite(plan.meanY[t])) {
            return false;
        }
    }
    const double slack = mode == ConstraintMode::kSegment
                             ? segmentConstraintSlack(p, plan.meanX, plan.meanY, split)
                             : waypointConstraintSlack(p, plan.meanX, plan.meanY, split);
    return slack >= 0.0 && siteBoundViolation(p, plan.meanX, plan.meanY) <= 0.0;
}

MilpResult solve(const CcProblem& p, const RiskSplit& split, const MilpOptions& opt,
                 const std::uint8_t (*fixedFaces)[kMaxPlanObstacles]) {
    const Clock::time_point begin = Clock::now();
    const LimitClock budget(opt.timeBase);
    if (!validateProblem(p).empty() || !splitValid(p, split)) {
        return badProblem();
    }
    if (fixedFaces != nullptr) {
        const std::size_t units = unitCount(p, opt.mode);
        for (std::size_t u = 0; u < units; ++u) {
            for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                if (fixedFaces[u][i] >= p.obstacles[i].faceCount) {
                    return badProblem();
                }
            }
        }
    }
    MilpResult r;
    const bool twoPhase = fixedFaces == nullptr && opt.regionTightening && p.obstacleCount > 0;
    const double firstPhase =
        opt.firstPhaseS >= 0.0 ? opt.firstPhaseS : std::clamp(0.2 * opt.timeLimitS, 0.5, 10.0);
    const double firstLimit = twoPhase ? std::min(firstPhase, opt.timeLimitS) : opt.timeLimitS;
    // A given cutoff: with the region search, straight to it (the region of
    // the cutoff is the first region); without, CBC's cutoff on the one run.
    const bool cutoffGiven = std::isfinite(opt.cutoff);
    bool noneBelow = false;  // proven: no plan costs less than opt.cutoff
    Run run;
    bool haveRun = false;
    if (twoPhase && opt.startPlan != nullptr && startPlanValid(p, split, opt.mode, *opt.startPlan)) {
        // A given plan (e.g. the flight planner's) as the first incumbent:
        // laid out as a solution of the model, each pair on its best face.
        Model dummy;
        build(p, split, opt.mode, nullptr, {}, kMaxPlanSteps + 1, dummy, run.lay);
        run.columns = dummy.columns();
        run.rows = dummy.rows();
        run.binaries = run.lay.binaries;
        run.solution.assign(static_cast<std::size_t>(run.columns), 0.0);
        const CcPlan& plan = *opt.startPlan;
        for (std::size_t t = 0; t <= p.steps; ++t) {
            run.solution[static_cast<std::size_t>(run.lay.x[t])] = plan.meanX[t];
            run.solution[static_cast<std::size_t>(run.lay.y[t])] = plan.meanY[t];
        }
        const std::size_t units = unitCount(p, opt.mode);
        for (std::size_t u = 0; u < units; ++u) {
            for (std::size_t i = 0; i < p.obstacleCount; ++i) {
                const std::size_t j = bestFace(p, split, opt.mode, u, i, plan.meanX, plan.meanY);
                run.solution[static_cast<std::size_t>(run.lay.z[u][i][j])] = 1.0;
            }
        }
        run.bound = -kInf;
        haveRun = true;
        r.startPlanUsed = true;
    }
    if (!haveRun && twoPhase && p.steps >= 4 && !cutoffGiven) {
        // A quick incumbent: the second half of the means pinned to the goal
        // (fewer free segments, so CBC finds good paths sooner). Its solution
        // is a plan of the full problem; its bound is not a bound of it.
        Run pinned = runCbc(p, split, opt, nullptr, {}, firstLimit, kInf, 0, (p.steps + 1u) / 2u);
        r.cbcSeconds += pinned.seconds;
        r.nodes += pinned.nodes;
        if (!pinned.solution.empty()) {
            run = pinned;
            run.proven = false;
            run.infeasible = false;
            run.bound = -kInf;
            haveRun = true;
        }
    }
    if (!haveRun && !(twoPhase && cutoffGiven)) {
        const double limit = fixedFaces == nullptr && twoPhase
                                 ? std::min(firstLimit, opt.timeLimitS - budget.elapsed())
                                 : opt.timeLimitS;
        run = runCbc(p, split, opt, fixedFaces, {}, limit, opt.cutoff, 0);
        r.cbcSeconds += run.seconds;
        r.nodes += run.nodes;
    }
    r.binaries = run.binaries;
    r.rows = run.rows;
    r.columns = run.columns;
    if (twoPhase && !cutoffGiven && !run.proven && !run.infeasible && run.solution.empty() &&
        budget.elapsed() < opt.timeLimitS) {
        // No incumbent yet: on without the region until the first one.
        const double left = opt.timeLimitS - budget.elapsed();
        run = runCbc(p, split, opt, nullptr, {}, left, kInf, 1);
        r.cbcSeconds += run.seconds;
        r.nodes += run.nodes;
    }
    if (twoPhase && !run.proven && !run.infeasible && (!run.solution.empty() || cutoffGiven)) {
        // Every mean of a path no longer than the incumbent (or shorter than
        // the given cutoff) lies in the reachable region: confine the means
        // to it and search under the incumbent (or the cutoff) as cutoff.
        // Each better solution ends the run (solution limit 1) and the next
        // one starts from the smaller region.
        double bestBound = run.bound;
        bool allowRestart = true;
        for (int round = 0; round < 40; ++round) {
            const bool have = !run.solution.empty();
            const double incumbent = have ? solutionCost(p, run) : kInf;
            // Every plan better than what we have (or than the cutoff) costs less than this.
            const double ceiling = std::min(incumbent, opt.cutoff);
            // The incumbent enters as a cutoff, not as a MIP start: CBC 2.10.8
            // crashed in CglPreProcess::postProcess after MIP starts here.
            const double cutoff = std::min(
                opt.cutoff, have ? incumbent + std::max(opt.absoluteGap, opt.relativeGap * std::fabs(incumbent)) : kInf);
            const std::vector<Point> region = reachableRegion(p, ceiling * (1.0 + 1e-9) + 1e-9);
            if (region.empty()) {
                // Not even the straight line is that short: nothing below the ceiling.
                bestBound = std::max(bestBound, ceiling);
                run.proven = have && ceiling >= incumbent;
                noneBelow = cutoffGiven && ceiling < incumbent;
                run.bound = bestBound;
                break;
            }
            const double left = opt.timeLimitS - budget.elapsed();
            // Under a given cutoff and no incumbent yet, the run is not stopped at
            // its first solution: every solution is below the cutoff, and a
            // cutoff near the optimum (a plan's cost) gains nothing from a
            // restart in a barely smaller region.
            const bool restart = allowRestart && round < 39 && have;
            Run next = runCbc(p, split, opt, nullptr, region, left, cutoff, restart ? 1 : 0);
            r.cbcSeconds += next.seconds;
            r.nodes += next.nodes;
            r.rows = next.rows;
            if (r.binaries == 0) {
                r.binaries = next.binaries;
                r.columns = next.columns;
            }
            // The optimum is at least the ceiling or inside the region.
            bestBound = std::max(bestBound, next.infeasible ? ceiling : std::min(ceiling, next.bound));
            const double nextCost = next.solution.empty() ? kInf : solutionCost(p, next);
            const bool better = nextCost < incumbent - 1e-9 * (1.0 + incumbent);
            if (!next.solution.empty() && (!have || nextCost <= incumbent + 1e-9 * (1.0 + incumbent))) {
                run = next;
            } else {
                // Nothing as good found: the incumbent (if any) stands; an
                // exhausted search proves it, or, under a cutoff below it,
                // proves that nothing costs less than the cutoff.
                const bool exhausted = next.proven || next.infeasible;
                run.proven = exhausted && have && ceiling >= incumbent;
                noneBelow = exhausted && cutoffGiven && ceiling < incumbent;
                run.timeLimit = next.timeLimit;
                run.solutionLimit = next.solutionLimit;
            }
            run.infeasible = false;
            run.bound = bestBound;
            if (run.proven || noneBelow || budget.elapsed() >= opt.timeLimitS) {
                break;
            }
            if (!better) {
                if (!next.solutionLimit) {
                    break;
                }
                allowRestart = false;  // stopped on a solution no better: finish without restarts
            }
        }
    }
    if (cutoffGiven && run.infeasible) {
        noneBelow = true;  // one run under the cutoff (no region search) found it empty
    }
    r.provenInfeasible = run.infeasible && !cutoffGiven;
    r.noneBelowCutoff = noneBelow;
    r.timeLimitReached = run.timeLimit;
    r.bestBound = noneBelow ? std::max(run.bound, opt.cutoff) : run.bound;
    if (cutoffGiven && run.solution.empty()) {
        r.bestBound = noneBelow ? opt.cutoff : std::min(opt.cutoff, run.bound);
    }
    if (run.solution.empty() || run.infeasible) {
        r.plan.status = deliberative::CcStatus::kNoPlan;
        r.cost = kInf;
        r.gap = kInf;
        r.seconds = secondsSince(begin);
        return r;
    }
    const Layout& lay = run.lay;
    const double* best = run.solution.data();
    fillPlan(p, split, best, lay, r);
    r.plan.status = run.proven ? deliberative::CcStatus::kOptimal : deliberative::CcStatus::kFeasible;

    // The faces the solution uses.
    std::uint8_t faces[kMaxPlanSteps + 1][kMaxPlanObstacles] = {};
    const std::size_t units = unitCount(p, opt.mode);
    for (std::size_t u = 0; u < units; ++u) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            if (fixedFaces != nullptr) {
                faces[u][i] = fixedFaces[u][i];
                continue;
            }
            std::size_t arg = 0;
            double top = -kInf;
            for (std::size_t j = 0; j < p.obstacles[i].faceCount; ++j) {
                if (best[lay.z[u][i][j]] > top) {
                    top = best[lay.z[u][i][j]];
                    arg = j;
                }
            }
            faces[u][i] = static_cast<std::uint8_t>(arg);
        }
    }
    for (std::size_t t = 0; t < p.steps; ++t) {
        for (std::size_t i = 0; i < p.obstacleCount; ++i) {
            r.plan.face[t][i] = faces[t][i];
        }
    }

    if (fixedFaces == nullptr && opt.polish && p.obstacleCount > 0) {
        MilpOptions lpOpt = opt;
        lpOpt.polish = false;
        lpOpt.regionTightening = false;
        lpOpt.cutoff = kInf;
        lpOpt.timeLimitS = std::max(1.0, opt.timeLimitS);
        const MilpResult lp = solve(p, split, lpOpt, faces);
        if (lp.plan.status == deliberative::CcStatus::kOptimal && lp.cost <= r.cost + 1e-6 * (1.0 + r.cost)) {
            const deliberative::CcStatus status = r.plan.status;
            for (std::size_t t = 0; t <= p.steps; ++t) {
                r.plan.meanX[t] = lp.plan.meanX[t];
                r.plan.meanY[t] = lp.plan.meanY[t];
            }
            r.plan.cost = lp.plan.cost;
            r.plan.euclideanLengthM = lp.plan.euclideanLengthM;
            r.plan.status = status;
            r.cost = lp.cost;
        }
    }
    r.gap = std::max(0.0, (r.cost - r.bestBound) / std::max(std::fabs(r.cost), 1e-12));
    r.constraintSlack = opt.mode == ConstraintMode::kSegment
                            ? segmentConstraintSlack(p, r.plan.meanX, r.plan.meanY, split)
                            : waypointConstraintSlack(p, r.plan.meanX, r.plan.meanY, split);
    r.seconds = secondsSince(begin);
    return r;
}

}  // namespace

MilpResult solveReferenceMilp(const CcProblem& problem, const RiskSplit& split, const MilpOptions& options) {
    return solve(problem, split, options, nullptr);
}

MilpResult solveReferenceMilp(const CcProblem& problem, const MilpOptions& options) {
    return solve(problem, evenSplit(problem), options, nullptr);
}

MilpResult solveFixedFaceLp(const CcProblem& problem, const RiskSplit& split,
                            const std::uint8_t face[kMaxPlanSteps + 1][kMaxPlanObstacles],
                            ConstraintMode mode) {
    MilpOptions options;
    options.mode = mode;
    options.polish = false;
    return solve(problem, split, options, face);
}

}  // namespace rse::test::cc
