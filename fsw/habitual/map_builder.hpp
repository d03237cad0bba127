// Builds the habitual layer's local map: the coarse (orbital) map from table 9
// plus the obstacles the hazard detector has seen, remembered across frames.
//
// A hazard sighting (HazardMsg, rover frame: range to the nearest point, bearing,
// half width across the line of sight; docs/icd.md §1.6) becomes two discs in
// the site frame, with one centre:
//   centre = rover + (range + halfWidth) * (cos(heading + bearing), sin(heading + bearing))
//   seen   radius = max(kSightingRadiusFactor * halfWidth, kMinHazardRadiusM)
//   cover  radius = max(kCoverRadiusFactor * halfWidth, kMinHazardRadiusM)
// What the sighting says: the nearest point P of the rock (range, bearing) and
// how wide the rock is across the line of sight (2 halfWidth), but not where that
// width lies about P - anywhere from centred on it to all on one side (a rock
// seen edge-on at its corner: the one-sided case) - nor how deep the rock is.
// So every point of the rock lies within 2 halfWidth of the bearing line, on
// either side, beyond P. Assuming the rock no deeper along the line of sight
// than its sighted width (2 halfWidth), every rock the sighting allows lies in
// the rectangle 4 halfWidth across by 2 halfWidth deep beyond P, whose smallest
// enclosing disc is the cover: centre halfWidth beyond P, radius sqrt(5)
// halfWidth. The seen disc (1.5 halfWidth) covers a rock centred on the bearing
// line and misses up to (sqrt(5) - 1.5) halfWidth of a one-sided one: Monte
// Carlo seed 52 (docs/montecarlo.md) saw its boulder edge-on at the corner,
// planned round a 0.39 m seen disc, passed the unseen side and touched it.
//
// The habitual layer plans, checks its path and backs out against the cover
// (centre, radiusM): it is what the detector's reports allow, not a guess. The
// seen disc (seenCentre, seenRadiusM) is the estimate of the rock the views
// converge on and is what the deliberative layer is told (KnownHazardsMsg): its
// coarse plans and leg ends need the rock where it most likely is, and the
// habitual layer keeps the rover off the rest (docs/habitual.md, "Hazards").
// With the seen disc alone at 1.0 the union of views left a corner of the demo's
// hidden rock 0.28 m outside; 1.5 is the factor the scenario's choreography was
// measured with (docs/mission.md), kept for the deliberative layer.
//
// Discs are remembered in a fixed table of kMaxMapDiscs slots keyed by the
// detector's obstacle id. A new sighting of an id is merged with its discs: each
// remembered disc becomes the smallest disc enclosing it and the new one
// (unchanged when it already encloses it). One sighting sees only the part of
// an obstacle in the field of view, nearest point first, so its disc is offset
// towards the rover and shrinks as the rover drives past; "latest wins" made the
// disc chase the rover round the obstacle (the lockstep demo replanned ten times
// and touched the rock), whereas the union of the views converges on a disc that
// covers the obstacle and only grows, so a detour planned round it stays free.
// When the seen discs merged would be wider than kMaxMergedRadiusM it is not the
// same obstacle (a reused id, or a pose jump): the new sighting then replaces
// both discs (the cover, from the same views, is then at most about
// kCoverRadiusFactor / kSightingRadiusFactor times that). A sighting whose
// centre lies inside a coarse-map polygon or within kKnownObstacleMarginM of one
// is an obstacle the map already has: it is counted and not added. When every
// slot is taken, the slot seen longest ago is replaced (counted: the caller
// events it).
//
// Lifetime: remembered discs are kept until forgetAll() (the habitual task calls
// it never during a mission; see habitual_task.hpp): rocks do not move, a disc
// seen on one leg is still there for the next, and each re-sighting completes it.
// A stale or wrong disc is bounded by the table size (the oldest goes first).
//
// build() fills a LocalMap from scratch: bounds and polygons from the coarse-map
// table (already checked convex at table validation), the remembered discs, every
// obstacle inflated by the caller's clearance. The coarse map is read through
// fsw/geometry/coarse_map.hpp (shared with the deliberative layer).
//
// Pure data: no bus, no events; counters say what happened. No heap; loops
// bounded by kMaxMapDiscs, the table's 16 slots and 8 vertices per slot.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/status.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/site_map/site_map.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// Below this a sighted obstacle is still given some size: a zero half width is
// a post or an edge seen end-on, not a point.
constexpr double kMinHazardRadiusM = 0.1;
// Seen-disc radius per sighted half width (the deliberative layer's estimate):
// see the file comment.
constexpr double kSightingRadiusFactor = 1.5;
// Cover radius per sighted half width, sqrt(5): the smallest disc enclosing every
// rock no deeper than its sighted width that the sighting allows, the width on
// either side of the nearest point (the file comment). Geometry, not a tuning:
// a site whose rocks are deeper than wide would need the depth assumption
// changed, not this number.
constexpr double kCoverRadiusFactor = 2.23606797749978969641;
// A sighting whose surface seen and centre estimate both lie this close to a
// known polygon is that polygon seen again (the detector's range and bearing
// noise and the pose error are a few centimetres; the disc centre estimate of
// a large rock lands inside or near it).
constexpr double kKnownObstacleMarginM = 0.3;
// Sightings beyond this range are refused as implausible (the detector reaches 3 m).
constexpr double kMaxSightingRangeM = 50.0;
// Largest disc a merge may produce: about twice the rocks a hazard detector
// reports on its own (the coarse map holds anything larger).
constexpr double kMaxMergedRadiusM = 2.0;

enum class SightingOutcome : std::uint8_t {
    kAdded = 0,           // a new obstacle id, in a free slot
    kUpdated = 1,         // an id already remembered: its discs grown to enclose the new ones (or replaced, see above)
    kUnchanged = 2,       // an id already remembered whose discs already enclose the new ones
    kReplacedOldest = 3,  // a new id with the table full: the oldest slot replaced
    kKnownObstacle = 4,   // on (or within the margin of) a coarse-map polygon: not added
    kRejected = 5,        // not finite, negative, beyond kMaxSightingRangeM, or id 0 ("clear")
};

struct RememberedHazard {
    geometry::Point2 centre;  // the cover: what the habitual layer plans round
    double radiusM;
    geometry::Point2 seenCentre;  // the seen disc: what the deliberative layer is told
    double seenRadiusM;
    std::uint32_t lastSeen;  // remember() call count when last sighted (larger is newer)
    std::uint8_t obstacleId;
    bool used;
};

// Points (the rover's start, its goal) round which remembered discs give up
// part of the clearance: a disc whose inflated radius contains one of them is
// added marginM smaller (not below 0), every other obstacle keeps the whole
// clearance. A rover that stopped inside a grown disc's planning margin can
// then plan away from it without the margin being cut for every obstacle.
// seenAt (the leg's end, when hasSeenAt): a hazard whose cover, inflated,
// contains it is added as its seen disc instead (before marginM is taken off).
// The deliberative layer keeps leg ends off the seen discs it is told of, not
// off the covers (the file comment), so such an end is reachable.
struct MapRelief {
    geometry::Point2 at[2] = {};
    std::size_t count = 0;
    double marginM = 0.0;
    geometry::Point2 seenAt = {};
    bool hasSeenAt = false;
};

// The site map's rocks a local map takes (site mode, docs/site_map.md): those
// whose boxes come within reachM of centre. A leg's window is the disc about
// its goal that holds every path the leg allows (a point on a path no longer
// than maxPathLengthM that ends at the goal lies within that of it), plus the
// clearance, at most kMaxSiteWindowM.
struct SiteWindow {
    const site_map::SiteMap* map = nullptr;   // null or not loaded: no site rocks
    site_map::SiteQuery* query = nullptr;
    geometry::Point2 centre{0.0, 0.0};
    double reachM = 0.0;
    // Set by build(): some rock of the window is not in the map (more than it
    // holds, the query refused, or the window cut to kMaxSiteWindowM): the
    // map does not show the leg's whole neighbourhood and must not be used.
    bool incomplete = false;
};
constexpr double kMaxSiteWindowM = 40.0;

// A contact (ContactMsg): the rover touched something the hazard detector
// did not report. Remembered as a disc of its own keyed by id 0, which no
// sighting carries (0 is the detector's "clear"), so no sighting merges with
// it; never the "oldest" a new sighting replaces (nothing will see it again),
// at most kMaxContactDiscs of them (a further contact replaces the oldest).
constexpr std::uint8_t kContactObstacleId = 0;
constexpr std::size_t kMaxContactDiscs = 8;

class MapBuilder {
public:
    // A contact's discs (both centred at centre): the seen disc (what the
    // deliberative layer is told) and the cover (what the habitual layer plans
    // round). kRejected for a value not finite, a seen radius not positive, a
    // cover smaller than it or larger than kMaxMergedRadiusM.
    SightingOutcome rememberContact(geometry::Point2 centre, double seenRadiusM, double coverRadiusM);
    // Turns one sighting into a disc and remembers it (see the file comment).
    // roverPosition / roverHeadingRad: the pose estimate the sighting is relative to.
    // site (may be null): a sighting on a site-map rock is known too.
    SightingOutcome remember(const tables::CoarseMapTable& coarse, geometry::Point2 roverPosition,
                             double roverHeadingRad, const msg::HazardSightingTlm& sighting,
                             const SiteWindow* site = nullptr);
    void forgetAll();

    // map reset to the coarse-map bounds with clearanceM, then every coarse
    // polygon, the site map's rocks in site's window (when site is given and
    // holds a map) and every remembered cover. The first refusal of the map is
    // returned (the map then holds what was added before it; more site rocks
    // in the window than the map holds: kFull and site->incomplete); kOk otherwise.
    core::Status build(const tables::CoarseMapTable& coarse, double clearanceM, LocalMap* map,
                       const MapRelief* relief = nullptr, SiteWindow* site = nullptr) const;

    std::size_t rememberedCount() const;
    const RememberedHazard& slot(std::size_t index) const { return slots_[index < kMaxMapDiscs ? index : 0]; }
    // Changes whenever a remembered disc is added, grown, replaced or forgotten.
    std::uint32_t revision() const { return revision_; }

    std::uint32_t added() const { return added_; }
    std::uint32_t updated() const { return updated_; }      // kUpdated outcomes
    std::uint32_t unchanged() const { return unchanged_; }  // kUnchanged outcomes
    std::uint32_t replacedOldest() const { return replaced_; }
    std::uint32_t knownObstacles() const { return known_; }
    std::uint32_t rejected() const { return rejected_; }

private:
    RememberedHazard slots_[kMaxMapDiscs] = {};
    std::uint32_t sightings_ = 0;
    std::uint32_t revision_ = 0;
    std::uint32_t added_ = 0;
    std::uint32_t updated_ = 0;
    std::uint32_t unchanged_ = 0;
    std::uint32_t replaced_ = 0;
    std::uint32_t known_ = 0;
    std::uint32_t rejected_ = 0;
};

}  // namespace rse::habitual
