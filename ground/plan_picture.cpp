// rse-plan-picture: the same map planned at two risk bounds, drawn side by side
// in one SVG (issue 7; `make plan-picture` writes build/plan_picture.svg).
//
//   rse-plan-picture [-o FILE] [--start X,Y] [--goal X,Y] [--sigma0 S] [--risk A,B]
//
// The map, planner and geometry are the compiled-in default tables
// (tables/coarse_map.toml: the demo mission's known rocks; planner.toml;
// rover_geometry.toml), made into problems by buildMapProblem() exactly as the
// deliberative layer does, and planned by CcPlanner with its default
// parameters. Panels, ellipses and captions: ground/plan_svg.hpp. A summary
// line per plan goes to stdout.
//
// Defaults. Start and goal are the demo mission's (sim_stub/scenarios/
// demo_mission.toml: (0, 0) to (20, 0)); risk bounds 1e-2 and 1e-6 (the RSE
// paper's figures 7 and 8). The start's position 1-sigma is --sigma0
// (isotropic, Sigma_0 = sigma0^2 I), default 0.20 m: a rover that has driven a
// while on odometry since its last position fix. Why not the fix's 0.05 m:
// then the margins near the two rocks beside the line (~3.8 and ~5.7 sd of
// 0.12 - 0.17 m) both stay inside the 1.0 - 1.2 m by which the straight line
// clears the grown rocks, so both plans are (up to the 16-gon objective's
// ties) the same straight line, 0.4 m and 0.8 m from a rock, and the
// picture shows almost nothing. At 0.20 m the 1e-2 plan still runs nearly
// straight (~0.7 m from the triangle south of the line) while the 1e-6 plan
// must swing north between the rocks (~1.1 m from every grown rock, ~1 m
// longer), and the ellipses (k = 2.33 against 4.75) show why. Above about
// 0.25 m the demo goal itself, 1.9 m from the grown rock beside it, can no
// longer keep the 1e-6 margin (~5.7 sd of 0.34 m at step 20): no plan.
//
// Exit: 0 written (whatever the plans' status: a failed plan is drawn as
// such), 1 a problem could not be built or the file not written, 2 bad usage.
#include <cmath>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "ground/plan_svg.hpp"
#include "ground/text_format.hpp"

namespace {

using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcStatus;
using rse::deliberative::MapProblemReport;
using rse::deliberative::PlanRequest;

constexpr double kDemoStartX = 0.0;
constexpr double kDemoStartY = 0.0;
constexpr double kDemoGoalX = 20.0;
constexpr double kDemoGoalY = 0.0;
constexpr double kDefaultSigma0 = 0.20;
constexpr double kDefaultRiskA = 1e-2;
constexpr double kDefaultRiskB = 1e-6;

// Static storage, as the flight planner is kept (~450 KB).
CcPlanner planner;

int usage(const char* why) {
    std::fprintf(stderr,
                 "rse-plan-picture: %s\n"
                 "usage: rse-plan-picture [-o FILE] [--start X,Y] [--goal X,Y] [--sigma0 S] [--risk A,B]\n"
                 "  -o FILE      SVG to write (default plan_picture.svg)\n"
                 "  --start X,Y  start mean, m (default %g,%g: the demo mission's)\n"
                 "  --goal X,Y   goal, m (default %g,%g)\n"
                 "  --sigma0 S   start position 1-sigma, m, isotropic (default %g)\n"
                 "  --risk A,B   the two risk bounds Delta (default %g,%g)\n",
                 why, kDemoStartX, kDemoStartY, kDemoGoalX, kDemoGoalY, kDefaultSigma0, kDefaultRiskA,
                 kDefaultRiskB);
    return 2;
}

bool parsePair(const std::string& text, double* a, double* b) {
    const std::size_t comma = text.find(',');
    return comma != std::string::npos && rse::ground::parseDouble(text.substr(0, comma), a) &&
           rse::ground::parseDouble(text.substr(comma + 1), b) && std::isfinite(*a) && std::isfinite(*b);
}

}  // namespace

int main(int argc, char** argv) {
    std::string outPath = "plan_picture.svg";
    double startX = kDemoStartX, startY = kDemoStartY, goalX = kDemoGoalX, goalY = kDemoGoalY;
    double sigma0 = kDefaultSigma0;
    double risks[2] = {kDefaultRiskA, kDefaultRiskB};
    for (int i = 1; i < argc; ++i) {
        const std::string arg = argv[i];
        if (arg == "-h" || arg == "--help") {
            usage("the same map planned at two risk bounds, as one SVG");
            return 0;
        }
        if (i + 1 >= argc) {
            return usage(("missing value after " + arg).c_str());
        }
        const std::string value = argv[++i];
        if (arg == "-o") {
            outPath = value;
        } else if (arg == "--start") {
            if (!parsePair(value, &startX, &startY)) {
                return usage("--start wants X,Y");
            }
        } else if (arg == "--goal") {
            if (!parsePair(value, &goalX, &goalY)) {
                return usage("--goal wants X,Y");
            }
        } else if (arg == "--sigma0") {
            if (!rse::ground::parseDouble(value, &sigma0) || !std::isfinite(sigma0) || sigma0 < 0.0) {
                return usage("--sigma0 wants a number >= 0");
            }
        } else if (arg == "--risk") {
            if (!parsePair(value, &risks[0], &risks[1])) {
                return usage("--risk wants A,B");
            }
        } else {
            return usage(("unknown option " + arg).c_str());
        }
    }

    rse::core::VirtualClock clock;
    rse::core::EventLog events(clock);
    rse::tables::TableService tables(events);
    if (!rse::core::isOk(tables.init(rse::tables::kDefaultTableImages, rse::tables::kDefaultTableImageCount))) {
        std::fprintf(stderr, "rse-plan-picture: the default tables did not load\n");
        return 1;
    }

    rse::ground::PlanPicture picture;
    picture.map = tables.coarseMap();
    picture.footprintRadiusM = static_cast<double>(tables.roverGeometry().footprint_radius_m);
    char title[256];
    std::snprintf(title, sizeof title,
                  "Chance-constrained plans on the demo coarse map: (%g, %g) to (%g, %g), start 1-sigma %g m, "
                  "\u0394 = %g and %g",
                  startX, startY, goalX, goalY, sigma0, risks[0], risks[1]);
    picture.title = title;
    for (const double risk : risks) {
        PlanRequest request;
        request.startX = startX;
        request.startY = startY;
        request.startCov[0] = request.startCov[3] = sigma0 * sigma0;
        request.goalX = goalX;
        request.goalY = goalY;
        request.riskBound = risk;
        rse::ground::PlanPanel panel;
        MapProblemReport report;
        if (!rse::core::isOk(rse::deliberative::buildMapProblem(tables.coarseMap(), tables.planner(),
                                                                tables.roverGeometry(), request, &panel.problem,
                                                                &report))) {
            std::fprintf(stderr, "rse-plan-picture: Delta %g: no problem: %s\n", risk,
                         rse::deliberative::toString(report.error));
            return 1;
        }
        (void)planner.solve(panel.problem, CcPlannerParams{}, &panel.plan);
        const bool planned = panel.plan.status == CcStatus::kOptimal || panel.plan.status == CcStatus::kFeasible;
        std::printf("Delta %-8g status %-8s risk used %-10.3g length %6.2f m  least clearance %5.2f m  "
                    "k = PhiInv(1 - Delta) %.2f  obstacles %u (dropped %u)  nodes %u\n",
                    risk,
                    panel.plan.status == CcStatus::kOptimal    ? "optimal"
                    : panel.plan.status == CcStatus::kFeasible ? "feasible"
                    : panel.plan.status == CcStatus::kNoPlan   ? "no-plan"
                                                               : "bad",
                    planned ? panel.plan.riskUsed : std::nan(""), planned ? panel.plan.euclideanLengthM : std::nan(""),
                    planned ? rse::ground::pathClearance(panel.problem, panel.plan) : std::nan(""),
                    rse::ground::ellipseQuantile(risk), static_cast<unsigned>(report.obstaclesUsed),
                    static_cast<unsigned>(report.obstaclesDropped), planner.nodes());
        picture.panels.push_back(panel);
    }

    std::ofstream out(outPath, std::ios::binary);
    out << rse::ground::renderPlanSvg(picture);
    out.close();
    if (!out) {
        std::fprintf(stderr, "rse-plan-picture: cannot write %s\n", outPath.c_str());
        return 1;
    }
    std::printf("wrote %s\n", outPath.c_str());
    return 0;
}
