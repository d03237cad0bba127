#include "fsw/habitual/hazard_memory.hpp"

#include <cmath>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/habitual/habitual_events.hpp"

namespace rse::habitual {

using geometry::Point2;

void HazardMemory::remember(const msg::HazardMsg& hazards, Point2 roverPosition, double roverHeadingRad) {
    for (std::size_t i = 0; i < hazards.count && i < msg::kMaxHazardsInMsg; ++i) {
        const msg::HazardSightingTlm& s = hazards.sightings[i];
        SiteWindow site;
        site.map = site_;
        site.query = &query_;
        switch (builder_.remember(coarse_, roverPosition, roverHeadingRad, s, &site)) {
            case SightingOutcome::kAdded:
                reportAdded(s.obstacleId);
                break;
            case SightingOutcome::kUpdated:
            case SightingOutcome::kUnchanged:
                break;
            case SightingOutcome::kReplacedOldest:
                if (core::isReportableOccurrence(builder_.replacedOldest())) {
                    events_.report(events::kHazardTableFull, core::Severity::kWarning,
                                   "habitual: hazard table full (%u): oldest replaced by id %u (%u so far)",
                                   static_cast<unsigned>(kMaxMapDiscs), static_cast<unsigned>(s.obstacleId),
                                   static_cast<unsigned>(builder_.replacedOldest()));
                }
                break;
            case SightingOutcome::kKnownObstacle:
                if (core::isReportableOccurrence(builder_.knownObstacles())) {
                    events_.report(events::kHazardKnown, core::Severity::kDebug,
                                   "habitual: hazard %u is on the coarse map: not added (%u so far)",
                                   static_cast<unsigned>(s.obstacleId),
                                   static_cast<unsigned>(builder_.knownObstacles()));
                }
                break;
            case SightingOutcome::kRejected:
                // The message decoded and its other sightings are good: this
                // one is counted (the task's malformed inputs) and skipped.
                if (core::isReportableOccurrence(builder_.rejected())) {
                    events_.report(events::kMalformedInput, core::Severity::kError,
                                   "habitual: malformed hazard sighting (msg 0x%04x) ignored (%u so far)",
                                   static_cast<unsigned>(msg::ids::kHazards),
                                   static_cast<unsigned>(builder_.rejected()));
                }
                break;
        }
    }
}

void HazardMemory::reportAdded(std::uint8_t obstacleId) {
    const RememberedHazard* h = nullptr;
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        if (builder_.slot(k).used && builder_.slot(k).obstacleId == obstacleId) {
            h = &builder_.slot(k);
        }
    }
    if (h != nullptr) {
        cmdtlm::event_data::HAZARD_REMEMBERED data;
        data.hazard = obstacleId;
        data.x = h->centre.x;
        data.y = h->centre.y;
        data.radius = h->radiusM;
        events_.report(events::kHazardRemembered, core::Severity::kInfo, data.pack(),
                       "habitual: hazard %u seen at (%.2f, %.2f), radius %.2f m: on the map",
                       static_cast<unsigned>(obstacleId), h->centre.x, h->centre.y, h->radiusM);
    }
}

bool HazardMemory::build(LocalMap* map, double clearanceM, const msg::LegCommandMsg& leg, const MapRelief* relief) {
    MapRelief withEnd = relief != nullptr ? *relief : MapRelief{};
    if (leg.legId != 0) {
        withEnd.seenAt = Point2{leg.goalXM, leg.goalYM};
        withEnd.hasSeenAt = true;
    }
    SiteWindow site = windowOf(leg, clearanceM);
    const core::Status status = builder_.build(coarse_, clearanceM, map, &withEnd, &site);
    if (!core::isOk(status) || site.incomplete) {
        ++mapRefused_;
        if (core::isReportableOccurrence(mapRefused_)) {
            events_.report(events::kMapRefused, core::Severity::kError,
                           "habitual: local map refused an obstacle (%s%s) (%u so far)", core::toString(status),
                           site.incomplete ? ", site rocks of the leg's window left out: map not used" : "",
                           static_cast<unsigned>(mapRefused_));
        }
    }
    // A window whose rocks are not all in the map hides some: not usable.
    return map->valid() && !site.incomplete;
}

void HazardMemory::rememberContact(const msg::ContactMsg& contact, double footprintM) {
    const double reach = contact.directionSign * footprintM;
    const Point2 lead{contact.xM + reach * std::cos(contact.headingRad), contact.yM + reach * std::sin(contact.headingRad)};
    const double cover = std::fmax(kContactCoverFactor * footprintM, kContactSeenRadiusM);
    const SightingOutcome outcome = builder_.rememberContact(lead, kContactSeenRadiusM, cover);
    events_.report(events::kContactRemembered, core::Severity::kWarning,
                   "habitual: contact %u at (%.2f, %.2f) remembered as a hazard at (%.2f, %.2f), cover %.2f m (%s)",
                   static_cast<unsigned>(contact.contacts), contact.xM, contact.yM, lead.x, lead.y, cover,
                   outcome == SightingOutcome::kRejected ? "refused" :
                   outcome == SightingOutcome::kReplacedOldest ? "replacing the oldest" : "added");
}

SiteWindow HazardMemory::windowOf(const msg::LegCommandMsg& leg, double clearanceM) {
    SiteWindow w;
    if (leg.legId == 0 || site_ == nullptr || !site_->loaded() || !std::isfinite(leg.maxPathLengthM)) {
        return w;   // no site map in force: the coarse map alone, as before site mode
    }
    w.map = site_;
    w.query = &query_;
    w.centre = Point2{leg.goalXM, leg.goalYM};
    const double reach = leg.maxPathLengthM + clearanceM;
    w.reachM = reach < kMaxSiteWindowM ? reach : kMaxSiteWindowM;
    // A leg whose paths reach past the window would plan on rocks unseen.
    w.incomplete = reach > kMaxSiteWindowM;
    return w;
}

void HazardMemory::refreshCheckMap(double footprintM, const msg::LegCommandMsg& leg) {
    (void)build(&checkMap_, footprintM, leg);
    checkedRevision_ = builder_.revision();
}

void HazardMemory::fillKnownHazards(core::TimeNs now, msg::KnownHazardsMsg* out) const {
    static_assert(msg::kMaxKnownHazards == kMaxMapDiscs, "KnownHazardsMsg carries the whole disc table");
    msg::KnownHazardsMsg& m = *out;
    m = msg::KnownHazardsMsg{};
    m.timeNs = now;
    m.revision = builder_.revision();
    for (std::size_t k = 0; k < kMaxMapDiscs; ++k) {
        const RememberedHazard& h = builder_.slot(k);
        if (h.used) {
            msg::KnownHazard& known = m.hazards[m.count++];
            // The seen disc, not the cover (map_builder.hpp).
            known.xM = static_cast<float>(h.seenCentre.x);
            known.yM = static_cast<float>(h.seenCentre.y);
            known.radiusM = static_cast<float>(h.seenRadiusM);
            known.obstacleId = h.obstacleId;
        }
    }
}

}  // namespace rse::habitual
