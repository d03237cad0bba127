#include "hal/devices/position_fix.hpp"

#include "hal/canopen/le_codec.hpp"
#include "hal/devices/rse_device_ids.hpp"

namespace rse::hal {

bool PositionFixSource::decode(const CanFrame& frame, core::TimeNs now, const char** reason) {
    if (frame.id == device_ids::kFixX) {
        const std::uint16_t sigmaMm = le::getU16(&frame.data[4]);
        if (sigmaMm == 0) {
            *reason = "zero sigma";
            return false;
        }
        if (haveX_) {
            ++unpaired_;  // the previous x never met its y
        }
        x_ = static_cast<double>(le::getI32(&frame.data[0])) * 1e-3;
        sigma_ = static_cast<double>(sigmaMm) * 1e-3;
        counterX_ = le::getU16(&frame.data[6]);
        haveX_ = true;
    } else {
        const std::int16_t heading = le::getI16(&frame.data[4]);
        if (heading > 31416 || heading < -31416) {
            *reason = "heading beyond +-pi";
            return false;
        }
        if (haveY_) {
            ++unpaired_;
        }
        y_ = static_cast<double>(le::getI32(&frame.data[0])) * 1e-3;
        heading_ = static_cast<double>(heading) * 1e-4;
        counterY_ = le::getU16(&frame.data[6]);
        haveY_ = true;
    }
    completeIfPaired(now);
    return true;
}

void PositionFixSource::completeIfPaired(core::TimeNs now) {
    if (!haveX_ || !haveY_) {
        return;
    }
    if (counterX_ != counterY_) {
        // Halves of different fixes: keep the newer half, drop the older.
        ++unpaired_;
        const bool xIsNewer = static_cast<std::uint16_t>(counterX_ - counterY_) < 0x8000;
        (xIsNewer ? haveY_ : haveX_) = false;
        return;
    }
    noteCounter(counterX_, 65536);
    latest_.xM = x_;
    latest_.yM = y_;
    latest_.headingRad = heading_;
    latest_.sigmaM = sigma_;
    latest_.time = now;
    ++latest_.count;
    haveX_ = haveY_ = false;
}

}  // namespace rse::hal
