// Fault-protection benchmark (make bench; issue 13): for each fault type, seeded
// whole missions (rse-demo's runner: GOTO (20, 0) on the demo site, the demo's
// own motor faults left out) with the fault injected by the simulator's
// fault scheduler at a random time, and per type:
//   recovered   the mission reached its goal with no response giving up
//   detect      injection -> the health monitor's raise event (s); drive
//               faults that fault protection sees in the drive status first
//               count from its response
//   e-stop      detection -> fault protection's hold (the e-stop), in minor
//               frames (target: <= 1)
//   1st action  response start -> the first recovery command (a drive fault
//               reset / node reset), in minor frames (target: within one
//               deliberative period, 10 frames, after the drive's own settle time
//               is over; the settle time is FAULT_RESPONSE.heartbeat_loss_ms for a lost drive)
//   resumed     injection -> the hold released for the last time (s)
// Attribution: every measurement is of the injected fault's own marks. The
// mission runner names the fault of each raise, response start and recovery
// action from the flight software's telemetry of that frame (FaultStatusMsg,
// FaultProtectionStatusMsg, DriveRecoveryMsg, TaskRestartMsg,
// ReplanRequestMsg; MissionMark::faultId and wheel), and each case says which
// fault ids are its own (the injected drive's: kDriveHeartbeatLost + wheel,
// the id fault protection answers a lost or faulted drive under; the hazard
// detector's heartbeat and stale ids; the stalled row's; ...). So another
// fault in the same moments (other drives tripping on over-current when one
// crashes on a turn) is neither the detection nor the response measured. The
// e-stop is the first hold set at or after the fault's own detection; a run
// where another fault's hold is already in force at detection is counted
// apart ("already held"), not as 0 frames. Runs where another fault's
// response came first, and marks the runner could not attribute, are counted
// and printed too.
// Simulator truth (position, collisions) is read only for the summary.
// Targets (issue 13; checked, unit_test/bench/bench_targets.hpp): 100 % recovered
// for every recoverable type, 0 % for the one that is not (it must call home);
// e-stop within 1 frame of detection; the first recovery action within one
// deliberative period (10 frames) after the fault's settle time.
//
// Usage: bench_fault_recovery [runs]   (default 100 per type)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <random>
#include <string>
#include <vector>

#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_types.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "unit_test/bench/bench_targets.hpp"

namespace {

using rse::sim::FaultSpec;
using rse::sim::FaultType;
using rse::sim::MarkKind;
using rse::sim::MissionMark;
using rse::sim::MissionSummary;

constexpr double kFrameS = 0.01;

using FaultIds = std::vector<std::uint8_t>;

struct FaultCase {
    const char* name;
    const char* scenario;
    double durationS;
    bool recoverable;
    // The fault for one run (at: its random time), and where its drive is.
    std::function<std::vector<FaultSpec>(double at, std::mt19937_64& rng)> make;
    const char* gotoXY = "20,0";                           // the mission's GOTO
    std::function<void(rse::sim::Scenario&)> site = nullptr;  // changes to the site and start
    // Changes to the COARSE_MAP the operator uplinks (by default the scenario's site and known rocks).
    std::function<void(rse::sim::Scenario&)> uplinked = nullptr;
    // The fault ids (msg::fault) that are this run's fault: its raises,
    // responses and recovery actions carry them (MissionMark::faultId). None:
    // no fault injected.
    std::function<FaultIds(const std::vector<FaultSpec>&, const MissionSummary&)> own =
        [](const std::vector<FaultSpec>&, const MissionSummary&) { return FaultIds{}; };
    // Frames fault protection lets the fault settle before it acts (the first
    // action's target is this + one deliberative period).
    std::function<double()> settleFrames = [] { return 0.0; };
};

constexpr double kDeliberativePeriodFrames = 10.0;
constexpr double kEstopTargetFrames = 1.0;

// A scalar field of a default table image (what rse-fsw boots with), so a
// target that follows a table value follows the table.
double defaultTableField(const char* tableName, const char* fieldName) {
    const rse::tables::TableDesc* desc = rse::tables::findTable(tableName);
    for (std::size_t i = 0; desc != nullptr && i < rse::tables::kDefaultTableImageCount; ++i) {
        const rse::tables::TableImageRef& ref = rse::tables::kDefaultTableImages[i];
        rse::tables::TableHeader h;
        if (!rse::tables::readTableHeader(ref.data, ref.length, &h) || h.tableId != static_cast<std::uint16_t>(desc->id)) {
            continue;
        }
        for (std::uint16_t f = 0; f < desc->fieldCount; ++f) {
            double value = 0.0;
            if (std::strcmp(desc->fields[f].name, fieldName) == 0 &&
                rse::tables::readFieldValue(*desc, ref.data + rse::tables::kTableHeaderSize,
                                            ref.length - rse::tables::kTableHeaderSize, f, 0, &value)) {
                return value;
            }
        }
    }
    std::fprintf(stderr, "bench_fault_recovery: no default %s.%s\n", tableName, fieldName);
    std::exit(1);
}

rse::core::TimeNs ns(double s) { return static_cast<rse::core::TimeNs>(s * 1e9); }

FaultSpec wheelFault(FaultType t, std::size_t wheel, double at, double until = -1.0) {
    FaultSpec f;
    f.type = t;
    f.wheel = wheel;
    f.at = ns(at);
    f.until = until < 0.0 ? rse::sim::kNever : ns(until);
    return f;
}

double percentile(std::vector<double> v, double p) {
    if (v.empty()) {
        return NAN;
    }
    std::sort(v.begin(), v.end());
    const auto i = static_cast<std::size_t>(p * static_cast<double>(v.size() - 1) + 0.5);
    return v[std::min(i, v.size() - 1)];
}

// The drive's own fault ids: its heartbeat (the raise of a lost drive) and
// the id fault protection answers it under, lost or faulted (1 + wheel).
FaultIds driveIds(const std::vector<FaultSpec>& f, const MissionSummary&) {
    return {static_cast<std::uint8_t>(rse::msg::fault::kDriveHeartbeatLost + f.at(0).wheel)};
}

struct Tally {
    unsigned runs = 0, recovered = 0, collisions = 0, noResponse = 0;
    unsigned alreadyHeld = 0;      // another fault's hold in force at detection: no e-stop of its own to count
    unsigned otherFirst = 0;       // another fault's response started between injection and this fault's
    unsigned otherRaised = 0;      // runs with a fault raised though none was injected (the baseline)
    unsigned unattributed = 0;     // runs with a mark the runner could not attribute (faultId 0)
    unsigned marksDropped = 0;     // runs with more marks than the summary keeps
    std::vector<double> detect, estopFrames, actionFrames, resumed;
};

bool isOwn(const MissionMark& m, const FaultIds& own) {
    return std::find(own.begin(), own.end(), m.faultId) != own.end();
}

// The first mark of a kind at or after timeS about one of the own fault ids
// (nullptr: none).
const MissionMark* firstOwn(const MissionSummary& s, MarkKind kind, double timeS, const FaultIds& own) {
    for (std::size_t i = 0; i < s.markCount; ++i) {
        const MissionMark& m = s.marks[i];
        if (m.kind == kind && m.timeS >= timeS && isOwn(m, own)) {
            return &m;
        }
    }
    return nullptr;
}

// Whether another fault's response started in [from, before).
bool otherResponseBetween(const MissionSummary& s, double from, double before, const FaultIds& own) {
    for (std::size_t i = 0; i < s.markCount; ++i) {
        const MissionMark& m = s.marks[i];
        if (m.kind == MarkKind::kResponseStarted && m.timeS >= from && m.timeS < before && !isOwn(m, own)) {
            return true;
        }
    }
    return false;
}

void measure(const MissionSummary& s, double at, const FaultIds& own, Tally* t) {
    ++t->runs;
    const bool reached = s.outcome == rse::sim::MissionOutcome::kGoalReached && s.goalDistanceM < 0.6;
    t->recovered += reached && s.responsesGaveUp == 0 ? 1 : 0;
    t->collisions += s.collisions;
    t->unattributed += s.marksUnattributed > 0 ? 1 : 0;
    t->marksDropped += s.marksDropped > 0 ? 1 : 0;
    if (own.empty()) {  // no fault injected
        t->otherRaised += s.firstMark(MarkKind::kFaultRaised, at) != nullptr ? 1 : 0;
        return;
    }
    const MissionMark* raised = firstOwn(s, MarkKind::kFaultRaised, at, own);
    const MissionMark* response = firstOwn(s, MarkKind::kResponseStarted, at, own);
    if (response == nullptr) {
        ++t->noResponse;
        return;
    }
    t->otherFirst += otherResponseBetween(s, at, response->timeS, own) ? 1 : 0;
    // Detection: the fault's health raise, or fault protection's own sight of a drive status.
    const double detected = raised != nullptr && raised->timeS <= response->timeS ? raised->timeS : response->timeS;
    t->detect.push_back(detected - at);
    if (s.heldBefore(detected)) {
        ++t->alreadyHeld;
    } else if (const MissionMark* hold = s.firstMark(MarkKind::kHoldSet, detected)) {
        t->estopFrames.push_back(std::round((hold->timeS - detected) / kFrameS));
    }
    const MissionMark* action = firstOwn(s, MarkKind::kRecoveryAction, response->timeS, own);
    if (action != nullptr) {
        t->actionFrames.push_back(std::round((action->timeS - response->timeS) / kFrameS));
    }
    if (s.lastResumeTimeS >= at) {
        t->resumed.push_back(s.lastResumeTimeS - at);
    }
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::atoi(argv[1]) : 100;
    if (runs < 1 || runs > 10000) {
        std::fprintf(stderr, "usage: bench_fault_recovery [runs 1..10000]\n");
        return 2;
    }
    const char* demo = rse::sim::kDefaultMissionScenario;
    std::vector<FaultCase> cases = {
        // The same missions without a fault: what the fault cases are measured against.
        {"none (baseline)", demo, 300.0, true, [](double, std::mt19937_64&) { return std::vector<FaultSpec>{}; }},
        {"drive heartbeat gap 0.2 s", demo, 300.0, true,
         [](double at, std::mt19937_64& rng) {
             return std::vector<FaultSpec>{wheelFault(FaultType::kDriveHeartbeatLoss, rng() % 6, at, at + 0.2)};
         }},
        {"drive crash, restart 2 s", demo, 300.0, true,
         [](double at, std::mt19937_64& rng) {
             return std::vector<FaultSpec>{wheelFault(FaultType::kDriveCrash, rng() % 6, at, at + 2.0)};
         }},
        {"drive fault (EMCY), resettable", demo, 300.0, true,
         [](double at, std::mt19937_64& rng) {
             FaultSpec f = wheelFault(FaultType::kDriveFault, rng() % 6, at);
             f.cobId = 0x2310;
             return std::vector<FaultSpec>{f};
         }},
        {"hazard detector silent 10 s", demo, 300.0, true,
         [](double at, std::mt19937_64&) {
             FaultSpec f;
             f.type = FaultType::kSensorDropout;
             f.device = rse::sim::SimDevice::kHazard;
             f.at = ns(at);
             f.until = ns(at + 10.0);
             return std::vector<FaultSpec>{f};
         }},
        {"IMU bias step 0.005 rad/s", demo, 300.0, true,
         [](double at, std::mt19937_64&) {
             FaultSpec f;
             f.type = FaultType::kImuBiasStep;
             f.at = ns(at);
             f.value = 0.005;
             return std::vector<FaultSpec>{f};
         }},
        {"motor fails (wheel locks)", demo, 300.0, false,
         [](double at, std::mt19937_64& rng) {
             return std::vector<FaultSpec>{wheelFault(FaultType::kMotorFailure, rng() % 6, at)};
         }},
        // Last, so the cases above keep their seeds. The ground link's owner
        // sends EXEC_SET_TASK (disable) for the row; only fault protection enables it.
        {"habitual layer stalled", demo, 300.0, true,
         [](double at, std::mt19937_64&) {
             FaultSpec f;
             f.type = FaultType::kTaskStall;
             f.taskName = "habitual";
             f.at = ns(at);
             return std::vector<FaultSpec>{f};
         }},
        // Along the south edge of the site (y_min -10 m) to (18, -8.6); the
        // ground gives way and the rover slides 2.5-3 m southwards (within
        // 10 degrees of due south) over 2 s, always far enough to leave the map,
        // off the orbital map (the world goes on to y = -20). Detected by the
        // off-map fault (fault 46, raise event 738), after the estimator has
        // refused the jump and re-anchored; fault protection asks for a
        // replan from the pose (no hold: the rover must drive back on).
        {"off the map (slide 2.5-3 m)", demo, 300.0, true,
         [](double at, std::mt19937_64& rng) {
             std::uniform_real_distribution<double> offset(2.5, 3.0);
             std::uniform_real_distribution<double> bearingDeg(-100.0, -80.0);
             FaultSpec f;
             f.type = FaultType::kSlide;
             f.at = ns(at);
             f.until = ns(at + 2.0);
             f.value = offset(rng);
             f.bearingRad = bearingDeg(rng) * 3.141592653589793 / 180.0;
             return std::vector<FaultSpec>{f};
         },
         "18,-8.6",
         [](rse::sim::Scenario& s) {
             s.start.x = 0.0;
             s.start.y = -8.6;
             s.map.yMin = -20.0;
         },
         [](rse::sim::Scenario& s) { s.map.yMin = -10.0; }},  // the orbital survey ends at -10 m
    };
    auto named = [&cases](const char* name) -> FaultCase& {
        for (FaultCase& c : cases) {
            if (std::strcmp(c.name, name) == 0) {
                return c;
            }
        }
        std::fprintf(stderr, "bench_fault_recovery: no case '%s'\n", name);
        std::exit(1);
    };
    // Each case's own fault ids (the file's top comment).
    for (const char* drive : {"drive heartbeat gap 0.2 s", "drive crash, restart 2 s", "drive fault (EMCY), resettable",
                              "motor fails (wheel locks)"}) {
        named(drive).own = driveIds;
    }
    named("hazard detector silent 10 s").own = [](const std::vector<FaultSpec>&, const MissionSummary&) {
        const auto hazard = static_cast<std::uint8_t>(rse::msg::DeviceNode::kHazard);
        return FaultIds{static_cast<std::uint8_t>(rse::msg::fault::kDeviceHeartbeatLost + hazard),
                        static_cast<std::uint8_t>(rse::msg::fault::kSensorStale + hazard)};
    };
    named("IMU bias step 0.005 rad/s").own = [](const std::vector<FaultSpec>&, const MissionSummary&) {
        return FaultIds{rse::msg::fault::kPoseUncertain};
    };
    named("habitual layer stalled").own = [](const std::vector<FaultSpec>&, const MissionSummary& s) {
        // The row the ground disabled (its EXEC_SET_TASK).
        return s.stalledRow < 0 ? FaultIds{} : FaultIds{static_cast<std::uint8_t>(rse::msg::fault::kTaskStalled + s.stalledRow)};
    };
    named("off the map (slide 2.5-3 m)").own = [](const std::vector<FaultSpec>&, const MissionSummary&) {
        return FaultIds{rse::msg::fault::kOffMap};
    };
    // Settle times, from the tables rse-fsw boots with: a lost drive is given
    // heartbeat_loss_ms to come back; a faulted one gets the CAN master's resets first.
    named("drive crash, restart 2 s").settleFrames = [] {
        return defaultTableField("FAULT_RESPONSE", "heartbeat_loss_ms") / (kFrameS * 1000.0);
    };
    named("motor fails (wheel locks)").settleFrames = [] {
        return defaultTableField("FAULT_RESPONSE", "drive_restart_attempts") *
               defaultTableField("FAULT_RESPONSE", "drive_fault_reset_wait_ms") / (kFrameS * 1000.0);
    };
    rse::bench::Targets targets;
    std::printf("fault recovery: %d seeded demo missions per fault type, fault at a random time in [5, 60] s\n", runs);
    std::printf("%-32s %5s %9s %9s %12s %12s %14s %10s\n", "fault", "runs", "recovered", "collide", "detect s p50/max",
                "e-stop fr max", "1st action fr", "resumed s p50/max");
    const auto wall0 = std::chrono::steady_clock::now();
    for (const FaultCase& c : cases) {
        Tally t;
        std::mt19937_64 rng(0x5EED0000u + static_cast<unsigned>(&c - cases.data()));
        std::uniform_real_distribution<double> when(5.0, 60.0);
        for (int r = 0; r < runs; ++r) {
            const double at = std::round(when(rng) * 100.0) / 100.0;
            const std::uint64_t seed = rng();
            const std::vector<FaultSpec> faults = c.make(at, rng);
            rse::sim::MissionOptions o;
            const char* args[] = {"rse-demo", "--no-faults", "--quiet", "--scenario", c.scenario, "--goto", c.gotoXY};
            std::string error;
            if (rse::sim::parseMissionArgs(7, args, &o, &error) != rse::sim::ParseOutcome::kRun) {
                std::fprintf(stderr, "bench_fault_recovery: %s\n", error.c_str());
                return 1;
            }
            o.durationS = c.durationS;
            o.editScenario = [&](rse::sim::Scenario& s) {
                s.seed = seed;
                s.faults = faults;
                if (c.site) {
                    c.site(s);
                }
            };
            o.editUplinkedMap = c.uplinked;
            const MissionSummary summary = rse::sim::runMission(o, nullptr);
            const unsigned unanswered = t.noResponse;
            measure(summary, at, c.own(faults, summary), &t);
            if (t.noResponse > unanswered && std::getenv("BENCH_VERBOSE") != nullptr) {
                std::printf("  %s: fault at %.2f s (value %.3f, bearing %.3f rad), seed %llu: no response; %s at "
                            "%.1f s, end (%.2f, %.2f)\n",
                            c.name, at, faults.empty() ? 0.0 : faults[0].value,
                            faults.empty() ? 0.0 : faults[0].bearingRad, static_cast<unsigned long long>(seed),
                            rse::sim::toString(summary.outcome), summary.outcomeTimeS, summary.finalX, summary.finalY);
            }
            const bool clean = summary.outcome == rse::sim::MissionOutcome::kGoalReached && summary.collisions == 0;
            if (!clean && c.recoverable && std::getenv("BENCH_VERBOSE") != nullptr) {
                std::printf("  %s: fault at %.2f s (wheel %zu), seed %llu: %s at %.1f s (%s), %u collisions, end (%.2f, %.2f)\n",
                            c.name, at, faults.empty() ? 0 : faults[0].wheel, static_cast<unsigned long long>(seed),
                            rse::sim::toString(summary.outcome),
                            summary.outcomeTimeS, summary.callHomeText.c_str(), summary.collisions, summary.finalX,
                            summary.finalY);
            }
        }
        auto maxOf = [](const std::vector<double>& v) { return v.empty() ? NAN : *std::max_element(v.begin(), v.end()); };
        std::printf("%-32s %5u %8.0f%% %9u %6.2f/%-6.2f %12.0f %6.0f/%-7.0f %6.1f/%-6.1f%s\n", c.name, t.runs,
                    100.0 * t.recovered / t.runs, t.collisions, percentile(t.detect, 0.5), maxOf(t.detect),
                    maxOf(t.estopFrames), percentile(t.actionFrames, 0.5), maxOf(t.actionFrames),
                    percentile(t.resumed, 0.5), maxOf(t.resumed), c.recoverable ? "" : "  (not recoverable: call home expected)");
        if (t.noResponse > 0) {
            std::printf("%-32s %u runs with no fault-protection response to this fault\n", "", t.noResponse);
        }
        if (t.otherRaised > 0) {
            std::printf("%-32s %u runs raised a fault with none injected\n", "", t.otherRaised);
        }
        if (t.otherFirst > 0) {
            std::printf("%-32s %u runs: another fault's response came first (not counted as this fault's)\n", "",
                        t.otherFirst);
        }
        if (t.alreadyHeld > 0) {
            std::printf("%-32s %u runs already held by another fault at detection (no e-stop counted)\n", "",
                        t.alreadyHeld);
        }
        if (t.unattributed > 0 || t.marksDropped > 0) {
            std::printf("%-32s %u runs with a mark no telemetry named, %u runs with marks dropped\n", "",
                        t.unattributed, t.marksDropped);
        }
        const auto verdict = [&targets](bool met) { return targets.check(met) ? "PASS" : "FAIL"; };
        const double actionTarget = c.settleFrames() + kDeliberativePeriodFrames;
        const bool recoveredOk = c.recoverable ? t.recovered == t.runs : t.recovered == 0;
        const bool estopOk = t.estopFrames.empty() || maxOf(t.estopFrames) <= kEstopTargetFrames;
        const bool actionOk = t.actionFrames.empty() || maxOf(t.actionFrames) <= actionTarget;
        std::printf("%-32s %s recovered %s, %s e-stop <= %.0f frame, %s 1st action <= %.0f frames\n", "",
                    verdict(recoveredOk), c.recoverable ? "100 %" : "0 % (call home)", verdict(estopOk),
                    kEstopTargetFrames, verdict(actionOk), actionTarget);
        std::fflush(stdout);
    }
    std::printf("wall time %.0f s\n",
                std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0).count());
    return targets.finish();
}
