// Position-fix client (0x6A3 x and sigma, 0x6A4 y and heading): a fix is complete
// when both halves with the same fix counter have arrived, in either order.
#pragma once

#include "hal/devices/device_frame_sink.hpp"

namespace rse::hal {

struct PositionFix {
    double xM = 0.0;
    double yM = 0.0;
    double headingRad = 0.0;
    double sigmaM = 0.0;  // the source's 1-sigma position accuracy
    core::TimeNs time = 0;
    std::uint32_t count = 0;  // complete fixes
};

class PositionFixSource final : public DeviceFrameSink {
public:
    explicit PositionFixSource(core::EventLog& events) : DeviceFrameSink(events, "position-fix") {}
    const PositionFix& latest() const { return latest_; }
    std::uint32_t unpaired() const { return unpaired_; }  // halves whose partner never came

private:
    bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) override;
    void completeIfPaired(core::TimeNs now);

    PositionFix latest_;
    bool haveX_ = false, haveY_ = false;
    std::uint16_t counterX_ = 0, counterY_ = 0;
    double x_ = 0.0, y_ = 0.0, heading_ = 0.0, sigma_ = 0.0;
    std::uint32_t unpaired_ = 0;
};

}  // namespace rse::hal
