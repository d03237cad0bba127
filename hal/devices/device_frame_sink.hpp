// Common front of the RSE (non-CANopen) device clients: every frame is checked
// before it is decoded. Wrong DLC, remote frames and values outside the device's
// documented range are rejected, counted and evented (1st, 2nd, 4th ...), and the
// last good sample is kept. The sensors report events 450 / 451; a device family
// may name its own pair (the science instruments: 452 / 453).
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "hal/canopen/canopen_master.hpp"
#include "hal/devices/device_events.hpp"

namespace rse::hal {

struct DeviceFrameStats {
    std::uint32_t accepted = 0;
    std::uint32_t badLength = 0;  // DLC other than the ICD's
    std::uint32_t badValue = 0;   // a field outside its documented range
    std::uint32_t gaps = 0;       // samples missed, from the device's counter
};

class DeviceFrameSink : public canopen::CanFrameSink {
public:
    void onFrame(const CanFrame& frame, core::TimeNs now) final;
    const DeviceFrameStats& frameStats() const { return stats_; }
    const char* deviceName() const { return name_; }

protected:
    DeviceFrameSink(core::EventLog& events, const char* name, core::EventId badFrameEvent = events::kDeviceBadFrame,
                    core::EventId badValueEvent = events::kDeviceBadValue)
        : events_(events), name_(name), badFrameEvent_(badFrameEvent), badValueEvent_(badValueEvent) {}
    ~DeviceFrameSink() = default;

    // Decodes a frame of the right length; returns false (with a reason) when a
    // value is out of range, in which case nothing is kept.
    virtual bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) = 0;
    // Counts samples skipped between two 8- or 16-bit counters.
    void noteCounter(std::uint32_t counter, std::uint32_t modulus);

private:
    core::EventLog& events_;
    const char* name_;
    core::EventId badFrameEvent_;
    core::EventId badValueEvent_;
    DeviceFrameStats stats_;
    bool haveCounter_ = false;
    std::uint32_t lastCounter_ = 0;
};

}  // namespace rse::hal
