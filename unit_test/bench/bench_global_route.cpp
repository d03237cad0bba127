// The global route's growth (issue 31, "Growth"): route-planning CPU and
// memory for 100, 1 000, 5 000 and 20 000 rocks (the site map holds 20 480) on a
// 1 km x 1 km site, a diagonal route from corner to corner, sliced as the
// deliberative task slices it (kSliceWork a run), each run's CPU time against
// the deliberative rate-group row's budget.
//
// Fields: Golombek and Rapp's model (sim_stub/scenario/rock_field.hpp) at
// k = 0.30 with every rock of 1 m or more (about 21 000 on the square
// kilometre), its first N rocks; no rock within
// 5 m of the route's ends. Time is this thread's CPU time
// (CLOCK_THREAD_CPUTIME_ID) around each step().
//
// The map is put in force the way MAP_COMMIT does it on board: the image
// uploaded into the service in 200-byte chunks, then the commit's slices
// (CRC-32, check, load into the slot not in force), one a command-task run,
// each timed.
//
// TARGET lines: a route found at every size; no run over the budget at any
// size; no MAP_COMMIT slice over its share of the command task's run at any
// size. Also printed: the work units' cost here (ns a unit: the scale
// kWorkKUnitsPerMs assumes 0.45 - 0.9 ns).
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <ctime>
#include <vector>

#include "fsw/core/crc32.hpp"
#include "fsw/deliberative/global_route.hpp"
#include "fsw/deliberative/plan_maker.hpp"
#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/site_map/site_map_service.hpp"
#include "ground/site_map_encoder.hpp"
#include "sim_stub/scenario/rock_field.hpp"
#include "unit_test/bench/bench_targets.hpp"

using rse::deliberative::GlobalRoute;
using rse::deliberative::RouteParams;
using rse::deliberative::RouteState;
using rse::geometry::Point2;

namespace {

// The deliberative row of the rate-group table (fsw/app/fsw_app.cpp): 5 ms a run.
constexpr double kDeliberativeBudgetUs = 5000.0;
// A MAP_COMMIT slice's share of the command task's 2 ms run: what ingest's
// allowance (1.2 ms, command_task.hpp) and the frame's dispatch (0.2 ms) leave.
constexpr double kCommitSliceBudgetUs = 600.0;

double threadCpuUs() {
    timespec ts{};
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    return static_cast<double>(ts.tv_sec) * 1e6 + static_cast<double>(ts.tv_nsec) / 1e3;
}

rse::ground::SiteMapSpec fieldOf(std::size_t rocks, Point2 a, Point2 b) {
    rse::sim::RockFieldParams p;
    p.k = 0.30;
    p.xMin = 0.0;
    p.yMin = 0.0;
    p.xMax = 1000.0;
    p.yMax = 1000.0;
    p.minDiameterM = 1.0;
    p.seed = 31;
    rse::ground::SiteMapSpec spec;
    spec.site = {0.0F, 0.0F, 1000.0F, 1000.0F};
    for (const rse::sim::FieldRock& r : rse::sim::generateRockField(p)) {
        if (spec.rocks.size() == rocks) {
            break;
        }
        if (std::hypot(r.x - a.x, r.y - a.y) < 5.0 + r.diameterM || std::hypot(r.x - b.x, r.y - b.y) < 5.0 + r.diameterM) {
            continue;
        }
        std::vector<rse::ground::MapVertex> v;
        for (const rse::sim::RockVertex& q : r.vertices) {
            v.push_back({static_cast<float>(q.x), static_cast<float>(q.y)});
        }
        spec.rocks.push_back(v);
    }
    return spec;
}

}  // namespace

int main() {
    static GlobalRoute route;
    rse::bench::Targets targets;
    const Point2 start{20.0, 20.0}, goal{980.0, 980.0};
    const double straight = std::hypot(goal.x - start.x, goal.y - start.y);
    std::printf("global route, 1 km x 1 km, (20, 20) to (980, 980): %.0f m straight; slice %llu units a run\n", straight,
                static_cast<unsigned long long>(rse::deliberative::kSliceWork));
    std::printf("static memory: site map %zu B, route search %zu B (the same at every size)\n",
                rse::site_map::kSiteMapBytes, rse::deliberative::kGlobalRouteBytes);
    std::printf("%7s %8s %9s %11s %7s %9s %10s %11s %9s %8s %12s %14s\n", "rocks", "state", "length/", "expansions", "runs",
                "CPU ms", "max run us", "work Munits", "ns/unit", "map B", "commit runs", "max slice us");
    std::printf("%7s %8s %9s\n", "", "", "straight");
    bool allFound = true;
    double worstRunUs = 0.0;
    double nsPerUnitMax = 0.0;
    double worstSliceUs = 0.0;
    double sliceUsByPhase[4] = {};
    static rse::core::VirtualClock clock;
    static rse::core::EventLog events(clock);
    static rse::site_map::SiteMapService service(events);
    for (const std::size_t n : {std::size_t{100}, std::size_t{1000}, std::size_t{5000}, std::size_t{20000}}) {
        const rse::ground::SiteMapSpec spec = fieldOf(n, start, goal);
        const std::vector<std::uint8_t> image = rse::ground::encodeSiteMap(spec);
        // MAP_LOAD's chunks, then MAP_COMMIT and its slices (this thread's CPU each).
        for (std::size_t at = 0; at < image.size(); at += 200) {
            (void)service.loadChunk(static_cast<std::uint32_t>(at), image.data() + at, std::min<std::size_t>(200, image.size() - at));
        }
        if (service.commit(static_cast<std::uint32_t>(image.size()), rse::core::crc32(image.data(), image.size())) !=
            rse::site_map::UploadRefusal::kNone) {
            std::printf("%7zu: MAP_COMMIT refused at once\n", n);
            return 1;
        }
        double sliceUs = 0.0;
        for (int run = 0; run < 10000 && service.commitPhase() != rse::site_map::CommitPhase::kNone; ++run) {
            const auto phase = static_cast<std::size_t>(service.commitPhase());
            const double c0 = threadCpuUs();
            (void)service.serviceCommit(false);
            const double us = threadCpuUs() - c0;
            sliceUs = std::max(sliceUs, us);
            sliceUsByPhase[phase] = std::max(sliceUsByPhase[phase], us);
        }
        if (service.lastRefusal() != rse::site_map::UploadRefusal::kNone || service.map().rockCount() != n) {
            std::printf("%7zu: the map was refused (%s)\n", n, rse::site_map::toString(service.lastRefusal()));
            return 1;
        }
        worstSliceUs = std::max(worstSliceUs, sliceUs);
        const rse::site_map::SiteMap& map = service.map();
        const RouteParams params;
        const double t0 = threadCpuUs();
        if (route.start(map, start, goal, params) != rse::deliberative::RouteRefusal::kNone) {
            std::printf("%7zu: refused (%s)\n", n, rse::deliberative::toString(route.refusal()));
            return 1;
        }
        double maxRunUs = threadCpuUs() - t0;   // start() runs in a task run of its own
        double total = maxRunUs;
        std::uint32_t runs = 1;
        for (std::uint32_t i = 0; i < 100000; ++i) {
            const double s0 = threadCpuUs();
            const bool ended = route.step(rse::deliberative::kSliceWork);
            const double us = threadCpuUs() - s0;
            maxRunUs = std::max(maxRunUs, us);
            total += us;
            ++runs;
            if (ended) {
                break;
            }
        }
        const bool found = route.state() == RouteState::kFound;
        allFound = allFound && found;
        worstRunUs = std::max(worstRunUs, maxRunUs);
        const double nsPerUnit = total * 1e3 / static_cast<double>(route.stats().work);
        nsPerUnitMax = std::max(nsPerUnitMax, nsPerUnit);
        std::printf("%7zu %8s %9.3f %11u %7u %9.1f %10.0f %11.1f %9.2f %8zu %12u %14.0f\n", map.rockCount(),
                    rse::deliberative::toString(route.state()), found ? route.lengthM() / straight : 0.0,
                    route.stats().expansions, runs, total / 1e3, maxRunUs,
                    static_cast<double>(route.stats().work) / 1e6, nsPerUnit, image.size(), service.commitRuns(), sliceUs);
    }
    std::printf("TARGET route found at every size (100 .. 20 000 rocks): %s %s\n", allFound ? "yes" : "no",
                targets.check(allFound) ? "PASS" : "FAIL");
    const bool inBudget = worstRunUs <= kDeliberativeBudgetUs;
    std::printf("TARGET no run over the deliberative budget at any size: worst %.0f us of %.0f %s\n", worstRunUs,
                kDeliberativeBudgetUs, targets.check(inBudget) ? "PASS" : "FAIL");
    std::printf("work units here: at most %.2f ns a unit (kWorkKUnitsPerMs assumes 0.45 - 0.9)\n", nsPerUnitMax);
    std::printf("MAP_COMMIT slices, longest at any size: CRC-32 %.0f us (%zu B a slice), check %.0f us (%zu records), "
                "load %.0f us (%zu units)\n",
                sliceUsByPhase[1], rse::site_map::kCommitCrcBytes, sliceUsByPhase[2], rse::site_map::kCommitCheckRecords,
                sliceUsByPhase[3], rse::site_map::kCommitStageUnits);
    const bool slicesFit = worstSliceUs <= kCommitSliceBudgetUs;
    std::printf("TARGET no MAP_COMMIT slice over its share of the command task's run at any size: worst %.0f us of %.0f %s\n",
                worstSliceUs, kCommitSliceBudgetUs, targets.check(slicesFit) ? "PASS" : "FAIL");
    return targets.finish();
}
