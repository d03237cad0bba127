#include "sim_stub/montecarlo/campaign.hpp"

#include <time.h>

#include <algorithm>
#include <chrono>
#include <cctype>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>

#include "fsw/deliberative/deliberative_events.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/montecarlo/results.hpp"
#include "sim_stub/scenario/field_rocks.hpp"

namespace rse::sim::mc {

namespace {

// One stream per purpose, so adding a draw to one leaves the others alone.
constexpr std::uint64_t kRockStream = 0x726f636b;   // "rock"
constexpr std::uint64_t kFaultStream = 0x66617574;  // "faut"
constexpr std::uint64_t kFieldStream = 0x6669656c;  // "fiel"

std::string hex64(std::uint64_t v) {
    char buf[20];
    std::snprintf(buf, sizeof buf, "%016llx", static_cast<unsigned long long>(v));
    return buf;
}

std::string num(double v) {
    char buf[40];
    std::snprintf(buf, sizeof buf, "%.6g", v);
    return buf;
}

double roundTo(double v, double step) { return std::round(v / step) * step; }

double processCpuSeconds() {
    timespec ts{};
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) + 1e-9 * static_cast<double>(ts.tv_nsec);
}

const char* reasonName(msg::CallHomeReason r) {
    switch (r) {
        case msg::CallHomeReason::kNone: return "none";
        case msg::CallHomeReason::kNoPlanWithinRisk: return "no_plan_within_risk";
        case msg::CallHomeReason::kGoalUnreachable: return "goal_unreachable";
        case msg::CallHomeReason::kReplansExhausted: return "replans_exhausted";
        case msg::CallHomeReason::kInsufficientPower: return "insufficient_power";
        case msg::CallHomeReason::kMobilityLost: return "mobility_lost";
        case msg::CallHomeReason::kFaultUnrecovered: return "fault_unrecovered";
        case msg::CallHomeReason::kPlanNoMethod: return "plan_no_method";
    }
    return nullptr;
}

std::string outcomeName(MissionOutcome o) {
    switch (o) {
        case MissionOutcome::kSetupFailed: return "setup_failed";
        case MissionOutcome::kGoalReached: return "goal_reached";
        case MissionOutcome::kCalledHome: return "called_home";
        case MissionOutcome::kTimedOut: return "timed_out";
        case MissionOutcome::kPlanComplete: return "plan_complete";
    }
    return "outcome_" + std::to_string(static_cast<unsigned>(o));
}

// The deliberative layer's plans, read after every frame from its events (a
// cursor of our own on the event log), its counters and the executive's task
// statistics; nothing is changed. A plan starts with event 901 and ends with
// 902 (found), 903 (no plan within the risk in force), a call home (912), the
// mode left (915) or the next 901. The deliberative task runs at most once a
// frame and steps the planner at most once a run: that run's slice belongs to
// the plan the frame ended, if it ended one, else to the plan still open.
class PlanWatch {
public:
    void onFrame(LockstepRig& rig) {
        app::FswApp& fsw = rig.fsw();
        if (row_ == kNoRow) {
            for (std::size_t i = 0; i < fsw.executive().taskCount(); ++i) {
                const core::RateGroupEntry* e = fsw.executive().entry(i);
                if (e != nullptr && std::string(e->name) == "deliberative") {
                    row_ = i;
                }
            }
        }
        const std::uint32_t runs = fsw.deliberative().counters().planningRuns;
        const core::TaskStats* stats = row_ == kNoRow ? nullptr : fsw.executive().taskStats(row_);
        const core::TimeNs host = stats == nullptr ? 0 : stats->hostTotal;
        std::uint32_t slices = runs - lastRuns_;
        double hostMs = slices > 0 ? 1e-6 * static_cast<double>(host - lastHost_) : 0.0;
        lastRuns_ = runs;
        lastHost_ = host;

        namespace ev = deliberative::events;
        core::Event e;
        while (core::isOk(fsw.events().read(&cursor_, &e))) {
            const bool start = e.id == ev::kPlanStarted;
            const bool end = e.id == ev::kPlanFound || e.id == ev::kNoPlan || e.id == ev::kCallHome ||
                             e.id == ev::kLeftAutonomous;
            if ((start || end) && open_) {
                current_.latencyS = 1e-9 * static_cast<double>(e.time - startNs_);
                current_.found = e.id == ev::kPlanFound;
                current_.slices += slices;
                current_.hostMs += hostMs;
                slices = 0;
                hostMs = 0.0;
                plans_.push_back(current_);
                open_ = false;
            }
            if (start) {
                open_ = true;
                startNs_ = e.time;
                current_ = PlanRecord{};
                // The plan maker plans the next horizon (a look-ahead) or the
                // one the rover waits for; a look-ahead stays in hand until
                // its handover or its drop, so it is still the task's when its
                // 901 is read after the frame.
                current_.lookAhead = fsw.deliberative().lookAhead().active();
            }
        }
        if (open_) {
            current_.slices += slices;
            current_.hostMs += hostMs;
        }
        nowNs_ = rig.clock().now();
    }
    // The plans, one still open at the end included (not found).
    std::vector<PlanRecord> plans() const {
        std::vector<PlanRecord> all = plans_;
        if (open_) {
            PlanRecord last = current_;
            last.latencyS = 1e-9 * static_cast<double>(nowNs_ - startNs_);
            all.push_back(last);
        }
        return all;
    }

private:
    static constexpr std::size_t kNoRow = static_cast<std::size_t>(-1);
    core::EventLog::Cursor cursor_{};
    std::size_t row_ = kNoRow;
    std::uint32_t lastRuns_ = 0;
    core::TimeNs lastHost_ = 0;
    bool open_ = false;
    core::TimeNs startNs_ = 0;
    core::TimeNs nowNs_ = 0;
    PlanRecord current_;
    std::vector<PlanRecord> plans_;
};

}  // namespace

bool prepareCampaign(const std::vector<std::string>& missionArgs, CampaignSpec* spec, std::string* error) {
    std::vector<const char*> argv{"rse-montecarlo"};
    for (const std::string& a : missionArgs) {
        if (a == "--quiet" || a == "--help" || a == "-h") {
            *error = "'" + a + "' is not a mission option here";
            return false;
        }
        argv.push_back(a.c_str());
    }
    MissionOptions o;
    if (parseMissionArgs(static_cast<int>(argv.size()), argv.data(), &o, error) != ParseOutcome::kRun) {
        return false;
    }
    o.quiet = true;
    if (o.scenarioPath.empty() || o.scenarioPath.find_first_of(" \t\n=") != std::string::npos) {
        *error = "scenario path '" + o.scenarioPath + "': no spaces or '=' (result files are key=value lines)";
        return false;
    }
    std::ifstream in(o.scenarioPath, std::ios::binary);
    if (!in) {
        *error = o.scenarioPath + ": cannot be read";
        return false;
    }
    std::ostringstream bytes;
    bytes << in.rdbuf();
    // The scenario's own goal and duration where the arguments give none, so
    // the campaign line says what every seed flies. Seeds vary the hidden
    // rocks along the way to one goal: a plan mission is not a campaign.
    Scenario scenario;
    if (!tryParseScenario(bytes.str(), o.scenarioPath, &scenario, error) ||
        !applyScenarioMission(scenario, &o, error)) {
        return false;
    }
    if (!o.planText.empty()) {
        *error = o.scenarioPath + ": its mission is a plan; give a goal (--goto X,Y[,RISK])";
        return false;
    }
    std::uint64_t h = 0xcbf29ce484222325ULL;  // FNV-1a 64
    for (char c : bytes.str()) {
        h = (h ^ static_cast<unsigned char>(c)) * 0x100000001b3ULL;
    }
    spec->mission = o;
    spec->missionArgs = missionArgs;
    spec->scenarioHash = hex64(h);
    return true;
}

std::string campaignLine(const CampaignSpec& s) {
    const MissionOptions& o = s.mission;
    return "C format=" + std::to_string(kFormatVersion) + " variation=" + std::to_string(kVariationVersion) +
           " scenario=" + o.scenarioPath + " scenario_fnv=" + s.scenarioHash + " goal=" + num(o.goalX) + "," +
           num(o.goalY) + " risk=" + num(o.risk) + " duration=" + num(o.durationS) +
           " faults=" + (o.clearFaults ? "off" : "on") + " first=" + std::to_string(s.firstSeed) +
           " count=" + std::to_string(s.seedCount);
}

SeedStream::SeedStream(std::uint64_t seed, std::uint64_t purpose)
    : state_(seed * 0x9e3779b97f4a7c15ULL ^ (purpose << 1 | 1ULL)) {}

std::uint64_t SeedStream::next() {
    std::uint64_t z = (state_ += 0x9e3779b97f4a7c15ULL);
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ULL;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebULL;
    return z ^ (z >> 31);
}

double SeedStream::uniform(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(next() >> 11) * 0x1.0p-53;
}

Variation varyScenario(Scenario* s, std::uint64_t seed, double goalX, double goalY) {
    Variation v;
    s->seed = seed;
    v.noiseSeed = seed;

    if (s->field.present) {
        // A field per seed: the field's rocks drawn again, cleared round the
        // start and the goal flown (the campaign's, which --goto may move).
        s->obstacles.erase(std::remove_if(s->obstacles.begin(), s->obstacles.end(),
                                          [](const Obstacle& ob) { return ob.id >= kFirstFieldRockId; }),
                           s->obstacles.end());
        SeedStream field(seed, kFieldStream);
        s->field.rocks.seed = field.next() & 0xFFFFFFFFULL;   // a readable seed, one the field file format takes
        const MissionSpec mission = s->mission;
        s->mission.present = true;
        s->mission.hasGoal = true;
        s->mission.goalX = goalX;
        s->mission.goalY = goalY;
        addFieldRocks(s->field, s);
        s->mission = mission;
        v.field = true;
        v.fieldSeed = s->field.rocks.seed;
    }

    SeedStream rocks(seed, kRockStream);
    const Vec2 ends[] = {{s->start.x, s->start.y}, {goalX, goalY}};
    const double keep = s->rover.radiusM + kRockEndClearanceM;
    for (Obstacle& ob : s->obstacles) {
        if (ob.known || ob.id >= kFirstFieldRockId) {
            continue;
        }
        Vec2 chosen{0.0, 0.0};
        for (int draw = 0; draw < kRockDraws; ++draw) {
            const Vec2 d{roundTo(rocks.uniform(-kRockShiftXM, kRockShiftXM), 1e-3),
                         roundTo(rocks.uniform(-kRockShiftYM, kRockShiftYM), 1e-3)};
            ConvexPolygon moved = ob.shape;
            bool fits = true;
            for (std::size_t i = 0; i < moved.n; ++i) {
                moved.v[i] = moved.v[i] + d;
                fits = fits && s->map.contains(moved.v[i]);
            }
            for (const Vec2& end : ends) {
                fits = fits && distanceToPolygon(end, moved) >= keep;
            }
            if (fits) {
                chosen = d;
                ob.shape = moved;
                break;
            }
        }
        v.rockShifts.push_back(chosen);
    }

    SeedStream faults(seed, kFaultStream);
    for (FaultSpec& f : s->faults) {
        const double at = 1e-9 * static_cast<double>(f.at);
        const double lo = std::max(at - kFaultWindowS, kEarliestFaultS);
        const double drawn = roundTo(faults.uniform(lo, at + kFaultWindowS), 1e-3);
        const core::TimeNs shift = static_cast<core::TimeNs>(std::llround(drawn * 1e3)) * 1000000 - f.at;
        f.at += shift;
        if (f.until != kNever) {
            f.until += shift;
        }
        v.faultTimesS.push_back(drawn);
    }
    std::stable_sort(s->faults.begin(), s->faults.end(),
                     [](const FaultSpec& a, const FaultSpec& b) { return a.at < b.at; });
    return v;
}

SeedRun runSeed(const CampaignSpec& spec, std::uint64_t seed, std::FILE* out) {
    MissionOptions o = spec.mission;
    o.quiet = out == nullptr;
    Variation variation;
    const auto edit = spec.mission.editScenario;
    o.editScenario = [&](Scenario& s) {
        if (edit) {
            edit(s);
        }
        variation = varyScenario(&s, seed, o.goalX, o.goalY);
    };
    PlanWatch watch;
    o.onFrame = [&watch](LockstepRig& rig) { watch.onFrame(rig); };

    const auto wall0 = std::chrono::steady_clock::now();
    const double cpu0 = processCpuSeconds();
    const MissionSummary m = runMission(o, out);
    Timing timing;
    timing.seed = seed;
    timing.cpuS = processCpuSeconds() - cpu0;
    timing.wallS = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count();

    Row r;
    r.seed = seed;
    r.outcome = outcomeName(m.outcome);
    if (m.outcome == MissionOutcome::kCalledHome) {
        const char* name = reasonName(m.callHome);
        r.reason = name != nullptr ? name : "reason_" + std::to_string(static_cast<unsigned>(m.callHome));
    }
    r.outcomeS = m.outcomeTimeS;
    r.distanceM = m.distanceM;
    r.energyWh = m.energyWh;
    r.goalDistanceM = m.goalDistanceM;
    r.clearanceM = m.leastClearanceM;
    r.collisions = m.collisions;
    r.plans = m.plansMade;
    r.legsSent = m.legsSent;
    r.legsAchieved = m.legsAchieved;
    r.failUps = m.failUps;
    r.replans = m.replans;
    r.boundRelaxations = m.boundRelaxations;
    r.riskRelaxations = m.riskRelaxations;
    r.callHomes = m.callHomes;
    r.habitualReplans = m.habitualReplans;
    r.riskBound = m.riskBound;
    r.riskInForce = m.riskInForce;
    r.riskUsed = m.riskUsed;
    for (const PlanRecord& p : watch.plans()) {
        if (p.lookAhead) {
            ++r.lookAheads;
            continue;
        }
        r.planLatencyS.push_back(p.latencyS);
        r.planSlices.push_back(p.slices);
        r.planFound.push_back(p.found ? 1 : 0);
        timing.planHostMs.push_back(p.hostMs);
    }
    char buf[64];
    std::string rocks, faults;
    for (const Vec2& d : variation.rockShifts) {
        std::snprintf(buf, sizeof buf, "%s%.3f,%.3f", rocks.empty() ? "" : ";", d.x, d.y);
        rocks += buf;
    }
    for (double t : variation.faultTimesS) {
        std::snprintf(buf, sizeof buf, "%s%.3f", faults.empty() ? "" : ",", t);
        faults += buf;
    }
    r.field = variation.field ? std::to_string(variation.fieldSeed) : "-";
    r.rocks = rocks.empty() ? "-" : rocks;
    r.faults = faults.empty() ? "-" : faults;
    if (m.outcome == MissionOutcome::kSetupFailed) {
        // Why, without spaces (a field value holds none).
        std::string why = m.setupError;
        for (char& c : why) {
            c = c == '=' ? ':' : (std::isspace(static_cast<unsigned char>(c)) != 0 ? '_' : c);
        }
        r.reason = why.empty() ? "-" : why;
    }
    return SeedRun{formatRow(r), formatTiming(timing)};
}

std::string crashedRow(std::uint64_t seed, const std::string& why) {
    Row r;
    r.seed = seed;
    r.outcome = "crashed";
    r.reason = why;
    return formatRow(r);
}

}  // namespace rse::sim::mc
