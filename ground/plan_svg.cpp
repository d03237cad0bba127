#include "ground/plan_svg.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdio>
#include <initializer_list>

#include "fsw/deliberative/gaussian.hpp"
#include "fsw/geometry/coarse_map.hpp"

namespace rse::ground {

using deliberative::CcPlan;
using deliberative::CcProblem;
using deliberative::CcStatus;
using deliberative::PlanObstacle;
using geometry::Point2;

std::vector<Point2> obstacleCorners(const PlanObstacle& obstacle) {
    constexpr double kTolerance = 1e-9;
    std::vector<Point2> corners;
    const std::size_t n = obstacle.faceCount;
    for (std::size_t j = 0; j < n; ++j) {
        for (std::size_t k = j + 1; k < n; ++k) {
            // a_j . x = b_j and a_k . x = b_k (Cramer's rule).
            const double det = obstacle.normalX[j] * obstacle.normalY[k] - obstacle.normalY[j] * obstacle.normalX[k];
            if (std::fabs(det) < 1e-12) {
                continue;  // parallel faces never meet
            }
            const Point2 c{(obstacle.offset[j] * obstacle.normalY[k] - obstacle.normalY[j] * obstacle.offset[k]) / det,
                           (obstacle.normalX[j] * obstacle.offset[k] - obstacle.offset[j] * obstacle.normalX[k]) / det};
            bool onPolygon = true;
            for (std::size_t f = 0; f < n && onPolygon; ++f) {
                onPolygon = obstacle.normalX[f] * c.x + obstacle.normalY[f] * c.y <= obstacle.offset[f] + kTolerance;
            }
            const bool seen = std::any_of(corners.begin(), corners.end(), [&c](Point2 q) {
                return geometry::distanceSquared(c, q) < kTolerance * kTolerance;
            });
            if (onPolygon && !seen) {
                corners.push_back(c);
            }
        }
    }
    if (corners.size() < 3) {
        return {};
    }
    Point2 centre{0.0, 0.0};
    for (const Point2& c : corners) {
        centre = centre + c;
    }
    centre = (1.0 / static_cast<double>(corners.size())) * centre;
    std::sort(corners.begin(), corners.end(), [&centre](Point2 a, Point2 b) {
        return std::atan2(a.y - centre.y, a.x - centre.x) < std::atan2(b.y - centre.y, b.x - centre.x);
    });
    return corners;
}

double segmentPolygonDistance(Point2 p, Point2 q, const std::vector<Point2>& corners) {
    const std::size_t n = corners.size();
    if (n == 0) {
        return INFINITY;
    }
    if (geometry::pointInConvexPolygon(p, corners.data(), n)) {
        return 0.0;
    }
    double best = INFINITY;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = geometry::segmentSegmentDistanceSquared(p, q, corners[i], corners[(i + 1) % n]);
        best = std::min(best, d);
    }
    return std::sqrt(best);
}

double pathClearance(const CcProblem& problem, const CcPlan& plan) {
    double least = INFINITY;
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        const std::vector<Point2> corners = obstacleCorners(problem.obstacles[i]);
        for (std::size_t t = 0; t < plan.steps; ++t) {
            const double d = segmentPolygonDistance(Point2{plan.meanX[t], plan.meanY[t]},
                                                    Point2{plan.meanX[t + 1], plan.meanY[t + 1]}, corners);
            least = std::min(least, d);
        }
    }
    return least;
}

double ellipseQuantile(double riskBound) { return deliberative::upperQuantile(riskBound); }

namespace {

const char* statusName(CcStatus status) {
    switch (status) {
        case CcStatus::kOptimal: return "optimal";
        case CcStatus::kFeasible: return "feasible (budget ran out)";
        case CcStatus::kNoPlan: return "no plan";
        case CcStatus::kBadProblem: return "bad problem";
    }
    return "?";
}

bool hasPath(const CcPlan& plan) {
    return (plan.status == CcStatus::kOptimal || plan.status == CcStatus::kFeasible) && plan.steps > 0;
}

bool allFinite(std::initializer_list<double> values) {
    return std::all_of(values.begin(), values.end(), [](double v) { return std::isfinite(v); });
}

std::string px(double v) { return svgNumber(v); }

std::string fixed(double v, int decimals) { return svgFixed(v, decimals); }

std::string scientific(double v) { return svgScientific(v); }

std::string escapeXml(const std::string& text) { return svgEscape(text); }

using Frame = SvgFrame;

std::string pointsAttribute(const std::vector<Point2>& points, const Frame& f) {
    std::string out;
    for (const Point2& p : points) {
        if (!out.empty()) {
            out += ' ';
        }
        out += px(f.x(p.x)) + ',' + px(f.y(p.y));
    }
    return out;
}

bool finitePoints(const std::vector<Point2>& points) {
    return std::all_of(points.begin(), points.end(), [](Point2 p) { return geometry::isFinite(p); });
}

std::vector<Point2> mapPolygon(const tables::CoarseMapTable& map, std::size_t slot) {
    std::vector<Point2> points;
    const std::size_t n = geometry::coarseMapVerticesUsed(map, slot);
    for (std::size_t v = 0; v < n; ++v) {
        points.push_back(geometry::coarseMapVertex(map, slot, v));
    }
    return points;
}

const char* panelColour(std::size_t panel) { return planColour(panel); }

// The ellipse of Sigma_t = Sigma_0 + t sigma^2 I scaled by k, centred on the mean.
std::string ellipseElement(const CcProblem& problem, const CcPlan& plan, std::size_t t, double k, const Frame& f) {
    const double var = static_cast<double>(t) * problem.processSigmaM * problem.processSigmaM;
    const double a = problem.startCov[0] + var;
    const double b = 0.5 * (problem.startCov[1] + problem.startCov[2]);
    const double d = problem.startCov[3] + var;
    const double mid = 0.5 * (a + d);
    const double radius = std::sqrt(0.25 * (a - d) * (a - d) + b * b);
    const double major = std::sqrt(std::max(0.0, mid + radius));
    const double minor = std::sqrt(std::max(0.0, mid - radius));
    const double angleDeg = 0.5 * std::atan2(2.0 * b, a - d) * 180.0 / M_PI;  // of the major axis, y up
    const double cx = f.x(plan.meanX[t]);
    const double cy = f.y(plan.meanY[t]);
    const double rx = k * major * f.scale;
    const double ry = k * minor * f.scale;
    if (!allFinite({cx, cy, rx, ry, angleDeg})) {
        return "";
    }
    std::string e = "<ellipse class=\"ellipse\" cx=\"" + px(cx) + "\" cy=\"" + px(cy) + "\" rx=\"" + px(rx) +
                    "\" ry=\"" + px(ry) + "\"";
    if (std::fabs(angleDeg) > 1e-9) {
        // SVG's rotation is clockwise on screen: the y flip turns the angle round.
        e += " transform=\"rotate(" + px(-angleDeg) + ' ' + px(cx) + ' ' + px(cy) + ")\"";
    }
    return e + "/>\n";
}

double sigma0(const CcProblem& problem) {
    const double a = problem.startCov[0];
    const double d = problem.startCov[3];
    const double b = 0.5 * (problem.startCov[1] + problem.startCov[2]);
    return std::sqrt(std::max(0.0, 0.5 * (a + d) + std::sqrt(0.25 * (a - d) * (a - d) + b * b)));
}

constexpr double kMargin = 20.0;
constexpr double kTitleHeight = 36.0;
constexpr double kCaptionHeight = 96.0;
constexpr double kLegendHeight = 64.0;
constexpr double kPanelWidth = 760.0;
constexpr double kPanelGap = 30.0;

void writePanel(const PlanPicture& picture, std::size_t index, double left, double top, double scale,
                std::string* svg) {
    const PlanPanel& panel = picture.panels[index];
    const CcProblem& problem = panel.problem;
    const CcPlan& plan = panel.plan;
    const tables::CoarseMapTable& map = picture.map;
    const Frame f{left, top, scale, static_cast<double>(map.x_min_m), static_cast<double>(map.y_max_m)};
    const double k = ellipseQuantile(problem.riskBound);
    const char* colour = panelColour(index);
    std::string& s = *svg;
    s += "<g class=\"panel\" id=\"panel-" + std::to_string(index) + "\">\n";
    // Site, and the region the means must stay in (the site shrunk by the footprint).
    drawSite(map, f, &s);
    const double siteH = (static_cast<double>(map.y_max_m) - static_cast<double>(map.y_min_m)) * scale;
    if (allFinite({problem.xMin, problem.xMax, problem.yMin, problem.yMax}) && problem.xMax > problem.xMin &&
        problem.yMax > problem.yMin) {
        s += "<rect class=\"means-region\" x=\"" + px(f.x(problem.xMin)) + "\" y=\"" + px(f.y(problem.yMax)) +
             "\" width=\"" + px((problem.xMax - problem.xMin) * scale) + "\" height=\"" +
             px((problem.yMax - problem.yMin) * scale) +
             "\" fill=\"none\" stroke=\"#aaa\" stroke-width=\"0.8\" stroke-dasharray=\"2 3\"/>\n";
    }
    drawRocks(map, f, &s);
    drawGrownObstacles(problem, f, &s);
    // Ellipses, the mean path and its waypoints.
    const bool drawn = hasPath(plan);
    drawPlan(problem, plan, colour, f, &s);
    // Start and goal.
    if (allFinite({problem.startX, problem.startY, problem.goalX, problem.goalY})) {
        s += "<circle class=\"start\" cx=\"" + px(f.x(problem.startX)) + "\" cy=\"" + px(f.y(problem.startY)) +
             "\" r=\"5\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"1.5\"/>\n";
        const double gx = f.x(problem.goalX);
        const double gy = f.y(problem.goalY);
        s += "<rect class=\"goal\" x=\"" + px(gx - 5.0) + "\" y=\"" + px(gy - 5.0) +
             "\" width=\"10\" height=\"10\" fill=\"#000\"/>\n";
    }
    // Caption.
    const double clearance = drawn ? pathClearance(problem, plan) : std::nan("");
    const double captionTop = top + siteH + 30.0;
    const std::string lines[] = {
        "\u0394 = " + scientific(problem.riskBound) + ": " + statusName(plan.status),
        drawn ? "risk used " + scientific(plan.riskUsed) + " \u00b7 path " + fixed(plan.euclideanLengthM, 2) +
                    " m \u00b7 least clearance " + fixed(clearance, 2) + " m"
              : std::string("no path to draw"),
        "ellipses: mean \u00b1 " + fixed(k, 2) + " \u03c3 (k = \u03a6\u207b\u00b9(1 \u2212 \u0394)), N = " +
            std::to_string(problem.steps) + " steps",
        "\u03c3\u2080 = " + fixed(sigma0(problem), 2) + " m, \u03c3 = " + fixed(problem.processSigmaM, 3) +
            " m per step, " + std::to_string(problem.obstacleCount) + " obstacles",
    };
    double y = captionTop;
    bool first = true;
    for (const std::string& line : lines) {
        const std::string style =
            first ? " font-size=\"15\" font-weight=\"bold\" fill=\"" + std::string(colour) + "\"" : " font-size=\"12\"";
        s += "<text class=\"caption\" x=\"" + px(left) + "\" y=\"" + px(y) + "\"" + style + ">" + escapeXml(line) +
             "</text>\n";
        y += first ? 20.0 : 16.0;
        first = false;
    }
    s += "</g>\n";
}

}  // namespace

std::string svgFixed(double v, int decimals) {
    if (!std::isfinite(v)) {
        return v > 0.0 ? "inf" : "n/a";
    }
    char text[48];
    std::snprintf(text, sizeof text, "%.*f", decimals, v);
    return text;
}

std::string svgScientific(double v) {
    if (!std::isfinite(v)) {
        return "n/a";
    }
    char text[48];
    std::snprintf(text, sizeof text, "%.3g", v);
    return text;
}

std::string svgNumber(double v) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f", v);
    return text;
}

std::string svgEscape(const std::string& text) {
    std::string out;
    for (const char c : text) {
        switch (c) {
            case '&': out += "&amp;"; break;
            case '<': out += "&lt;"; break;
            case '>': out += "&gt;"; break;
            case '"': out += "&quot;"; break;
            default: out += c;
        }
    }
    return out;
}

const char* planColour(std::size_t index) {
    static const char* const kColours[] = {"#1f5fbf", "#c0392b", "#1e8449", "#7d3c98"};
    return kColours[index % (sizeof kColours / sizeof kColours[0])];
}

std::string svgPoints(const std::vector<Point2>& points, const SvgFrame& f) { return pointsAttribute(points, f); }

void drawSite(const tables::CoarseMapTable& map, const SvgFrame& f, std::string* svg) {
    std::string& s = *svg;
    const double left = f.originX;
    const double top = f.originY;
    const double siteW = (static_cast<double>(map.x_max_m) - static_cast<double>(map.x_min_m)) * f.scale;
    const double siteH = (static_cast<double>(map.y_max_m) - static_cast<double>(map.y_min_m)) * f.scale;
    s += "<rect class=\"site\" x=\"" + px(left) + "\" y=\"" + px(top) + "\" width=\"" + px(siteW) + "\" height=\"" +
         px(siteH) + "\" fill=\"#fbf8f1\" stroke=\"#555\" stroke-width=\"1\"/>\n";
    // Axis labels along the west and south edges: every 5 m, or on a large
    // site (a site map's kilometre) every 10, 25, 50 ... m, 30 px apart at least.
    double step = 5.0;
    for (const double wider : {10.0, 25.0, 50.0, 100.0, 250.0, 500.0}) {
        step = step * f.scale < 30.0 ? wider : step;
    }
    for (double x = std::ceil(static_cast<double>(map.x_min_m) / step) * step; x <= static_cast<double>(map.x_max_m);
         x += step) {
        s += "<text class=\"tick\" x=\"" + px(f.x(x)) + "\" y=\"" + px(top + siteH + 12.0) +
             "\" font-size=\"9\" text-anchor=\"middle\" fill=\"#777\">" + fixed(x, 0) + "</text>\n";
    }
    for (double y = std::ceil(static_cast<double>(map.y_min_m) / step) * step; y <= static_cast<double>(map.y_max_m);
         y += step) {
        s += "<text class=\"tick\" x=\"" + px(left - 3.0) + "\" y=\"" + px(f.y(y) + 3.0) +
             "\" font-size=\"9\" text-anchor=\"end\" fill=\"#777\">" + fixed(y, 0) + "</text>\n";
    }
}

void drawRocks(const tables::CoarseMapTable& map, const SvgFrame& f, std::string* svg) {
    const std::size_t slots = geometry::coarseMapSlotsUsed(map);
    for (std::size_t slot = 0; slot < slots; ++slot) {
        const std::vector<Point2> rock = mapPolygon(map, slot);
        if (rock.size() >= 3 && finitePoints(rock)) {
            *svg += "<polygon class=\"rock\" points=\"" + pointsAttribute(rock, f) +
                    "\" fill=\"#8d6e63\" fill-opacity=\"0.85\" stroke=\"#5d4037\" stroke-width=\"1\"/>\n";
        }
    }
}

void drawGrownObstacles(const CcProblem& problem, const SvgFrame& f, std::string* svg) {
    for (std::size_t i = 0; i < problem.obstacleCount; ++i) {
        const std::vector<Point2> grown = obstacleCorners(problem.obstacles[i]);
        if (!grown.empty() && finitePoints(grown)) {
            *svg += "<polygon class=\"grown\" points=\"" + pointsAttribute(grown, f) +
                    "\" fill=\"none\" stroke=\"#5d4037\" stroke-width=\"1\" stroke-dasharray=\"5 3\"/>\n";
        }
    }
}

void drawPlan(const CcProblem& problem, const CcPlan& plan, const char* colour, const SvgFrame& f, std::string* svg) {
    if (!hasPath(plan)) {
        return;
    }
    std::string& s = *svg;
    const double k = ellipseQuantile(problem.riskBound);
    s += "<g fill=\"" + std::string(colour) + "\" fill-opacity=\"0.10\" stroke=\"" + colour +
         "\" stroke-opacity=\"0.6\" stroke-width=\"0.8\">\n";
    for (std::size_t t = 0; t <= plan.steps; ++t) {
        s += ellipseElement(problem, plan, t, k, f);
    }
    s += "</g>\n";
    std::vector<Point2> means;
    for (std::size_t t = 0; t <= plan.steps; ++t) {
        means.push_back(Point2{plan.meanX[t], plan.meanY[t]});
    }
    if (finitePoints(means)) {
        s += "<polyline class=\"mean-path\" points=\"" + pointsAttribute(means, f) + "\" fill=\"none\" stroke=\"" +
             colour + "\" stroke-width=\"2\"/>\n";
        s += "<g fill=\"" + std::string(colour) + "\">\n";
        for (const Point2& m : means) {
            s += "<circle class=\"waypoint\" cx=\"" + px(f.x(m.x)) + "\" cy=\"" + px(f.y(m.y)) + "\" r=\"2.5\"/>\n";
        }
        s += "</g>\n";
    }
}

std::string renderPlanSvg(const PlanPicture& picture) {
    const tables::CoarseMapTable& map = picture.map;
    const double siteW = static_cast<double>(map.x_max_m) - static_cast<double>(map.x_min_m);
    const double siteH = static_cast<double>(map.y_max_m) - static_cast<double>(map.y_min_m);
    const double scale = siteW > 0.0 && std::isfinite(siteW) ? kPanelWidth / siteW : 1.0;
    const double panelH = (siteH > 0.0 && std::isfinite(siteH) ? siteH : 0.0) * scale;
    const std::size_t count = std::max<std::size_t>(picture.panels.size(), 1);
    const double width = 2.0 * kMargin + static_cast<double>(count) * kPanelWidth +
                         static_cast<double>(count - 1) * kPanelGap;
    const double height = kTitleHeight + panelH + kCaptionHeight + kLegendHeight + kMargin;
    std::string s;
    s += "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n";
    s += "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"" + px(width) + "\" height=\"" + px(height) +
         "\" viewBox=\"0 0 " + px(width) + ' ' + px(height) + "\" font-family=\"sans-serif\">\n";
    s += "<rect x=\"0\" y=\"0\" width=\"" + px(width) + "\" height=\"" + px(height) + "\" fill=\"#fff\"/>\n";
    s += "<text class=\"title\" x=\"" + px(kMargin) + "\" y=\"24\" font-size=\"17\" font-weight=\"bold\">" +
         escapeXml(picture.title) + "</text>\n";
    for (std::size_t i = 0; i < picture.panels.size(); ++i) {
        writePanel(picture, i, kMargin + static_cast<double>(i) * (kPanelWidth + kPanelGap), kTitleHeight, scale,
                   &s);
    }
    // Legend.
    const double ly = kTitleHeight + panelH + kCaptionHeight + 22.0;
    double lx = kMargin;
    s += "<g class=\"legend\" font-size=\"12\">\n";
    s += "<rect x=\"" + px(lx) + "\" y=\"" + px(ly - 10.0) +
         "\" width=\"18\" height=\"12\" fill=\"#8d6e63\" stroke=\"#5d4037\"/>\n";
    s += "<text x=\"" + px(lx + 24.0) + "\" y=\"" + px(ly) + "\">rock (coarse map)</text>\n";
    lx += 150.0;
    s += "<rect x=\"" + px(lx) + "\" y=\"" + px(ly - 10.0) +
         "\" width=\"18\" height=\"12\" fill=\"none\" stroke=\"#5d4037\" stroke-dasharray=\"5 3\"/>\n";
    s += "<text x=\"" + px(lx + 24.0) + "\" y=\"" + px(ly) + "\">" +
         escapeXml("grown by the footprint radius " + fixed(picture.footprintRadiusM, 2) +
                   " m (the planner's obstacle)") +
         "</text>\n";
    lx += 420.0;
    s += "<line x1=\"" + px(lx) + "\" y1=\"" + px(ly - 4.0) + "\" x2=\"" + px(lx + 18.0) + "\" y2=\"" + px(ly - 4.0) +
         "\" stroke=\"#333\" stroke-width=\"2\"/>\n";
    s += "<circle cx=\"" + px(lx + 9.0) + "\" cy=\"" + px(ly - 4.0) + "\" r=\"2.5\" fill=\"#333\"/>\n";
    s += "<text x=\"" + px(lx + 24.0) + "\" y=\"" + px(ly) + "\">mean path, a dot per step</text>\n";
    lx += 200.0;
    s += "<ellipse cx=\"" + px(lx + 9.0) + "\" cy=\"" + px(ly - 4.0) +
         "\" rx=\"9\" ry=\"6\" fill=\"#333\" fill-opacity=\"0.1\" stroke=\"#333\"/>\n";
    s += "<text x=\"" + px(lx + 24.0) + "\" y=\"" + px(ly) + "\">" +
         escapeXml("{x : (x \u2212 \u03bc\u209c)\u1d40 \u03a3\u209c\u207b\u00b9 (x \u2212 \u03bc\u209c) = k\u00b2}, "
                   "\u03a3\u209c = \u03a3\u2080 + t \u03c3\u00b2 I, k = \u03a6\u207b\u00b9(1 \u2212 \u0394)") +
         "</text>\n";
    const double ly2 = ly + 20.0;
    s += "<circle cx=\"" + px(kMargin + 9.0) + "\" cy=\"" + px(ly2 - 4.0) +
         "\" r=\"5\" fill=\"#fff\" stroke=\"#000\" stroke-width=\"1.5\"/>\n";
    s += "<text x=\"" + px(kMargin + 24.0) + "\" y=\"" + px(ly2) + "\">start</text>\n";
    s += "<rect x=\"" + px(kMargin + 84.0) + "\" y=\"" + px(ly2 - 9.0) +
         "\" width=\"10\" height=\"10\" fill=\"#000\"/>\n";
    s += "<text x=\"" + px(kMargin + 100.0) + "\" y=\"" + px(ly2) + "\">goal</text>\n";
    s += "<text x=\"" + px(kMargin + 150.0) + "\" y=\"" + px(ly2) + "\">" +
         escapeXml("every end's risk is at most \u0394, so its margin is at least k\u00b7sd: the ellipses stay "
                   "off the grown obstacles; least clearance = least distance from a mean-path segment to a "
                   "grown obstacle; dotted: where the means must stay") +
         "</text>\n";
    s += "</g>\n";
    s += "</svg>\n";
    return s;
}

}  // namespace rse::ground
