#include "hal/devices/power_monitor.hpp"

#include "hal/canopen/le_codec.hpp"

namespace rse::hal {

bool PowerMonitor::decode(const CanFrame& frame, core::TimeNs now, const char** reason) {
    const std::uint16_t soc = le::getU16(&frame.data[4]);
    if (soc > 10000) {
        *reason = "state of charge above 100 %";
        return false;
    }
    latest_.busVoltageV = static_cast<double>(le::getU16(&frame.data[0])) * 1e-3;
    latest_.busCurrentA = static_cast<double>(le::getI16(&frame.data[2])) * 1e-3;
    latest_.stateOfCharge = static_cast<double>(soc) * 1e-4;
    latest_.solarCurrentA = static_cast<double>(le::getU16(&frame.data[6])) * 1e-3;
    latest_.time = now;
    ++latest_.count;
    return true;
}

}  // namespace rse::hal
