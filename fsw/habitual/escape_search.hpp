// Where a rover that cannot plan from where it stands backs out to: pure
// geometry on the planning map, the remembered hazards and the coarse map
// (no bus, no events, no state), used by the planning session
// (planning_session.hpp) before it would ask RRT* for a start it refuses.
//
// Out of a hazard disc (findEscape). A remembered disc grows as more of its
// rock comes into view, so the rover can stop with its centre inside a disc
// grown by the footprint (the rover itself clear: the disc over-estimates).
// The way out is a straight segment directly away from the centre of the disc
// the start lies deepest in (or turned by 30, 60, 90 degrees either way when
// that runs towards another obstacle) to the first point clear of that disc by
// footprint + margin + kEscapeExtraM and of everything else by footprint +
// margin (kEscapeSteps of kEscapeStepM further out, at most kMaxEscapeM from
// the start). The way there keeps the bare footprint from the mapped rocks and
// from every other remembered disc (one the start already lies in: no deeper
// into it); it is not checked against the disc it leaves (it only moves away
// from its centre).
//
// Back onto the site (findReentry). A start outside the coarse map's bounds
// (the rover slid or was driven off the orbital map) goes straight to the
// nearest point footprint + margin + kEscapeExtraM inside the site, or one slid
// along the edge by kEscapeStepM steps either way when a rock stands there, at
// most kMaxReentryM away, with the same checks of the end and the way there.
//
// Every loop is bounded by a constant: 7 directions x kEscapeSteps,
// 2 kEscapeSteps + 1 slides, kEscapeChecks points along the way, kMaxMapDiscs.
#pragma once

#include <cstdint>

#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// The extra clearance the way out leaves from the disc it leaves.
constexpr double kEscapeExtraM = 0.05;
// Points tried further out along each direction (and slides along the site's edge).
constexpr double kEscapeStepM = 0.25;
constexpr std::uint32_t kEscapeSteps = 8;
constexpr double kMaxEscapeM = 3.0;
// The longest drive back onto the site. A slide or a wander off the orbital map
// is metres, not tens of metres; a pose farther off is more likely wrong than
// the rover there, and driving that far over unmapped ground on it is not a
// recovery: the leg fails up (no path) and fault protection's tries end in a
// call home.
constexpr double kMaxReentryM = 10.0;
// Points checked along the way out against the mapped rocks (3 m / 30: 0.1 m apart).
constexpr std::uint32_t kEscapeChecks = 30;

class EscapeSearch {
public:
    // planMap: the planning map at the bare footprint (its discs are the
    // remembered covers grown by the footprint); footprintM: the rover's
    // clearance radius; marginM: the planning margin the end keeps beyond it.
    EscapeSearch(const LocalMap& planMap, const MapBuilder& hazards, const tables::CoarseMapTable& coarse,
                 double footprintM, double marginM)
        : planMap_(planMap), hazards_(hazards), coarse_(coarse), footprintM_(footprintM), marginM_(marginM) {}

    // The start lies outside the coarse map's bounds (a re-entry, not an escape).
    bool offSite(geometry::Point2 start) const;
    // start inside a remembered disc grown by the footprint: the point to back
    // out to; false when the start lies in no disc (a coarse-map polygon or the
    // bounds block it) or no direction is clear. headingRad: the way the rover
    // faces (the way out when the start is the disc's very centre is behind it).
    bool findEscape(geometry::Point2 start, double headingRad, geometry::Point2* exit) const;
    // start off the site: the point on it to drive back to; false when none
    // within kMaxReentryM.
    bool findReentry(geometry::Point2 start, geometry::Point2* exit) const;
    // exit keeps footprint + margin from the coarse map and from every
    // remembered disc but leaving (nullptr: every disc), and the way from start
    // keeps the bare footprint from the coarse map and the other discs.
    bool escapeClear(geometry::Point2 start, geometry::Point2 exit, const RememberedHazard* leaving) const;
    // A point q of the way from start lies deeper inside another remembered disc than start does.
    bool intoOtherDisc(geometry::Point2 start, geometry::Point2 q, const RememberedHazard* leaving) const;

private:
    const LocalMap& planMap_;
    const MapBuilder& hazards_;
    const tables::CoarseMapTable& coarse_;
    double footprintM_;
    double marginM_;
};

}  // namespace rse::habitual
