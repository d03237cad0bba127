#include "ground/mission_report.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <system_error>

#include "ground/plan_svg.hpp"

namespace rse::ground {

namespace {

using geometry::Point2;

std::string num(int decimals, double v) { return svgFixed(v, decimals); }

std::string sci(double v) { return svgScientific(v); }

// A Markdown table cell: no bar, no line break.
std::string cell(const std::string& text) {
    std::string out;
    for (const char c : text) {
        out += c == '|' ? '/' : (c == '\n' ? ' ' : c);
    }
    return out;
}

bool hasPath(const deliberative::CcPlan& plan) {
    return (plan.status == deliberative::CcStatus::kOptimal || plan.status == deliberative::CcStatus::kFeasible) &&
           plan.steps > 0;
}

}  // namespace

std::string renderMissionReport(const MissionRecord& r, const std::string& mapFileName) {
    std::string s;
    s += "# Mission report: " + r.scenario + "\n\n";
    s += "Goal (" + num(2, r.goalX) + ", " + num(2, r.goalY) + ") at risk bound " + sci(r.riskBound) +
         ", sent by the operator as an authenticated GOTO. Outcome: " + r.outcome + ".\n\n";
    s += "Map: [" + mapFileName + "](" + mapFileName + ") (the coarse map, the hidden rocks, every plan with its risk "
         "ellipses, the driven and estimated tracks, the ten points where they happened).\n\n";

    s += "## The ten points\n\n";
    s += "**" + r.verdict + "**\n\n";
    s += "Each point is read from the flight software's own output (its events and its plan status), never from the "
         "simulator; the times are simulated seconds since boot.\n\n";
    s += "| # | time (s) | layer | what happened |\n|---:|---:|---|---|\n";
    for (const MissionPoint& p : r.points) {
        s += "| " + std::to_string(p.number) + " | " + (p.seen ? num(2, p.timeS) : std::string("-")) + " | " +
             cell(p.seen ? p.layer : std::string("-")) + " | " + cell(p.seen ? p.what : std::string("NOT SEEN")) + " |\n";
    }

    s += "\n## Legs\n\n";
    s += "Bounds as the deliberative layer handed them down (event 905); driven figures are the habitual layer's own "
         "count when it reported the leg achieved (event 808).\n\n";
    s += "| leg | sent (s) | to | length bound (m) | energy bound (J) | power bound (W) | outcome | driven (m) | driven (J) |\n";
    s += "|---:|---:|---|---:|---:|---:|---|---:|---:|\n";
    double drivenJ = 0.0;
    for (const LegRecord& l : r.legs) {
        const bool achieved = l.outcome == "achieved";
        drivenJ += achieved ? l.drivenJ : 0.0;
        s += "| " + std::to_string(l.legId) + " | " + num(2, l.sentS) + " | (" + num(2, l.xM) + ", " +
             num(2, l.yM) + ") | " + num(2, l.lengthBoundM) + " | " + num(0, l.energyBoundJ) + " | " +
             (l.powerBoundW > 0.0 ? num(0, l.powerBoundW) : std::string("-")) + " | " +
             cell(l.outcome.empty() ? std::string("open at the end") : l.outcome) + " | " +
             (achieved ? num(1, l.drivenM) : std::string("-")) + " | " +
             (achieved ? num(0, l.drivenJ) : std::string("-")) + " |\n";
    }

    s += "\n## Fail-ups, relaxations, replans, call homes\n\n";
    s += "| time (s) | what | the flight software's words |\n|---:|---|---|\n";
    for (const MissionDecision& d : r.decisions) {
        s += "| " + num(2, d.timeS) + " | " + cell(d.kind) + " | " + cell(d.text) + " |\n";
    }

    s += "\n## Counters\n\n";
    s += "| legs sent | achieved | fail-ups | replans | bound relaxations | risk relaxations | call homes | habitual "
         "replans |\n|---:|---:|---:|---:|---:|---:|---:|---:|\n";
    s += "| " + std::to_string(r.legsSent) + " | " + std::to_string(r.legsAchieved) + " | " + std::to_string(r.failUps) +
         " | " + std::to_string(r.replans) + " | " + std::to_string(r.boundRelaxations) + " | " +
         std::to_string(r.riskRelaxations) + " | " + std::to_string(r.callHomes) + " | " +
         std::to_string(r.habitualReplans) + " |\n";

    s += "\n## Energy and truth\n\n";
    s += "- The habitual layer counted " + num(0, drivenJ) + " J (" + num(2, drivenJ / 3600.0) +
         " Wh) on the legs it achieved (its power model on the driven path).\n";
    if (r.energyWh >= 0.0) {
        s += "- The battery gave " + num(2, r.energyWh) + " Wh in all (the simulator's truth: drives and "
             "avionics, standing time included).\n";
    }
    if (r.drivenM >= 0.0) {
        s += "- Driven " + num(2, r.drivenM) + " m (truth); " + std::to_string(r.collisions) +
             " collisions; least clearance to any rock " + num(2, r.leastClearanceM) + " m.\n";
    }

    s += "\n## Plans\n\n";
    s += "| made at (s) | status | length (m) | risk used | risk bound | motion noise (m/step) | start |\n";
    s += "|---:|---|---:|---:|---:|---:|---|\n";
    for (const PlanDrawing& p : r.plans) {
        s += "| " + num(2, p.timeS) + " | " +
             (p.plan.status == deliberative::CcStatus::kOptimal ? "optimal" : "budget") + " | " +
             num(2, p.plan.euclideanLengthM) + " | " + sci(p.plan.riskUsed) + " | " +
             sci(p.problem.riskBound) + " | " + num(3, p.problem.processSigmaM) + " | (" +
             num(2, p.problem.startX) + ", " + num(2, p.problem.startY) + ") |\n";
    }

    s += "\n## Timing per task\n\n";
    s += "Judged on the executive's clock (budget, over budget); host figures are this machine's wall time per run.\n\n";
    s += "| task | runs | budget (us) | mean (us) | max (us) | host mean (us) | host max (us) | over budget |\n";
    s += "|---|---:|---:|---:|---:|---:|---:|---:|\n";
    for (const TaskTimingRow& t : r.timing) {
        s += "| " + cell(t.name) + " | " + std::to_string(t.runs) + " | " + num(0, t.budgetUs) + " | " +
             num(0, t.meanUs) + " | " + num(0, t.maxUs) + " | " + num(1, t.hostMeanUs) + " | " +
             num(1, t.hostMaxUs) + " | " + std::to_string(t.overBudget) + " |\n";
    }
    return s;
}

namespace {

// Where things go on the mission map: the site scaled to the picture's width,
// the legend and the list of points under it.
struct MissionMapLayout {
    static constexpr double kMargin = 30.0;
    static constexpr double kTitle = 50.0;
    static constexpr double kWidth = 1400.0;
    static constexpr double kLineHeight = 17.0;
    double scale = 1.0;
    double legendTop = 0.0;
    double listTop = 0.0;
    double height = 0.0;
    SvgFrame frame{};

    explicit MissionMapLayout(const tables::CoarseMapTable& map) {
        const double siteW = static_cast<double>(map.x_max_m) - static_cast<double>(map.x_min_m);
        const double siteH = static_cast<double>(map.y_max_m) - static_cast<double>(map.y_min_m);
        scale = siteW > 0.0 && std::isfinite(siteW) ? (kWidth - 2.0 * kMargin) / siteW : 1.0;
        const double mapH = (siteH > 0.0 && std::isfinite(siteH) ? siteH : 0.0) * scale;
        legendTop = kTitle + mapH + 30.0;
        listTop = legendTop + 3.0 * kLineHeight + 10.0;
        height = listTop + (kMissionPointCount + 2) * kLineHeight + kMargin;
        frame = SvgFrame{kMargin, kTitle, scale, static_cast<double>(map.x_min_m), static_cast<double>(map.y_max_m)};
    }
};

// The document's head: size, background, title and outcome lines.
void mapHeading(const MissionRecord& r, const MissionMapLayout& l, std::string* s) {
    const std::string w = svgNumber(MissionMapLayout::kWidth);
    const std::string h = svgNumber(l.height);
    *s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    *s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + w + "\" height=\"" + h + "\" viewBox=\"0 0 " + w +
          ' ' + h + "\" font-family=\"sans-serif\">\n";
    *s += "<rect x=\"0\" y=\"0\" width=\"" + w + "\" height=\"" + h + "\" fill=\"#fff\"/>\n";
    *s += "<text class=\"title\" x=\"" + svgNumber(MissionMapLayout::kMargin) +
          "\" y=\"20\" font-size=\"16\" font-weight=\"bold\">" +
          svgEscape("Mission " + r.scenario + ": goal (" + num(2, r.goalX) + ", " + num(2, r.goalY) +
                    "), risk bound " + sci(r.riskBound)) +
          "</text>\n";
    *s += "<text class=\"outcome\" x=\"" + svgNumber(MissionMapLayout::kMargin) + "\" y=\"38\" font-size=\"13\">" +
          svgEscape(r.outcome + " \u2014 " + r.verdict) + "</text>\n";
}

// What the rover did not know: the hidden rocks (truth) and the hazard discs it saw.
void mapHiddenRocksAndHazards(const MissionRecord& r, const MissionMapLayout& l, std::string* s) {
    const SvgFrame& f = l.frame;
    for (const std::vector<Point2>& rock : r.hiddenRocks) {
        if (rock.size() >= 3) {
            *s += "<polygon class=\"hidden-rock\" points=\"" + svgPoints(rock, f) +
                  "\" fill=\"#e67e22\" fill-opacity=\"0.55\" stroke=\"#a04000\" stroke-width=\"1.2\" "
                  "stroke-dasharray=\"3 2\"/>\n";
        }
    }
    for (const HazardSeen& hz : r.hazards) {
        *s += "<circle class=\"" + std::string(hz.hidden ? "hazard-hidden" : "hazard-known") + "\" cx=\"" +
              svgNumber(f.x(hz.xM)) + "\" cy=\"" + svgNumber(f.y(hz.yM)) + "\" r=\"" +
              svgNumber(hz.radiusM * l.scale) + "\" fill=\"none\" stroke=\"" + (hz.hidden ? "#d35400" : "#7f8c8d") +
              "\" stroke-width=\"1.2\" stroke-dasharray=\"2 2\"/>\n";
    }
}

// Site mode: the site map's rocks (as the coarse map's) and the global routes.
void mapSiteRocksAndRoutes(const MissionRecord& r, const SvgFrame& f, std::string* s) {
    for (const std::vector<Point2>& rock : r.siteRocks) {
        if (rock.size() >= 3) {
            *s += "<polygon class=\"site-rock\" points=\"" + svgPoints(rock, f) +
                  "\" fill=\"#8d6e63\" stroke=\"#5d4037\" stroke-width=\"1\"/>\n";
        }
    }
    for (const std::vector<Point2>& route : r.routes) {
        if (route.size() >= 2) {
            *s += "<polyline class=\"route\" points=\"" + svgPoints(route, f) +
                  "\" fill=\"none\" stroke=\"#8e44ad\" stroke-width=\"2\" stroke-dasharray=\"10 4\"/>\n";
        }
    }
}

// A track's finite points as a polyline (none for fewer than two).
void mapTrack(const std::vector<TrackPoint>& points, const char* cls, const char* style, const SvgFrame& f,
              std::string* s) {
    std::vector<Point2> line;
    for (const TrackPoint& p : points) {
        if (std::isfinite(p.xM) && std::isfinite(p.yM)) {
            line.push_back(Point2{p.xM, p.yM});
        }
    }
    if (line.size() >= 2) {
        *s += "<polyline class=\"" + std::string(cls) + "\" points=\"" + svgPoints(line, f) + "\" fill=\"none\" " +
              style + "/>\n";
    }
}

// The driven and estimated tracks, the start and the goal.
void mapTracks(const MissionRecord& r, const SvgFrame& f, std::string* s) {
    mapTrack(r.truthTrack, "track-truth", "stroke=\"#111\" stroke-width=\"2.2\"", f, s);
    mapTrack(r.estimatedTrack, "track-estimate", "stroke=\"#00a0a0\" stroke-width=\"1.4\" stroke-dasharray=\"6 3\"", f,
             s);
    if (!r.truthTrack.empty() || !r.estimatedTrack.empty()) {
        const TrackPoint& start = r.truthTrack.empty() ? r.estimatedTrack.front() : r.truthTrack.front();
        *s += "<circle class=\"start\" cx=\"" + svgNumber(f.x(start.xM)) + "\" cy=\"" + svgNumber(f.y(start.yM)) +
              "\" r=\"6\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"1.5\"/>\n";
    }
    *s += "<rect class=\"goal\" x=\"" + svgNumber(f.x(r.goalX) - 6.0) + "\" y=\"" + svgNumber(f.y(r.goalY) - 6.0) +
          "\" width=\"12\" height=\"12\" fill=\"#000\"/>\n";
}

// The points, numbered where they happened; markers at one place stack up.
void mapPointMarkers(const MissionRecord& r, const SvgFrame& f, std::string* s) {
    std::vector<Point2> placed;
    for (const MissionPoint& p : r.points) {
        if (!p.seen || !p.hasPlace || !std::isfinite(p.xM) || !std::isfinite(p.yM)) {
            continue;
        }
        const Point2 at{f.x(p.xM), f.y(p.yM)};
        const long crowd = std::count_if(placed.begin(), placed.end(),
                                         [&at](Point2 q) { return geometry::distance(at, q) < 24.0; });
        const double cy = at.y - 22.0 - 22.0 * static_cast<double>(crowd);
        placed.push_back(at);
        *s += "<g class=\"point\" id=\"point-" + std::to_string(p.number) + "\">\n";
        *s += "<line x1=\"" + svgNumber(at.x) + "\" y1=\"" + svgNumber(at.y) + "\" x2=\"" + svgNumber(at.x) +
              "\" y2=\"" + svgNumber(cy) + "\" stroke=\"#444\" stroke-width=\"0.8\"/>\n";
        *s += "<circle cx=\"" + svgNumber(at.x) + "\" cy=\"" + svgNumber(cy) +
              "\" r=\"9.5\" fill=\"#ffd54f\" stroke=\"#333\" stroke-width=\"1\"/>\n";
        *s += "<text x=\"" + svgNumber(at.x) + "\" y=\"" + svgNumber(cy + 4.0) +
              "\" font-size=\"11\" font-weight=\"bold\" text-anchor=\"middle\">" + std::to_string(p.number) +
              "</text>\n</g>\n";
    }
}

// The legend's swatches in one row, then a line naming each plan.
void mapLegend(const MissionRecord& r, const MissionMapLayout& l, std::string* s) {
    double lx = MissionMapLayout::kMargin;
    const double ly = l.legendTop;
    *s += "<g class=\"legend\" font-size=\"12\">\n";
    auto legend = [&](const std::string& swatch, const std::string& text, double width) {
        *s += swatch + "<text x=\"" + svgNumber(lx + 26.0) + "\" y=\"" + svgNumber(ly) + "\">" + svgEscape(text) +
              "</text>\n";
        lx += width;
    };
    legend("<rect x=\"" + svgNumber(lx) + "\" y=\"" + svgNumber(ly - 10.0) +
               "\" width=\"18\" height=\"12\" fill=\"#8d6e63\" stroke=\"#5d4037\"/>",
           r.siteRocks.empty() ? "rock on the coarse map" : "rock on the site map", 190.0);
    legend("<rect x=\"" + svgNumber(lx) + "\" y=\"" + svgNumber(ly - 10.0) +
               "\" width=\"18\" height=\"12\" fill=\"#e67e22\" fill-opacity=\"0.55\" stroke=\"#a04000\"/>",
           "hidden rock (truth)", 160.0);
    legend("<circle cx=\"" + svgNumber(lx + 9.0) + "\" cy=\"" + svgNumber(ly - 4.0) +
               "\" r=\"7\" fill=\"none\" stroke=\"#d35400\" stroke-dasharray=\"2 2\"/>",
           "hazard disc the habitual layer saw", 260.0);
    legend("<line x1=\"" + svgNumber(lx) + "\" y1=\"" + svgNumber(ly - 4.0) + "\" x2=\"" + svgNumber(lx + 18.0) +
               "\" y2=\"" + svgNumber(ly - 4.0) + "\" stroke=\"#111\" stroke-width=\"2.2\"/>",
           "driven track (truth)", 170.0);
    legend("<line x1=\"" + svgNumber(lx) + "\" y1=\"" + svgNumber(ly - 4.0) + "\" x2=\"" + svgNumber(lx + 18.0) +
               "\" y2=\"" + svgNumber(ly - 4.0) + "\" stroke=\"#00a0a0\" stroke-width=\"1.4\" stroke-dasharray=\"6 3\"/>",
           "estimated track", 150.0);
    legend("<ellipse cx=\"" + svgNumber(lx + 9.0) + "\" cy=\"" + svgNumber(ly - 4.0) +
               "\" rx=\"9\" ry=\"6\" fill=\"#1f5fbf\" fill-opacity=\"0.1\" stroke=\"#1f5fbf\"/>",
           r.routes.empty() ? "plan: mean path, risk ellipses k = \u03a6\u207b\u00b9(1 \u2212 \u0394)"
                            : "horizon plans, risk ellipses",
           r.routes.empty() ? 330.0 : 240.0);
    if (!r.routes.empty()) {
        legend("<line x1=\"" + svgNumber(lx) + "\" y1=\"" + svgNumber(ly - 4.0) + "\" x2=\"" + svgNumber(lx + 18.0) +
                   "\" y2=\"" + svgNumber(ly - 4.0) + "\" stroke=\"#8e44ad\" stroke-width=\"2\" stroke-dasharray=\"10 4\"/>",
               "global route (site map)", 180.0);
    }
    *s += "</g>\n";
    std::string plans;
    // A long traverse makes a plan a horizon: the first few are named, the rest counted.
    constexpr std::size_t kPlansNamed = 6;
    for (std::size_t i = 0; i < r.plans.size() && i < kPlansNamed; ++i) {
        plans += (i == 0 ? "" : "; ") + std::string("plan ") + std::to_string(i + 1) + " at " +
                 num(1, r.plans[i].timeS) + " s (" + planColour(i) + "): " +
                 (hasPath(r.plans[i].plan) ? num(2, r.plans[i].plan.euclideanLengthM) + " m" : std::string("no path")) +
                 ", \u03c3 " + num(3, r.plans[i].problem.processSigmaM) + " m/step";
    }
    if (r.plans.size() > kPlansNamed) {
        plans += "; " + std::to_string(r.plans.size() - kPlansNamed) + " more";
    }
    *s += "<text x=\"" + svgNumber(MissionMapLayout::kMargin) + "\" y=\"" +
          svgNumber(ly + MissionMapLayout::kLineHeight + 4.0) + "\" font-size=\"12\">" +
          svgEscape(plans.empty() ? std::string("no plan was made") : plans) + "</text>\n";
}

// The points listed under the legend, the verdict first.
void mapPointList(const MissionRecord& r, const MissionMapLayout& l, std::string* s) {
    *s += "<g class=\"point-list\" font-size=\"12\">\n";
    *s += "<text x=\"" + svgNumber(MissionMapLayout::kMargin) + "\" y=\"" + svgNumber(l.listTop) +
          "\" font-weight=\"bold\">" + svgEscape(r.verdict) + "</text>\n";
    double y = l.listTop + MissionMapLayout::kLineHeight;
    for (const MissionPoint& p : r.points) {
        std::string line = std::to_string(p.number) + "  ";
        line += p.seen ? num(2, p.timeS) + " s" + "  " + p.layer + ": " + p.what : std::string("not seen");
        if (line.size() > 230) {
            line = line.substr(0, 227) + "...";
        }
        *s += "<text x=\"" + svgNumber(MissionMapLayout::kMargin) + "\" y=\"" + svgNumber(y) + "\">" +
              svgEscape(line) + "</text>\n";
        y += MissionMapLayout::kLineHeight;
    }
    *s += "</g>\n";
}

}  // namespace

std::string renderMissionMap(const MissionRecord& r) {
    const MissionMapLayout layout(r.map);
    const SvgFrame& f = layout.frame;
    std::string s;
    mapHeading(r, layout, &s);
    drawSite(r.map, f, &s);
    drawRocks(r.map, f, &s);
    mapSiteRocksAndRoutes(r, f, &s);
    if (!r.plans.empty()) {
        drawGrownObstacles(r.plans.front().problem, f, &s);
    }
    mapHiddenRocksAndHazards(r, layout, &s);
    for (std::size_t i = 0; i < r.plans.size(); ++i) {
        drawPlan(r.plans[i].problem, r.plans[i].plan, planColour(i), f, &s);
    }
    mapTracks(r, f, &s);
    mapPointMarkers(r, f, &s);
    mapLegend(r, layout, &s);
    mapPointList(r, layout, &s);
    s += "</svg>\n";
    return s;
}

bool writeMissionFiles(const MissionRecord& r, const std::string& dir, std::string* reportPath, std::string* mapPath,
                       std::string* error) {
    std::error_code ec;
    std::filesystem::create_directories(dir, ec);
    if (ec) {
        *error = "cannot make " + dir + ": " + ec.message();
        return false;
    }
    const std::string report = dir + "/report.md";
    const std::string picture = dir + "/map.svg";
    const std::pair<std::string, std::string> files[] = {{report, renderMissionReport(r, "map.svg")},
                                                         {picture, renderMissionMap(r)}};
    for (const auto& [path, text] : files) {
        std::ofstream out(path, std::ios::binary | std::ios::trunc);
        out << text;
        out.close();
        if (!out) {
            *error = "cannot write " + path;
            return false;
        }
    }
    *reportPath = report;
    *mapPath = picture;
    return true;
}

}  // namespace rse::ground
