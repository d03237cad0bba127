// The habitual layer's memory of the hazards it has seen, and the maps built
// from it: the hazard detector's sightings placed with the pose and
// remembered (map_builder.hpp: discs kept for the whole mission, the oldest
// replaced when full), each outcome evented; the local maps a leg plans and
// checks on (the coarse map plus the remembered covers, inflated); the check
// map the path being driven is held against (bare footprint, rebuilt whenever
// the memory changes); and the KnownHazardsMsg that tells the deliberative
// layer the seen discs.
//
// Every map of a leg (planning and checking alike) takes the hazard whose cover
// reaches the leg's end as its seen disc (map_builder.hpp, MapRelief::seenAt):
// the deliberative layer keeps leg ends off the seen discs it is told of.
//
// Events: 816 (first sighting of an id), 814 (table full, throttled), 815 (on
// the coarse map, throttled), 817 (the local map refused an obstacle,
// throttled), 813 (a sighting that is not finite or out of range, throttled on
// the rejected sightings: the hazard message's other sightings are placed). No
// bus, no heap; loops bounded by kMaxHazardsInMsg and kMaxMapDiscs.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "fsw/geometry/geometry2d.hpp"
#include "fsw/habitual/local_map.hpp"
#include "fsw/habitual/map_builder.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::habitual {

// A contact's discs (rememberContact): the seen disc's radius, and the
// cover's as a fraction of the footprint radius.
constexpr double kContactSeenRadiusM = 0.25;
constexpr double kContactCoverFactor = 0.8;

class HazardMemory {
public:
    // site: the site map in force (site mode), or null.
    HazardMemory(core::EventLog& events, const tables::CoarseMapTable& coarse,
                 const site_map::SiteMap* site = nullptr)
        : events_(events), coarse_(coarse), site_(site) {}

    // hazards' sightings, relative to the rover at roverPosition facing
    // roverHeadingRad, remembered (hazards.count is checked by the caller).
    void remember(const msg::HazardMsg& hazards, geometry::Point2 roverPosition, double roverHeadingRad);

    // A contact (ContactMsg, already checked): a disc where the rover's
    // footprint (radius footprintM) touched, on the side it drove towards
    // (kContactSeenRadiusM about the footprint's leading point, cover
    // kContactCoverFactor x footprintM about it: the footprint's rim within
    // about 45 degrees of the heading), remembered (MapBuilder::rememberContact)
    // and evented (823).
    void rememberContact(const msg::ContactMsg& contact, double footprintM);

    // map rebuilt from the coarse map and the memory, every obstacle inflated
    // by clearanceM, with relief (may be null) and the leg's end (legId 0: no
    // leg) as the seen disc's place; in site mode with the site map's rocks in
    // the leg's window (map_builder.hpp, SiteWindow). Whether the map is usable.
    bool build(LocalMap* map, double clearanceM, const msg::LegCommandMsg& leg, const MapRelief* relief = nullptr);

    // The check map: rebuilt at footprintM for the leg, at the memory's revision.
    void refreshCheckMap(double footprintM, const msg::LegCommandMsg& leg);
    // Sightings changed the memory since the check map was built.
    bool checkMapStale() const { return builder_.revision() != checkedRevision_; }
    const LocalMap& checkMap() const { return checkMap_; }

    // The remembered seen discs, for the deliberative layer.
    void fillKnownHazards(core::TimeNs now, msg::KnownHazardsMsg* out) const;

    const MapBuilder& builder() const { return builder_; }
    std::uint32_t revision() const { return builder_.revision(); }
    std::uint32_t mapRefused() const { return mapRefused_; }
    std::uint32_t rejectedSightings() const { return builder_.rejected(); }

private:
    void reportAdded(std::uint8_t obstacleId);

    // The site rocks' window of a leg (none without a leg or a site map).
    SiteWindow windowOf(const msg::LegCommandMsg& leg, double clearanceM);

    core::EventLog& events_;
    const tables::CoarseMapTable& coarse_;
    const site_map::SiteMap* site_ = nullptr;
    site_map::SiteQuery query_{};
    std::uint32_t checkedRevision_ = 0;
    std::uint32_t mapRefused_ = 0;
    MapBuilder builder_;
    LocalMap checkMap_;
};

}  // namespace rse::habitual
