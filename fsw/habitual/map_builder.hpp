// Builds the habitual layer's local map: the coarse (orbital) map from table 9
// plus the obstacles the hazard detector has seen, remembered across frames.
//
// A hazard sighting (HazardMsg, rover frame: range to the nearest point, bearing,
// half width across the line of sight) becomes a disc in the site frame:
//   centre = rover + (range + halfWidth) * (cos(heading + bearing), sin(heading + bearing))
//   radius = max(kSightingRadiusFactor * halfWidth, kMinHazardRadiusM)
// The sighting says how wide the rock is across the line of sight (2 halfWidth)
// but not where that width lies about the nearest point (anywhere from all on
// one side to centred), nor how deep the rock is. With radius = halfWidth the
// union of views still left a corner of the demo's hidden rock 0.28 m outside
// its disc, and the three-layer lockstep mission (unit_test/lockstep/
// test_lockstep_deliberative.cpp) drove into it. A disc enclosing every rock
// those figures allow (no deeper than wide: sqrt(5) halfWidth) blocked the
// rover's own position on close sightings and stalled the habitual lockstep
// leg. kSightingRadiusFactor = 1.5 is the measured compromise: both lockstep
// missions pass without contact. It is not a guarantee for every rock shape. Discs are remembered in a fixed table of kMaxMapDiscs slots keyed by the
// detector's obstacle id. A new sighting of an id is merged with its disc: the
// remembered disc becomes the smallest disc enclosing both (unchanged when it
// already encloses the new one). One sighting sees only the part of an obstacle
// in the field of view, nearest point first, so its disc is offset towards the
// rover and shrinks as the rover drives past; "latest wins" made the disc chase
// the rover round the obstacle (the lockstep demo replanned ten times and
// touched the rock), whereas the union of the views converges on a disc that
// covers the obstacle and only grows, so a detour planned round it stays free.
// A merged disc wider than kMaxMergedRadiusM is not the same obstacle (a reused
// id, or a pose jump): the new sighting then replaces it. A sighting whose centre lies inside a coarse-map
// polygon or within kKnownObstacleMarginM of one is an obstacle the map already
// has: it is counted and not added. When every slot is taken, the slot seen
// longest ago is replaced (counted: the caller events it).
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
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// Below this a sighted obstacle is still given some size: a zero half width is
// a post or an edge seen end-on, not a point.
constexpr double kMinHazardRadiusM = 0.1;
// Disc radius per sighted half width: see the file comment.
constexpr double kSightingRadiusFactor = 1.5;
// A sighting this close to a known polygon is that polygon seen again (the
// detector's range and bearing noise and the pose error are a few centimetres;
// the disc centre estimate of a large rock lands inside or near it).
constexpr double kKnownObstacleMarginM = 0.3;
// Sightings beyond this range are refused as implausible (the detector reaches 3 m).
constexpr double kMaxSightingRangeM = 50.0;
// Largest disc a merge may produce: about twice the rocks a hazard detector
// reports on its own (the coarse map holds anything larger).
constexpr double kMaxMergedRadiusM = 2.0;

enum class SightingOutcome : std::uint8_t {
    kAdded = 0,           // a new obstacle id, in a free slot
    kUpdated = 1,         // an id already remembered: its disc grown to enclose the new one (or replaced, see above)
    kUnchanged = 2,       // an id already remembered whose disc already encloses the new one
    kReplacedOldest = 3,  // a new id with the table full: the oldest slot replaced
    kKnownObstacle = 4,   // on (or within the margin of) a coarse-map polygon: not added
    kRejected = 5,        // not finite, negative, beyond kMaxSightingRangeM, or id 0 ("clear")
};

struct RememberedHazard {
    geometry::Point2 centre;
    double radiusM;
    std::uint32_t lastSeen;  // remember() call count when last sighted (larger is newer)
    std::uint8_t obstacleId;
    bool used;
};

// Points (the rover's start, its goal) round which remembered discs give up
// part of the clearance: a disc whose inflated radius contains one of them is
// added marginM smaller (not below 0), every other obstacle keeps the whole
// clearance. A rover that stopped inside a grown disc's planning margin can
// then plan away from it without the margin being cut for every obstacle.
struct MapRelief {
    geometry::Point2 at[2] = {};
    std::size_t count = 0;
    double marginM = 0.0;
};

class MapBuilder {
public:
    // Turns one sighting into a disc and remembers it (see the file comment).
    // roverPosition / roverHeadingRad: the pose estimate the sighting is relative to.
    SightingOutcome remember(const tables::CoarseMapTable& coarse, geometry::Point2 roverPosition,
                             double roverHeadingRad, const msg::HazardSightingTlm& sighting);
    void forgetAll();

    // map reset to the coarse-map bounds with clearanceM, then every coarse
    // polygon and remembered disc. The first refusal of the map is returned (the
    // map then holds what was added before it); kOk otherwise.
    core::Status build(const tables::CoarseMapTable& coarse, double clearanceM, LocalMap* map,
                       const MapRelief* relief = nullptr) const;

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
