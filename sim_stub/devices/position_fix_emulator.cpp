#include "sim_stub/devices/position_fix_emulator.hpp"

#include <cmath>

#include "hal/canopen/le_codec.hpp"

namespace rse::sim {

PositionFixEmulator::PositionFixEmulator(hal::CanBus& bus, const World& world, const PositionFixParams& params,
                                         std::uint64_t seed, bool pollsBus)
    : DeviceEmulator(bus, kPositionFixNodeId, pollsBus),
      world_(world),
      params_(params),
      rng_(seed, RngStream::kPositionFix) {}

bool PositionFixEmulator::injectOutlier(double offsetM, double bearingRad, std::uint32_t count) {
    if (!(std::isfinite(offsetM) && offsetM > 0.0) || !std::isfinite(bearingRad) || count == 0) {
        return false;
    }
    outliersPending_ = count;
    outlierDx_ = offsetM * std::cos(bearingRad);
    outlierDy_ = offsetM * std::sin(bearingRad);
    return true;
}

void PositionFixEmulator::onBoot(core::TimeNs now, bool resetApplication) {
    if (resetApplication) {
        counter_ = 0;
    }
    schedule_.start(now + kFixPeriodNs, kFixPeriodNs);
}

void PositionFixEmulator::produce(core::TimeNs now) {
    if (schedule_.take(now, 1, &mutableStats().samplesSkipped) == 0) {
        return;  // a late fix is one fix
    }
    const Pose2& pose = world_.truth().pose;
    double x = pose.x + params_.sigmaM * rng_.gaussian();
    double y = pose.y + params_.sigmaM * rng_.gaussian();
    if (outliersPending_ > 0) {
        --outliersPending_;
        ++outliersProduced_;
        x += outlierDx_;
        y += outlierDy_;
    }
    const double heading = wrapAngle(pose.theta + params_.headingSigmaRad * rng_.gaussian());
    std::uint16_t sigmaMm = saturateU16(params_.sigmaM * 1e3);
    sigmaMm = sigmaMm == 0 ? 1 : sigmaMm;
    std::int16_t headingField = saturateI16(heading * 1e4);
    headingField = headingField > 31416 ? 31416 : (headingField < -31416 ? -31416 : headingField);

    hal::CanFrame fx;
    fx.id = kFixXCobId;
    fx.dlc = 8;
    hal::le::putI32(&fx.data[0], saturateI32(x * 1e3));
    hal::le::putU16(&fx.data[4], sigmaMm);
    hal::le::putU16(&fx.data[6], counter_);
    hal::CanFrame fy;
    fy.id = kFixYCobId;
    fy.dlc = 8;
    hal::le::putI32(&fy.data[0], saturateI32(y * 1e3));
    hal::le::putI16(&fy.data[4], headingField);
    hal::le::putU16(&fy.data[6], counter_);
    counter_ = static_cast<std::uint16_t>(counter_ + 1);
    sendData(fx);
    sendData(fy);
}

}  // namespace rse::sim
