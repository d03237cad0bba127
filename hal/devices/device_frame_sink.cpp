#include "hal/devices/device_frame_sink.hpp"

namespace rse::hal {

using core::Severity;

void DeviceFrameSink::onFrame(const CanFrame& frame, core::TimeNs now) {
    if (frame.dlc != 8 || frame.remote()) {
        ++stats_.badLength;
        if (core::isReportableOccurrence(stats_.badLength)) {
            events_.report(badFrameEvent_, Severity::kWarning,
                           "%s: frame 0x%03X with dlc %u rejected (%u so far)", name_, static_cast<unsigned>(frame.id),
                           static_cast<unsigned>(frame.dlc), static_cast<unsigned>(stats_.badLength));
        }
        return;
    }
    const char* reason = "out of range";
    if (!decode(frame, now, &reason)) {
        ++stats_.badValue;
        if (core::isReportableOccurrence(stats_.badValue)) {
            events_.report(badValueEvent_, Severity::kWarning, "%s: frame 0x%03X rejected: %s (%u so far)",
                           name_, static_cast<unsigned>(frame.id), reason, static_cast<unsigned>(stats_.badValue));
        }
        return;
    }
    ++stats_.accepted;
}

void DeviceFrameSink::noteCounter(std::uint32_t counter, std::uint32_t modulus) {
    if (haveCounter_) {
        const std::uint32_t step = (counter + modulus - lastCounter_) % modulus;
        if (step > 1) {
            stats_.gaps += step - 1;
        }
    }
    haveCounter_ = true;
    lastCounter_ = counter;
}

}  // namespace rse::hal
