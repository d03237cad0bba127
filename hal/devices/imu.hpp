// IMU client (0x6A0): yaw rate at 100 Hz.
#pragma once

#include "hal/devices/device_frame_sink.hpp"

namespace rse::hal {

struct ImuSample {
    double yawRateRadS = 0.0;
    bool valid = false;       // the device's own status bit
    core::TimeNs time = 0;
    std::uint32_t count = 0;  // samples accepted
};

constexpr double kImuMaxYawRate = 10.0;  // rad/s; beyond this a frame is rejected

class Imu final : public DeviceFrameSink {
public:
    explicit Imu(core::EventLog& events) : DeviceFrameSink(events, "imu") {}
    const ImuSample& latest() const { return latest_; }

private:
    bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) override;
    ImuSample latest_;
};

}  // namespace rse::hal
