#include "hal/devices/imu.hpp"

#include "hal/canopen/le_codec.hpp"

namespace rse::hal {

bool Imu::decode(const CanFrame& frame, core::TimeNs now, const char** reason) {
    const double rate = static_cast<double>(le::getI32(&frame.data[0])) * 1e-6;
    if (rate > kImuMaxYawRate || rate < -kImuMaxYawRate) {
        *reason = "yaw rate beyond +-10 rad/s";
        return false;
    }
    noteCounter(le::getU16(&frame.data[4]), 65536);
    latest_.yawRateRadS = rate;
    latest_.valid = (frame.data[6] & 0x01) != 0;
    latest_.time = now;
    ++latest_.count;
    return true;
}

}  // namespace rse::hal
