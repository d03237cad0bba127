#include "sim_stub/devices/imu_emulator.hpp"

#include "hal/canopen/le_codec.hpp"

namespace rse::sim {

ImuEmulator::ImuEmulator(hal::CanBus& bus, const World& world, const ImuParams& params, std::uint64_t seed,
                         bool pollsBus)
    : DeviceEmulator(bus, kImuNodeId, pollsBus),
      world_(world),
      params_(params),
      rng_(seed, RngStream::kImu),
      bias_(params.biasRadS) {}

void ImuEmulator::onBoot(core::TimeNs now, bool resetApplication) {
    if (resetApplication) {
        counter_ = 0;
    }
    schedule_.start(now + kImuPeriodNs, kImuPeriodNs);
}

void ImuEmulator::produce(core::TimeNs now) {
    const std::size_t due = schedule_.take(now, kDeviceMaxCatchUp, &mutableStats().samplesSkipped);
    for (std::size_t i = 0; i < due; ++i) {
        const double rate = world_.truth().yawRateRadS + bias_ + params_.noiseSigmaRadS * rng_.gaussian();
        hal::CanFrame f;
        f.id = kImuCobId;
        f.dlc = 8;
        hal::le::putI32(&f.data[0], saturateI32(rate * 1e6));
        hal::le::putU16(&f.data[4], counter_);
        f.data[6] = 0x01;  // valid
        f.data[7] = 0;
        ++counter_;
        sendData(f);
    }
}

}  // namespace rse::sim
