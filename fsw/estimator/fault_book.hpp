// The health monitor's record of its faults (ids in fsw/msg/health_msgs.hpp):
// which are active, how often each was raised and cleared, when each last
// changed, and the latest transition, which is what FaultStatusMsg carries.
#pragma once

#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/msg/health_msgs.hpp"

namespace rse::estimator {

class FaultBook {
public:
    static bool validId(std::uint8_t id) { return id != 0 && id < msg::fault::kCount; }

    // Returns true when the fault changed state (false for an unknown id).
    bool set(std::uint8_t id, bool active, core::TimeNs now) {
        if (!validId(id) || isActive(id) == active) {
            return false;
        }
        const std::uint64_t bit = std::uint64_t{1} << id;
        if (active) {
            mask_ |= bit;
            ++raised_[id];
            ++raisedTotal_;
        } else {
            mask_ &= ~bit;
            ++cleared_[id];
            ++clearedTotal_;
        }
        changedAt_[id] = now;
        lastFaultId_ = id;
        lastRaised_ = active;
        return true;
    }

    bool isActive(std::uint8_t id) const { return validId(id) && (mask_ & (std::uint64_t{1} << id)) != 0; }
    std::uint32_t raisedCount(std::uint8_t id) const { return validId(id) ? raised_[id] : 0; }
    std::uint32_t clearedCount(std::uint8_t id) const { return validId(id) ? cleared_[id] : 0; }
    // When the fault last changed state (0: never).
    core::TimeNs changedAt(std::uint8_t id) const { return validId(id) ? changedAt_[id] : 0; }

    std::uint64_t activeMask() const { return mask_; }
    std::uint32_t raisedTotal() const { return raisedTotal_; }
    std::uint32_t clearedTotal() const { return clearedTotal_; }
    std::uint8_t lastFaultId() const { return lastFaultId_; }
    bool lastRaised() const { return lastRaised_; }

private:
    static_assert(msg::fault::kCount <= 64, "activeMask holds one bit per fault id");

    std::uint64_t mask_ = 0;
    std::uint32_t raised_[msg::fault::kCount] = {};
    std::uint32_t cleared_[msg::fault::kCount] = {};
    core::TimeNs changedAt_[msg::fault::kCount] = {};
    std::uint32_t raisedTotal_ = 0;
    std::uint32_t clearedTotal_ = 0;
    std::uint8_t lastFaultId_ = 0;
    bool lastRaised_ = false;
};

}  // namespace rse::estimator
