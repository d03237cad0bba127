// The plan picture (ground/plan_svg.hpp): the geometry it measures with
// (corners from faces, segment-to-polygon distance, a plan's least
// clearance) against hand values, and the SVG it writes for two small plans:
// well-formed XML, one panel per plan, one mean path per panel, steps + 1
// ellipses and waypoints per panel, every number finite, ellipses of the
// covariance scaled by PhiInv(1 - Delta), the y axis flipped.
#include <cmath>
#include <cstddef>
#include <cstdlib>
#include <regex>
#include <string>
#include <vector>

#include "fsw/deliberative/cc_planner.hpp"
#include "fsw/deliberative/gaussian.hpp"
#include "fsw/deliberative/map_problem.hpp"
#include "ground/plan_svg.hpp"

#include "CppUTest/TestHarness.h"

using rse::deliberative::CcPlan;
using rse::deliberative::CcPlanner;
using rse::deliberative::CcPlannerParams;
using rse::deliberative::CcProblem;
using rse::deliberative::CcStatus;
using rse::deliberative::PlanObstacle;
using rse::ground::obstacleCorners;
using rse::ground::pathClearance;
using rse::ground::PlanPicture;
using rse::ground::segmentPolygonDistance;
using rse::geometry::Point2;

namespace {

CcPlanner planner;  // ~440 KB: static storage

// [xmin, xmax] x [ymin, ymax], faces right, top, left, bottom.
PlanObstacle box(double xmin, double xmax, double ymin, double ymax) {
    PlanObstacle o;
    o.faceCount = 4;
    const double n[4][3] = {{1, 0, xmax}, {0, 1, ymax}, {-1, 0, -xmin}, {0, -1, -ymin}};
    for (std::size_t j = 0; j < 4; ++j) {
        o.normalX[j] = n[j][0];
        o.normalY[j] = n[j][1];
        o.offset[j] = n[j][2];
    }
    return o;
}

std::size_t countOf(const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) {
        ++n;
    }
    return n;
}

// Tags balance (a stack of names), attributes are name="value", text holds
// no raw '<' or a '&' that starts no entity. "" when well-formed, else why.
std::string wellFormed(const std::string& xml) {
    if (xml.rfind("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n", 0) != 0) {
        return "no XML declaration";
    }
    std::vector<std::string> open;
    const std::regex attribute(R"re(\s+[A-Za-z_:][-A-Za-z0-9_:.]*="[^"<&]*")re");
    const std::regex name(R"re([A-Za-z_][-A-Za-z0-9_:.]*)re");
    std::size_t at = xml.find('>') + 1;
    bool rootSeen = false;
    while (at < xml.size()) {
        const std::size_t lt = xml.find('<', at);
        const std::string text = xml.substr(at, lt == std::string::npos ? std::string::npos : lt - at);
        for (std::size_t amp = text.find('&'); amp != std::string::npos; amp = text.find('&', amp + 1)) {
            const std::string rest = text.substr(amp);
            if (rest.rfind("&amp;", 0) != 0 && rest.rfind("&lt;", 0) != 0 && rest.rfind("&gt;", 0) != 0 &&
                rest.rfind("&quot;", 0) != 0) {
                return "bare & in text";
            }
        }
        if (lt == std::string::npos) {
            break;
        }
        if (open.empty() && rootSeen) {
            return "content after the root element";
        }
        const std::size_t gt = xml.find('>', lt);
        if (gt == std::string::npos) {
            return "unterminated tag";
        }
        std::string tag = xml.substr(lt + 1, gt - lt - 1);
        if (tag.find('<') != std::string::npos) {
            return "'<' inside a tag";
        }
        if (!tag.empty() && tag[0] == '/') {
            if (open.empty() || open.back() != tag.substr(1)) {
                return "mismatched </" + tag.substr(1) + ">";
            }
            open.pop_back();
        } else {
            const bool selfClosing = !tag.empty() && tag.back() == '/';
            if (selfClosing) {
                tag.pop_back();
            }
            std::smatch m;
            if (!std::regex_search(tag, m, name) || m.position(0) != 0) {
                return "bad tag name in <" + tag + ">";
            }
            const std::string tagName = m.str(0);
            const std::string attributes = std::regex_replace(tag.substr(tagName.size()), attribute, "");
            if (attributes.find_first_not_of(" \n\t") != std::string::npos) {
                return "bad attributes in <" + tag + ">";
            }
            if (open.empty() && tagName != "svg") {
                return "root is not svg";
            }
            rootSeen = true;
            if (!selfClosing) {
                open.push_back(tagName);
            }
        }
        at = gt + 1;
    }
    return open.empty() && rootSeen ? "" : "unclosed elements";
}

// Every attribute value that starts like a number is entirely finite numbers.
bool numbersFinite(const std::string& xml) {
    const std::regex value(R"re(="([-0-9.][^"]*)")re");
    for (auto it = std::sregex_iterator(xml.begin(), xml.end(), value); it != std::sregex_iterator(); ++it) {
        const std::string v = (*it)[1].str();
        const std::regex number(R"re(-?[0-9]+(\.[0-9]+)?)re");
        for (auto n = std::sregex_iterator(v.begin(), v.end(), number); n != std::sregex_iterator(); ++n) {
            if (!std::isfinite(std::strtod(n->str().c_str(), nullptr))) {
                return false;
            }
        }
    }
    return xml.find("nan") == std::string::npos && xml.find("inf\"") == std::string::npos;
}

double attributeOf(const std::string& element, const std::string& name) {
    const std::size_t at = element.find(" " + name + "=\"");
    return at == std::string::npos ? NAN : std::strtod(element.c_str() + at + name.size() + 3, nullptr);
}

// The panels' texts, in order.
std::vector<std::string> panels(const std::string& svg) {
    std::vector<std::string> out;
    const std::string start = "<g class=\"panel\"";
    for (std::size_t at = svg.find(start); at != std::string::npos;) {
        const std::size_t next = svg.find(start, at + 1);
        const std::size_t end = next == std::string::npos ? svg.find("<g class=\"legend\"") : next;
        out.push_back(svg.substr(at, end - at));
        at = next;
    }
    return out;
}

// A 12 x 8 site with one 2 m rock in the middle between start and goal.
PlanPicture smallPicture(CcStatus* statusA, CcStatus* statusB) {
    PlanPicture picture;
    picture.map.x_min_m = 0.0F;
    picture.map.x_max_m = 12.0F;
    picture.map.y_min_m = -4.0F;
    picture.map.y_max_m = 4.0F;
    picture.map.obstacle_count = 1;
    picture.map.vertex_count[0] = 4;
    const float vx[4] = {5, 7, 7, 5};
    const float vy[4] = {-1, -1, 1, 1};
    for (std::size_t v = 0; v < 4; ++v) {
        picture.map.vertex_x_m[v] = vx[v];
        picture.map.vertex_y_m[v] = vy[v];
    }
    picture.footprintRadiusM = 0.5;
    picture.title = "test <&> title";
    rse::tables::PlannerTable table{};
    table.horizon_steps = 8;
    table.process_noise_sigma_m = 0.0625F;
    table.risk_allocation = 1;
    rse::tables::RoverGeometryTable geometry{};
    geometry.footprint_radius_m = 0.5F;
    CcStatus* statuses[2] = {statusA, statusB};
    const double risks[2] = {1e-2, 1e-6};
    for (std::size_t k = 0; k < 2; ++k) {
        rse::deliberative::PlanRequest r;
        r.startX = 1.0;
        r.startY = 0.25;
        r.goalX = 11.0;
        r.goalY = 0.0;
        r.startCov[0] = 0.04;
        r.startCov[1] = r.startCov[2] = 0.01;  // a tilted ellipse
        r.startCov[3] = 0.02;
        r.riskBound = risks[k];
        rse::ground::PlanPanel panel;
        rse::deliberative::MapProblemReport report;
        CHECK(rse::deliberative::buildMapProblem(picture.map, table, geometry, r, &panel.problem, &report) ==
              rse::core::Status::kOk);
        *statuses[k] = planner.solve(panel.problem, CcPlannerParams{}, &panel.plan);
        picture.panels.push_back(panel);
    }
    return picture;
}

}  // namespace

TEST_GROUP(PlanSvg){};

TEST(PlanSvg, CornersOfABoxCounterClockwise) {
    const std::vector<Point2> c = obstacleCorners(box(1.0, 3.0, -2.0, 0.5));
    CHECK_EQUAL(4U, c.size());
    double twiceArea = 0.0;
    for (std::size_t i = 0; i < c.size(); ++i) {
        twiceArea += rse::geometry::cross(c[i], c[(i + 1) % c.size()]);
    }
    DOUBLES_EQUAL(2.0 * 2.0 * 2.5, twiceArea, 1e-12);  // positive: counter-clockwise
    for (const Point2& p : c) {
        CHECK(p.x == 1.0 || p.x == 3.0);
        CHECK(p.y == -2.0 || p.y == 0.5);
    }
    // A redundant face (x <= 10) adds no corner; faces that bound nothing give none.
    PlanObstacle o = box(1.0, 3.0, -2.0, 0.5);
    o.faceCount = 5;
    o.normalX[4] = 1.0;
    o.offset[4] = 10.0;
    CHECK_EQUAL(4U, obstacleCorners(o).size());
    o.faceCount = 2;
    CHECK_EQUAL(0U, obstacleCorners(o).size());
}

TEST(PlanSvg, SegmentPolygonDistanceHandValues) {
    const std::vector<Point2> square = obstacleCorners(box(0.0, 1.0, 0.0, 1.0));
    DOUBLES_EQUAL(1.0, segmentPolygonDistance({2.0, -1.0}, {2.0, 3.0}, square), 1e-12);       // beside a face
    DOUBLES_EQUAL(std::sqrt(2.0), segmentPolygonDistance({2.0, 2.0}, {4.0, 2.0}, square), 1e-12);  // a corner
    DOUBLES_EQUAL(0.0, segmentPolygonDistance({-1.0, 0.5}, {2.0, 0.5}, square), 0.0);          // through it
    DOUBLES_EQUAL(0.0, segmentPolygonDistance({0.25, 0.5}, {0.75, 0.5}, square), 0.0);         // inside
    DOUBLES_EQUAL(0.0, segmentPolygonDistance({1.0, 2.0}, {1.0, 1.0}, square), 0.0);           // touching
}

TEST(PlanSvg, PathClearanceIsTheLeastOverSegmentsAndObstacles) {
    CcProblem p;
    p.obstacleCount = 2;
    p.obstacles[0] = box(2.0, 3.0, 1.0, 2.0);     // 1 m north of the first segment
    p.obstacles[1] = box(6.0, 7.0, -1.0, -0.75);  // 0.75 m south of the second
    CcPlan plan;
    plan.steps = 2;
    plan.meanX[1] = 4.0;
    plan.meanX[2] = 8.0;
    DOUBLES_EQUAL(0.75, pathClearance(p, plan), 1e-12);
    plan.meanY[2] = -1.0;  // the second segment now passes through the corner (7, -0.75)
    DOUBLES_EQUAL(0.0, pathClearance(p, plan), 1e-12);
    p.obstacleCount = 0;
    CHECK(std::isinf(pathClearance(p, plan)));
}

TEST(PlanSvg, PictureOfTwoPlansIsWellFormedWithOnePathAndStepsPlusOneEllipsesPerPanel) {
    CcStatus a = CcStatus::kBadProblem;
    CcStatus b = CcStatus::kBadProblem;
    const PlanPicture picture = smallPicture(&a, &b);
    CHECK(a == CcStatus::kOptimal || a == CcStatus::kFeasible);
    CHECK(b == CcStatus::kOptimal || b == CcStatus::kFeasible);
    const std::string svg = rse::ground::renderPlanSvg(picture);
    STRCMP_EQUAL("", wellFormed(svg).c_str());
    CHECK(numbersFinite(svg));
    CHECK(svg.find("test &lt;&amp;&gt; title") != std::string::npos);
    const std::vector<std::string> parts = panels(svg);
    CHECK_EQUAL(2U, parts.size());
    const double scale = 760.0 / 12.0;  // the panel's width over the site's
    for (std::size_t k = 0; k < parts.size(); ++k) {
        const std::string& part = parts[k];
        const CcPlan& plan = picture.panels[k].plan;
        const std::size_t points = plan.steps + 1U;
        CHECK_EQUAL(1U, countOf(part, "class=\"mean-path\""));
        CHECK_EQUAL(points, countOf(part, "class=\"ellipse\""));
        CHECK_EQUAL(points, countOf(part, "class=\"waypoint\""));
        CHECK_EQUAL(1U, countOf(part, "class=\"rock\""));
        CHECK_EQUAL(1U, countOf(part, "class=\"grown\""));
        // The start's ellipse: Sigma_0 = [0.04 0.01; 0.01 0.02], eigenvalues
        // 0.03 +- sqrt(0.0002), major axis at 0.5 atan2(0.02, 0.02) = 22.5 deg
        // (y up), so rotate(-22.5) on screen; semi-axes k sqrt(lambda) scale.
        const double k99 = rse::deliberative::upperQuantile(picture.panels[k].problem.riskBound);
        const std::size_t e0 = part.find("<ellipse class=\"ellipse\"");
        const std::string first = part.substr(e0, part.find("/>", e0) - e0);
        DOUBLES_EQUAL(k99 * std::sqrt(0.03 + std::sqrt(0.0002)) * scale, attributeOf(first, "rx"), 0.006);
        DOUBLES_EQUAL(k99 * std::sqrt(0.03 - std::sqrt(0.0002)) * scale, attributeOf(first, "ry"), 0.006);
        CHECK(first.find("rotate(-22.50 ") != std::string::npos);
        // Centred on the start, y flipped: site y = 0.25 is 3.75 m below the top edge.
        const double top = attributeOf(part.substr(part.find("<rect class=\"site\"")), "y");
        DOUBLES_EQUAL(top + 3.75 * scale, attributeOf(first, "cy"), 0.006);
        const std::size_t w0 = part.find("<circle class=\"waypoint\"");
        DOUBLES_EQUAL(top + 3.75 * scale, attributeOf(part.substr(w0), "cy"), 0.006);
        CHECK(part.find("least clearance") != std::string::npos);
    }
    // The smaller Delta draws larger ellipses: k = 4.75 against 2.33.
    const std::size_t a0 = parts[0].find("<ellipse class=\"ellipse\"");
    const std::size_t b0 = parts[1].find("<ellipse class=\"ellipse\"");
    CHECK(attributeOf(parts[1].substr(b0), "rx") > 2.0 * attributeOf(parts[0].substr(a0), "rx"));
}

TEST(PlanSvg, APanelWithoutAPlanDrawsNoPathAndSaysSo) {
    CcStatus a = CcStatus::kBadProblem;
    CcStatus b = CcStatus::kBadProblem;
    PlanPicture picture = smallPicture(&a, &b);
    picture.panels[1].plan = CcPlan{};  // kNoPlan
    const std::string svg = rse::ground::renderPlanSvg(picture);
    STRCMP_EQUAL("", wellFormed(svg).c_str());
    const std::vector<std::string> parts = panels(svg);
    CHECK_EQUAL(2U, parts.size());
    CHECK_EQUAL(0U, countOf(parts[1], "class=\"mean-path\""));
    CHECK_EQUAL(0U, countOf(parts[1], "class=\"ellipse\""));
    CHECK(parts[1].find("no plan") != std::string::npos);
    CHECK_EQUAL(1U, countOf(parts[0], "class=\"mean-path\""));
}
