// A campaign over generated rock fields (issue 31, "Targets"): each run a
// field of its own (Golombek and Rapp's model, sim_stub/scenario/field_rocks.hpp;
// half the runs at k = 0.05, half at k = 0.10, rocks of 0.5 m and more, those
// of 1 m and more known and uplinked as the site map), a 200 m traverse on a
// 220 m x 60 m site flown in lockstep as rse-demo flies it.
//
// Per run: the outcome (goal reached, called home and why, timed out), the
// contacts (the simulator's truth) and those the flight software felt (its
// contact reflex: one felt with no touch is a false alarm), the path driven against the straight
// line and against an offline shortest path with the rover's clearance (the
// global route's search over every rock, known and hidden, at the bare
// footprint, unpriced, on a 0.5 m lattice: the way a rover that knew every
// rock could take).
//
// TARGET lines (the issue's): 0 contacts; at least 95 % reach the goal and
// every other run ends in a call home with its reason (none times out); path
// length at most 1.15 x the straight line in the median and 1.46 x at worst.
//
// Then the 700 m Snowdrift traverse (sim_stub/scenarios/snowdrift.toml) once:
// TARGET lines for its goal, its contacts, every CPU-timed task in budget in
// every frame, and lockstep at least 20 x real time (wall clock, here). Every
// horizon it flew (a plan made, then a leg sent from it) is sampled against
// every rock of the site map (whole_map_mc.hpp): TARGET, each horizon's
// collision rate within its risk bound Delta (the risk in force when it was
// planned) by at most sampling noise (cc_monte_carlo.hpp, allowedCollisions:
// n Delta + 4 sd), and the collisions of all horizons within the sum of their
// bounds.
//
// Usage: bench_site_fields [RUNS] (default 100; half at each k; 0: Snowdrift only).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "fsw/deliberative/global_route.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/reflexive/contact_reflex.hpp"
#include "fsw/site_map/site_map.hpp"
#include "ground/site_map_encoder.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/mission_runner.hpp"
#include "fsw/geometry/rover_footprint.hpp"
#include "sim_stub/scenario/coarse_map_source.hpp"
#include "sim_stub/scenario/field_rocks.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/bench/bench_targets.hpp"
#include "unit_test/bench/cc_monte_carlo.hpp"
#include "unit_test/bench/whole_map_mc.hpp"

using namespace rse;

namespace {

constexpr const char* kTemplate = "sim_stub/scenarios/rock_field_100m.toml";
constexpr double kStraightM = 200.0;

// The template's site made 220 m x 60 m, a fresh field of k and seed on it.
void fieldRun(sim::Scenario& s, double k, std::uint64_t seed) {
    s.map = sim::MapBounds{0.0, 220.0, 0.0, 60.0};
    s.start = sim::Pose2{10.0, 30.0, 0.0};
    s.mission.present = true;
    s.mission.hasGoal = true;
    s.mission.goalX = 210.0;
    s.mission.goalY = 30.0;
    s.obstacles.clear();
    s.field.rocks.k = k;
    s.field.rocks.seed = seed;
    sim::addFieldRocks(s.field, &s);
}

// The shortest way with the rover's clearance past every rock (known and hidden).
double offlineShortestM(const sim::Scenario& s, double clearanceM) {
    static site_map::SiteMap map;
    static deliberative::GlobalRoute route;
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(sim::siteMapSpec(s, sim::MapRocks::kEvery));
    site_map::SiteMapCheck check;
    if (map.load(image.data(), image.size(), &check) != core::Status::kOk) {
        return -1.0;
    }
    deliberative::RouteParams p;
    p.clearanceM = clearanceM;
    p.comfortM = clearanceM + 0.01;
    p.proximityCost = 0.0;
    p.spacingM = 0.5;
    p.workBudget = 4000000000ULL;
    if (route.start(map, {s.start.x, s.start.y}, {s.mission.goalX, s.mission.goalY}, p) !=
        deliberative::RouteRefusal::kNone) {
        return -1.0;
    }
    for (int i = 0; i < 1000000 && !route.step(100000000ULL); ++i) {
    }
    return route.state() == deliberative::RouteState::kFound ? route.lengthM() : -1.0;
}

double median(std::vector<double> v) {
    if (v.empty()) {
        return 0.0;
    }
    std::sort(v.begin(), v.end());
    const std::size_t n = v.size();
    return n % 2 == 1 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

struct Horizon {
    deliberative::CcProblem problem;
    deliberative::CcPlan plan;
    double riskInForce;
};

// Each flown horizon sampled against every known rock of the scenario (the
// site map the rover was sent, built again here as the runner built it).
void flownHorizonsAgainstTheMap(const char* scenarioPath, const std::vector<Horizon>& flown, double radiusM,
                                rse::bench::Targets* targets) {
    static site_map::SiteMap map;
    const std::vector<std::uint8_t> image = ground::encodeSiteMap(sim::siteMapSpec(sim::loadScenarioFile(scenarioPath)));
    site_map::SiteMapCheck check;
    if (map.load(image.data(), image.size(), &check) != core::Status::kOk || flown.empty() || radiusM <= 0.0) {
        std::printf("TARGET snowdrift: every flown horizon's whole-map collision rate <= Delta (+4 sd): "
                    "no horizons or no map FAIL\n");
        (void)targets->check(false);
        return;
    }
    constexpr std::size_t kSamples = 20000;
    std::size_t within = 0, hits = 0, samples = 0;
    double sumDelta = 0.0, worstRatio = 0.0;
    bool crowded = false;
    std::printf("%3s %6s %9s %9s %8s %6s\n", "h", "steps", "Delta", "certified", "rate", "hits");
    for (std::size_t h = 0; h < flown.size(); ++h) {
        const Horizon& f = flown[h];
        const test::WholeMapMcResult r =
            test::sampleAgainstWholeMap(map, f.problem, f.plan, radiusM, kSamples, 31 + h);
        const bool ok = r.collisions <= test::cc::allowedCollisions(f.riskInForce, r.samples);
        within += ok ? 1 : 0;
        hits += r.collisions;
        samples += r.samples;
        sumDelta += f.riskInForce * static_cast<double>(r.samples);
        crowded = crowded || r.crowded;
        const double rate = static_cast<double>(r.collisions) / static_cast<double>(r.samples);
        worstRatio = std::max(worstRatio, rate / f.riskInForce);
        std::printf("%3zu %6u %9.2e %9.2e %8.5f %6zu%s\n", h + 1, static_cast<unsigned>(f.plan.steps),
                    f.riskInForce, f.plan.riskUsed, rate, r.collisions, ok ? "" : "  over");
    }
    std::printf("snowdrift horizons: %zu flown, %zu samples each against %zu rocks; %zu collisions in %zu samples "
                "(rate %.2e against a mean Delta of %.2e), the worst horizon at %.2f x its Delta%s\n",
                flown.size(), kSamples, map.rockCount(), hits, samples,
                static_cast<double>(hits) / static_cast<double>(samples), sumDelta / static_cast<double>(samples),
                worstRatio, crowded ? "; some segment crowded (counted as a collision)" : "");
    // For information: the same paths against every rock, the hidden ones
    // too (the certificate is against the map the rover was given; the
    // habitual layer plans round the hidden rocks it sees).
    {
        static site_map::SiteMap everyRock;
        const std::vector<std::uint8_t> all =
            ground::encodeSiteMap(sim::siteMapSpec(sim::loadScenarioFile(scenarioPath), sim::MapRocks::kEvery));
        if (everyRock.load(all.data(), all.size(), &check) == core::Status::kOk) {
            std::size_t allHits = 0;
            for (std::size_t h = 0; h < flown.size(); ++h) {
                allHits += test::sampleAgainstWholeMap(everyRock, flown[h].problem, flown[h].plan, radiusM, kSamples,
                                                       31 + h).collisions;
            }
            std::printf("snowdrift horizons against every rock, hidden ones too (%zu): %zu collisions in %zu samples "
                        "(open loop: not what the rover flies, which sees and plans round them)\n",
                        everyRock.rockCount(), allHits, samples);
        }
    }
    const bool all = within == flown.size();
    std::printf("TARGET snowdrift: every flown horizon's whole-map collision rate <= Delta (+4 sd): %zu of %zu %s\n",
                within, flown.size(), targets->check(all) ? "PASS" : "FAIL");
    const bool pooled = static_cast<double>(hits) <= sumDelta;
    std::printf("TARGET snowdrift: all flown horizons' collisions <= the sum of their Deltas: %zu <= %.1f %s\n", hits,
                sumDelta, targets->check(pooled) ? "PASS" : "FAIL");
}

void snowdrift(rse::bench::Targets* targets) {
    sim::MissionOptions o;
    const char* args[] = {"bench_site_fields", "--scenario", "sim_stub/scenarios/snowdrift.toml", "--quiet",
                          "--no-report"};
    std::string error;
    if (sim::parseMissionArgs(5, args, &o, &error) != sim::ParseOutcome::kRun) {
        std::printf("snowdrift: %s\n", error.c_str());
        return;
    }
    std::uint32_t cpuOver = 0;
    std::string overWhere;  // each CPU-timed row: its runs over budget, its longest run
    double kthCurrentMax = 0.0, contactAmps = 0.0;
    // The horizons flown: a plan copied when it is made, kept when a leg is sent before the next.
    std::vector<Horizon> flown;
    Horizon pending{};
    bool havePending = false;
    std::uint32_t plansSeen = 0, legsSeen = 0;
    double radiusM = 0.0;
    o.onFrame = [&](sim::LockstepRig& rig) {
        const core::Executive& exec = rig.fsw().executive();
        cpuOver = 0;
        overWhere.clear();
        for (std::size_t i = 0; i < exec.taskCount(); ++i) {
            const core::TaskStats* st = exec.taskStats(i);
            cpuOver += st != nullptr ? st->cpuOverBudget : 0U;
            const core::RateGroupEntry* e = exec.entry(i);
            if (st != nullptr && e != nullptr && e->cpuTimed) {
                overWhere += " " + std::string(e->name) + " " + std::to_string(st->cpuOverBudget) + " (longest " +
                             std::to_string(st->cpuMax / 1000) + " of " + std::to_string(e->budgetUs) + " us)";
            }
        }
        const deliberative::DeliberativeTask& d = rig.fsw().deliberative();
        if (d.status().plansMade != plansSeen) {
            plansSeen = d.status().plansMade;
            pending = Horizon{d.problem(), d.plan(), d.status().riskInForce};
            havePending = d.plan().status == deliberative::CcStatus::kOptimal ||
                          d.plan().status == deliberative::CcStatus::kFeasible;
        }
        if (d.counters().legsSent != legsSeen) {
            legsSeen = d.counters().legsSent;
            if (havePending) {
                flown.push_back(pending);
                havePending = false;
            }
        }
        radiusM = geometry::clearanceRadiusM(rig.fsw().tables().roverGeometry());
        // The contact reflex's margin in normal driving: the contact_wheels-th
        // largest current among the wheels it would judge (commanded to turn,
        // operational), the figure that reaching contact_current_a makes a contact.
        const msg::DriveStatusMsg& drives = rig.driveStatus();
        double amps[msg::kWheelCount];
        std::size_t active = 0;
        for (const msg::WheelStatus& w : drives.wheels) {
            if (std::fabs(w.targetRadS) >= reflexive::kActiveWheelRadS && w.health == msg::DriveHealth::kOperational) {
                // Kept in descending order (at most six).
                std::size_t at = active++;
                for (; at > 0 && amps[at - 1] < std::fabs(w.currentA); --at) {
                    amps[at] = amps[at - 1];
                }
                amps[at] = std::fabs(w.currentA);
            }
        }
        const std::size_t kth = rig.fsw().tables().follower().contact_wheels;
        if (active >= kth && kth > 0) {
            kthCurrentMax = std::max(kthCurrentMax, amps[kth - 1]);
        }
        contactAmps = static_cast<double>(rig.fsw().tables().follower().contact_current_a);
    };
    const sim::MissionSummary s = sim::runMission(o, nullptr);
    const double speed = s.wallTimeS > 0.0 ? s.endTimeS / s.wallTimeS : 0.0;
    std::printf("snowdrift: %s at %.0f s, driven %.1f m (%.3f x 700 m), %u contacts, %u plans, %.0f x real time\n",
                sim::toString(s.outcome), s.outcomeTimeS, s.distanceM, s.distanceM / 700.0, s.collisions, s.plansMade,
                speed);
    std::printf("snowdrift horizon ends: %u, %u driven through (the next horizon planned while driving), %u stops "
                "to plan (PLAN telemetry)\n",
                s.horizonsReached, s.horizonsDrivenThrough, s.horizonStops);
    const bool reached = s.outcome == sim::MissionOutcome::kGoalReached;
    std::printf("TARGET snowdrift 700 m: goal reached: %s %s\n", reached ? "yes" : "no",
                targets->check(reached) ? "PASS" : "FAIL");
    std::printf("TARGET snowdrift 700 m: 0 contacts: %u %s\n", s.collisions,
                targets->check(s.collisions == 0) ? "PASS" : "FAIL");
    std::printf("TARGET snowdrift 700 m: every CPU-timed task inside its budget in every frame: %u runs over %s\n",
                cpuOver, targets->check(cpuOver == 0) ? "PASS" : "FAIL");
    std::printf("snowdrift CPU-timed rows: runs over budget (longest run):%s\n", overWhere.c_str());
    std::printf("snowdrift contact margin: the contact_wheels-th largest active wheel current in any frame %.2f A, "
                "a contact at %.2f A\n",
                kthCurrentMax, contactAmps);
    std::printf("TARGET snowdrift 700 m: lockstep >= 20 x real time: %.0f x %s\n", speed,
                targets->check(speed >= 20.0) ? "PASS" : "FAIL");
    flownHorizonsAgainstTheMap("sim_stub/scenarios/snowdrift.toml", flown, radiusM, targets);
}

}  // namespace

int main(int argc, char** argv) {
    const int runs = argc > 1 ? std::atoi(argv[1]) : 100;
    if (runs < 0 || runs == 1) {
        std::fprintf(stderr, "usage: bench_site_fields [RUNS: 0 (Snowdrift only) or >= 2]\n");
        return 2;
    }
    rse::bench::Targets targets;
    if (runs == 0) {
        snowdrift(&targets);
        return targets.finish();
    }
    std::printf("site fields: %d runs of a 200 m traverse (220 m x 60 m), half at k = 0.05, half at k = 0.10\n", runs);
    std::printf("%4s %5s %6s %6s %-22s %5s %5s %8s %8s %8s %7s\n", "run", "k", "rocks", "known", "outcome", "hits",
                "felt", "driven", "/line", "/short", "wall s");
    int reached = 0, calledHome = 0, timedOut = 0, setup = 0;
    std::uint32_t contacts = 0;
    std::uint32_t felt = 0;  // contacts the flight software felt (its contact reflex), whatever the truth
    std::vector<double> ratios, shortRatios;
    double worst = 0.0;
    for (int run = 0; run < runs; ++run) {
        const double k = run % 2 == 0 ? 0.05 : 0.10;
        const std::uint64_t seed = 1000 + static_cast<std::uint64_t>(run);
        sim::MissionOptions o;
        const char* args[] = {"bench_site_fields", "--scenario", kTemplate, "--goto", "210,30,1e-3", "--quiet",
                              "--no-report", "--duration", "2400"};
        std::string error;
        if (sim::parseMissionArgs(9, args, &o, &error) != sim::ParseOutcome::kRun) {
            std::fprintf(stderr, "bench_site_fields: %s\n", error.c_str());
            return 1;
        }
        o.editScenario = [k, seed](sim::Scenario& s) { fieldRun(s, k, seed); };
        std::uint32_t feltHere = 0;
        o.onFrame = [&feltHere](sim::LockstepRig& rig) { feltHere = rig.fsw().follower().counters().contacts; };
        sim::Scenario scenario = sim::loadScenarioFile(kTemplate);
        fieldRun(scenario, k, seed);
        const sim::FieldCounts counts = sim::fieldCounts(scenario);
        const sim::MissionSummary s = sim::runMission(o, nullptr);
        const double shortest = offlineShortestM(scenario, scenario.rover.radiusM);
        const char* outcome = sim::toString(s.outcome);
        std::string what = outcome;
        if (s.outcome == sim::MissionOutcome::kGoalReached) {
            ++reached;
            ratios.push_back(s.distanceM / kStraightM);
            worst = std::max(worst, s.distanceM / kStraightM);
            if (shortest > 0.0) {
                shortRatios.push_back(s.distanceM / shortest);
            }
        } else if (s.outcome == sim::MissionOutcome::kCalledHome) {
            ++calledHome;
            what += " (" + std::to_string(static_cast<int>(s.callHome)) + ")";
        } else if (s.outcome == sim::MissionOutcome::kTimedOut) {
            ++timedOut;
        } else {
            ++setup;
            what += ": " + s.setupError;
        }
        contacts += s.collisions;
        felt += feltHere;
        std::printf("%4d %5.2f %6zu %6zu %-22s %5u %5u %8.1f %8.3f %8.3f %7.1f\n", run, k, counts.rocks, counts.known,
                    what.c_str(), s.collisions, feltHere, s.distanceM, s.distanceM / kStraightM,
                    shortest > 0.0 ? s.distanceM / shortest : 0.0, s.wallTimeS);
        std::fflush(stdout);
    }
    const double rate = static_cast<double>(reached) / runs;
    std::printf("reached %d, called home %d, timed out %d, setup failed %d of %d; contacts %u (felt by the flight "
                "software: %u)\n",
                reached, calledHome, timedOut, setup, runs, contacts, felt);
    std::printf("path driven / straight line: median %.3f, worst %.3f; / offline shortest with clearance: median %.3f\n",
                median(ratios), worst, median(shortRatios));
    std::printf("TARGET 0 contacts over every run: %u %s\n", contacts, targets.check(contacts == 0) ? "PASS" : "FAIL");
    std::printf("TARGET at least 95 %% reach the goal: %.1f %% %s\n", 100.0 * rate,
                targets.check(rate >= 0.95) ? "PASS" : "FAIL");
    std::printf("TARGET every other run calls home with its reason (none times out): %d timed out, %d setup %s\n",
                timedOut, setup, targets.check(timedOut == 0 && setup == 0) ? "PASS" : "FAIL");
    std::printf("TARGET path <= 1.15 x the straight line in the median: %.3f %s\n", median(ratios),
                targets.check(!ratios.empty() && median(ratios) <= 1.15) ? "PASS" : "FAIL");
    std::printf("TARGET path <= 1.46 x the straight line at worst: %.3f %s\n", worst,
                targets.check(!ratios.empty() && worst <= 1.46) ? "PASS" : "FAIL");
    snowdrift(&targets);
    return targets.finish();
}
