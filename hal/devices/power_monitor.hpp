// Power monitor client (0x6A1): bus voltage and current, state of charge, solar current.
#pragma once

#include "hal/devices/device_frame_sink.hpp"

namespace rse::hal {

struct PowerSample {
    double busVoltageV = 0.0;
    double busCurrentA = 0.0;  // + = discharge
    double stateOfCharge = 0.0;  // 0..1
    double solarCurrentA = 0.0;
    core::TimeNs time = 0;
    std::uint32_t count = 0;
};

class PowerMonitor final : public DeviceFrameSink {
public:
    explicit PowerMonitor(core::EventLog& events) : DeviceFrameSink(events, "power") {}
    const PowerSample& latest() const { return latest_; }

private:
    bool decode(const CanFrame& frame, core::TimeNs now, const char** reason) override;
    PowerSample latest_;
};

}  // namespace rse::hal
