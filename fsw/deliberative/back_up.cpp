#include "fsw/deliberative/back_up.hpp"

#include <cmath>

#include "fsw/deliberative/deliberative_events.hpp"

namespace rse::deliberative {

void BackUpManoeuvre::record(const msg::PoseEstimateMsg& pose, bool poseSeen) {
    if (active_ || !poseSeen || pose.initialised == 0 || !std::isfinite(pose.xM) || !std::isfinite(pose.yM)) {
        return;
    }
    if (trackCount_ > 0) {
        const std::size_t newest = (trackHead_ + trackCount_ - 1) % kTrackPoints;
        if (std::hypot(pose.xM - trackX_[newest], pose.yM - trackY_[newest]) < kTrackStepM) {
            return;
        }
    }
    const std::size_t slot = (trackHead_ + trackCount_) % kTrackPoints;
    trackX_[slot] = pose.xM;
    trackY_[slot] = pose.yM;
    if (trackCount_ < kTrackPoints) {
        ++trackCount_;
    } else {
        trackHead_ = (trackHead_ + 1) % kTrackPoints;
    }
}

bool BackUpManoeuvre::target(const msg::PoseEstimateMsg& pose, double distanceM, const LegEndClearance& clear,
                             msg::PlanLeg* out, std::size_t* keep) const {
    // Walk back from the pose through the track, newest first; the first point
    // at or beyond distanceM (then every kTrackStepM, up to twice it) that is
    // clear of every seen hazard.
    double fromX = pose.xM;
    double fromY = pose.yM;
    double walked = 0.0;
    double want = distanceM;
    const double farthest = 2.0 * distanceM;
    for (std::size_t k = 0; k < trackCount_; ++k) {
        const std::size_t i = (trackHead_ + trackCount_ - 1 - k) % kTrackPoints;
        const double seg = std::hypot(trackX_[i] - fromX, trackY_[i] - fromY);
        // At most farthest / kTrackStepM candidates in all (80 for 10 m).
        for (std::uint32_t c = 0; c < 100 && seg > 0.0 && walked + seg >= want; ++c) {
            const double f = (want - walked) / seg;
            msg::PlanLeg p{};
            p.xM = fromX + f * (trackX_[i] - fromX);
            p.yM = fromY + f * (trackY_[i] - fromY);
            if (!clear.tooClose(p.xM, p.yM)) {
                *out = p;
                *keep = trackCount_ - 1 - k;  // the points beyond the target are driven back over
                return true;
            }
            want += kTrackStepM;
            if (want > farthest) {
                return false;
            }
        }
        walked += seg;
        fromX = trackX_[i];
        fromY = trackY_[i];
    }
    return false;
}

bool BackUpManoeuvre::start(const msg::PoseEstimateMsg& pose, double distanceM, std::uint32_t limit,
                            std::uint32_t replans, const LegEndClearance& clear) {
    msg::PlanLeg found{};
    std::size_t keep = 0;
    if (goalBackUps_ >= limit || !(distanceM > 0.0) || !target(pose, distanceM, clear, &found, &keep)) {
        return false;
    }
    keep_ = keep;
    ++goalBackUps_;
    ++backUps_;
    active_ = true;
    leg_ = found;
    events_.report(events::kBackingUp, core::Severity::kWarning,
                   "deliberative: no path after %u replans: backing up %.1f m along the track to (%.2f, %.2f), %u of %u",
                   static_cast<unsigned>(replans), std::hypot(found.xM - pose.xM, found.yM - pose.yM), found.xM,
                   found.yM, static_cast<unsigned>(goalBackUps_), static_cast<unsigned>(limit));
    return true;
}

void BackUpManoeuvre::reached(const msg::PoseEstimateMsg& pose, bool poseSeen, std::uint32_t limit,
                              std::size_t goalNumber) {
    active_ = false;
    // The track now ends where the back-up did: a further back-up goes on
    // back, not over the ground just reversed along.
    trackCount_ = keep_ < trackCount_ ? keep_ : trackCount_;
    record(pose, poseSeen);
    events_.report(events::kBackedUp, core::Severity::kInfo,
                   "deliberative: backed up to (%.2f, %.2f) (%u of %u): replanning goal %u from there", pose.xM,
                   pose.yM, static_cast<unsigned>(goalBackUps_), static_cast<unsigned>(limit),
                   static_cast<unsigned>(goalNumber));
}

}  // namespace rse::deliberative
