#include "fsw/deliberative/drive_health.hpp"

#include "fsw/rover_model/power_model.hpp"

namespace rse::deliberative {

namespace {

bool unhealthy(msg::DriveHealth h) {
    return h == msg::DriveHealth::kFaulted || h == msg::DriveHealth::kFailed || h == msg::DriveHealth::kLost;
}

}  // namespace

void DriveHealthView::takeDriveStatus(const msg::DriveStatusMsg& drives) {
    interlockTripped_ = drives.interlockTripped != 0;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        health_[w] = drives.wheels[w].health;
    }
}

void DriveHealthView::takeDriveModes(const msg::DriveModesMsg& modes, core::TimeNs now) {
    modes_ = modes;
    modesSeen_ = true;
    // Since when each drive has been declared failed or unknown without a break.
    const std::uint8_t failed = failedDrives(true);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (((failed >> w) & 1U) == 0U) {
            failedSinceNs_[w] = 0;
        } else if (failedSinceNs_[w] == 0) {
            failedSinceNs_[w] = now > 0 ? now : 1;
        }
    }
}

std::uint8_t DriveHealthView::failedDrives(bool withUnknown) const {
    std::uint8_t mask = 0;
    for (std::size_t w = 0; modesSeen_ && w < msg::kWheelCount; ++w) {
        const msg::DriveMode m = modes_.drives[w].declared;
        if (m == msg::DriveMode::kFailed || (withUnknown && m == msg::DriveMode::kUnknown)) {
            mask = static_cast<std::uint8_t>(mask | (1U << w));
        }
    }
    return mask;
}

std::uint8_t DriveHealthView::confirmedFailedDrives(core::TimeNs now, double confirmS) const {
    const auto confirm = static_cast<core::TimeNs>(confirmS * 1e9);
    std::uint8_t mask = 0;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (failedSinceNs_[w] != 0 && now - failedSinceNs_[w] >= confirm) {
            mask = static_cast<std::uint8_t>(mask | (1U << w));
        }
    }
    return mask;
}

bool DriveHealthView::mobilityLost() const {
    if (!interlockTripped_) {
        return false;
    }
    const std::uint8_t failed = failedDrives(false);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (unhealthy(health_[w]) && ((failed >> w) & 1U) == 0U) {
            return true;
        }
    }
    return failed == 0;
}

double DriveHealthView::meanPowerFactor(double failedDriveFactor) const {
    if (!modesSeen_) {
        return 1.0;
    }
    return rover_model::meanPowerFactor(modes_, failedDriveFactor);
}

void wheelNames(std::uint8_t mask, char* out, std::size_t size) {
    std::size_t used = 0;
    out[0] = '\0';
    for (std::size_t w = 0; w < msg::kWheelCount && used + 4 < size; ++w) {
        if (((mask >> w) & 1U) != 0U) {
            const char* name = msg::wheelName(w);
            if (used > 0) {
                out[used++] = ' ';
            }
            for (std::size_t i = 0; name[i] != '\0' && used + 1 < size; ++i) {
                out[used++] = name[i];
            }
            out[used] = '\0';
        }
    }
}

}  // namespace rse::deliberative
