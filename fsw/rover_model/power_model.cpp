#include "fsw/rover_model/power_model.hpp"

#include <cmath>

namespace rse::rover_model {

using geometry::Point2;
using geometry::wrapAngleRad;

PowerModel powerModelFrom(const tables::HabitualTable& table) {
    return PowerModel{static_cast<double>(table.drive_energy_j_per_m), static_cast<double>(table.turn_energy_j_per_rad),
                      static_cast<double>(table.failed_drive_power_factor)};
}

double meanPowerFactor(const msg::DriveModesMsg& modes, double failedDrivePowerFactor) {
    const double failedFloor = std::isfinite(failedDrivePowerFactor) && failedDrivePowerFactor > 1.0
                                   ? failedDrivePowerFactor
                                   : 1.0;
    double sum = 0.0;
    for (const msg::DriveModeBelief& drive : modes.drives) {
        const double factor = static_cast<double>(drive.powerFactor);
        const bool failed = drive.declared == msg::DriveMode::kFailed || drive.declared == msg::DriveMode::kUnknown;
        if (!std::isfinite(factor)) {
            sum += failedFloor;
        } else {
            sum += std::fmax(factor, failed ? failedFloor : 1.0);
        }
    }
    return sum / static_cast<double>(msg::kWheelCount);
}

double totalHeadingChangeRad(const Point2* path, std::size_t count, double headingRad) {
    if (path == nullptr || count < 2) {
        return 0.0;
    }
    double total = 0.0;
    double previous = headingRad;
    for (std::size_t i = 1; i < count; ++i) {
        const Point2 d = path[i] - path[i - 1];
        if (d.x == 0.0 && d.y == 0.0) {
            continue;
        }
        const double heading = std::atan2(d.y, d.x);
        total += std::fabs(wrapAngleRad(heading - previous));
        previous = heading;
    }
    return total;
}

double motionEnergyJ(const PowerModel& model, double lengthM, double headingChangeRad, double meanFactor) {
    return meanFactor * (model.driveEnergyJPerM * lengthM + model.turnEnergyJPerRad * headingChangeRad);
}

double cruisePowerW(const PowerModel& model, double cruiseSpeedMS, double meanFactor) {
    return meanFactor * model.driveEnergyJPerM * cruiseSpeedMS;
}

double pathEnergyJ(const PowerModel& model, const Point2* path, std::size_t count, double headingRad,
                   double meanFactor) {
    if (path == nullptr || count < 2) {
        return 0.0;
    }
    double length = 0.0;
    for (std::size_t i = 1; i < count; ++i) {
        length += distance(path[i - 1], path[i]);
    }
    return motionEnergyJ(model, length, totalHeadingChangeRad(path, count, headingRad), meanFactor);
}

}  // namespace rse::rover_model
