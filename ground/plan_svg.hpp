// Chance-constrained plans drawn as one SVG (rse-plan-picture, `make
// plan-picture`): one panel per plan, side by side, each showing the site, the
// coarse map's polygons (filled), the obstacles the planner was given (the
// polygons grown by the footprint, dashed), the mean path (polyline and a dot
// per waypoint), the start and the goal, and at every step t = 0 .. N the
// ellipse {x : (x - mu_t)' Sigma_t^-1 (x - mu_t) = k^2} of the plan's
// covariance Sigma_t = Sigma_0 + t sigma^2 I, with k = PhiInv(1 - Delta).
//
// Why that k: the support function of that ellipse in a direction a is
// k sqrt(a' Sigma_t a), the tightening margin of a face end at risk Delta
// (gaussian.hpp). Every end's risk is at most the plan's total Delta, so its
// margin is at least that: the drawn ellipses stay off every grown obstacle
// (on the safe side of the face each segment was assigned). A smaller Delta
// gives a larger k, larger ellipses and so a path that keeps farther away.
//
// Each panel's caption: Delta, planner status, risk used, Euclidean path
// length, least clearance (pathClearance) and k. The site frame is y-up
// (x east, y north); SVG's y axis is flipped when drawing. Every number
// written is finite (a non-finite one is drawn as nothing, never as "nan").
// Host only (std::string, std::vector).
#pragma once

#include <string>
#include <vector>

#include "fsw/deliberative/cc_problem.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::ground {

// The corners of a convex obstacle given by its faces, counter-clockwise:
// every point where two face lines meet that lies on or below every other
// face (within 1e-9 m). Empty when the faces bound no polygon.
std::vector<geometry::Point2> obstacleCorners(const deliberative::PlanObstacle& obstacle);

// Euclidean distance between the closed segment [p, q] and the closed convex
// polygon (corners counter-clockwise); 0 when they meet.
double segmentPolygonDistance(geometry::Point2 p, geometry::Point2 q, const std::vector<geometry::Point2>& corners);

// The least clearance of a plan: the least, over the mean path's segments
// mu_t -> mu_{t+1} and the problem's obstacles (grown by the footprint), of
// the Euclidean distance from the segment to the grown polygon; 0 when one
// meets one, INFINITY with no obstacle or no step. The distance the rover's
// footprint disc keeps from a rock is at least this (the grown polygon
// contains every disc centre that touches the rock).
double pathClearance(const deliberative::CcProblem& problem, const deliberative::CcPlan& plan);

// One panel: a problem and its plan (any status; only a plan is drawn as a path).
struct PlanPanel {
    deliberative::CcProblem problem{};
    deliberative::CcPlan plan{};
};

struct PlanPicture {
    tables::CoarseMapTable map{};   // site bounds and the polygons to fill
    double footprintRadiusM = 0.0;  // for the legend
    std::string title;              // drawn above the panels
    std::vector<PlanPanel> panels;
};

// The ellipse scale k of a panel: PhiInv(1 - Delta).
double ellipseQuantile(double riskBound);

// The pieces a panel is drawn with, for other pictures of the same site (the
// mission map, ground/mission_report.hpp).
// Site metres to pixels, y up (SVG's y axis points down).
struct SvgFrame {
    double originX;  // pixel of the site's west edge
    double originY;  // pixel of the site's north edge
    double scale;    // pixels per metre
    double xMin;
    double yMax;
    double x(double metres) const { return originX + (metres - xMin) * scale; }
    double y(double metres) const { return originY + (yMax - metres) * scale; }
};
// A pixel figure with two decimals; text with XML's five specials escaped.
std::string svgNumber(double v);
// A figure for people: `decimals` decimals, or three significant digits ("n/a"
// or "inf" when not finite).
std::string svgFixed(double v, int decimals);
std::string svgScientific(double v);
std::string svgEscape(const std::string& text);
// "x,y x,y ...": a polygon's or polyline's points attribute.
std::string svgPoints(const std::vector<geometry::Point2>& points, const SvgFrame& f);
// The colour of plan (or panel) `index`.
const char* planColour(std::size_t index);
// The site rectangle and its 5 m ticks; the coarse map's rocks, filled; a
// problem's obstacles grown by the footprint, dashed; a plan's ellipse at every
// step (k = PhiInv(1 - Delta)), its mean path and a dot per step in `colour`
// (nothing when it has no path).
void drawSite(const tables::CoarseMapTable& map, const SvgFrame& f, std::string* svg);
void drawRocks(const tables::CoarseMapTable& map, const SvgFrame& f, std::string* svg);
void drawGrownObstacles(const deliberative::CcProblem& problem, const SvgFrame& f, std::string* svg);
void drawPlan(const deliberative::CcProblem& problem, const deliberative::CcPlan& plan, const char* colour,
              const SvgFrame& f, std::string* svg);

// The whole SVG document (UTF-8, with the XML declaration).
std::string renderPlanSvg(const PlanPicture& picture);

}  // namespace rse::ground
