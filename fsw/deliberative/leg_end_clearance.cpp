#include "fsw/deliberative/leg_end_clearance.hpp"

#include <cstddef>

#include "fsw/geometry/coarse_map.hpp"

namespace rse::deliberative {

bool LegEndClearance::tooClose(double xM, double yM) const {
    if (geometry::distanceToCoarseMap(map_, geometry::Point2{xM, yM}) < clearanceM_) {
        return true;
    }
    for (std::size_t i = 0; i < hazards_.count && i < msg::kMaxKnownHazards; ++i) {
        const msg::KnownHazard& h = hazards_.hazards[i];
        const double reach = static_cast<double>(h.radiusM) + clearanceM_;
        const double dx = xM - static_cast<double>(h.xM);
        const double dy = yM - static_cast<double>(h.yM);
        if (dx * dx + dy * dy < reach * reach) {
            return true;
        }
    }
    return false;
}

}  // namespace rse::deliberative
