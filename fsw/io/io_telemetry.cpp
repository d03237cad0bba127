#include "fsw/io/io_telemetry.hpp"

namespace rse::io {

core::Status DrivesTelemetry::routeInputs(core::InputPipe& pipe) {
    core::Status status = pipe.route<&DrivesTelemetry::takeDrives>(this);
    if (core::isOk(status)) {
        status = pipe.route<&DrivesTelemetry::takeWheelCommand>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&DrivesTelemetry::takeMode>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&DrivesTelemetry::takeContact>(this);
    }
    if (core::isOk(status)) {
        status = pipe.route<&DrivesTelemetry::takeFollowerStatus>(this);
    }
    return status;
}

void DrivesTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot != kDrivesSlot) {
        return;
    }
    cmdtlm::DRIVES_Tlm tlm{};
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        const msg::WheelStatus& w = drives_.wheels[i];
        tlm.state[i] = static_cast<std::uint8_t>(w.health);
        tlm.speed[i] = static_cast<float>(w.velocityRadS);
        tlm.commanded[i] = static_cast<float>(wheelCommand_.velocityRadS[i]);
        tlm.current[i] = static_cast<float>(w.currentA);
        tlm.last_emcy[i] = w.lastEmcyCode;
    }
    tlm.interlock = drives_.interlockTripped;
    tlm.estop = mode_.estop;
    tlm.contacts = contact_.contacts;
    tlm.last_contact_x = static_cast<float>(contact_.xM);
    tlm.last_contact_y = static_cast<float>(contact_.yM);
    tlm.last_contact_current = static_cast<float>(contact_.maxCurrentA);
    tlm.last_contact_wheels = contact_.wheelsPushing;
    tlm.contacts_unplaced = follower_.contactsUnplaced;
    tlm.backoffs = follower_.backoffs;
    tlm.backoffs_cut = follower_.backoffsCut;
    tlm.last_backoff_end = follower_.lastBackoffEnd;
    tlm.wheel_readings_not_finite = follower_.wheelReadingsNotFinite;
    sink.send(tlm);
}

core::Status InstrumentsTelemetry::takeStatus(const msg::InstrumentStatusMsg& m) {
    const auto i = static_cast<std::size_t>(m.instrument);
    if (i >= msg::kInstrumentCount) {
        return core::Status::kInvalidArgument;  // names no instrument
    }
    const msg::InstrumentStatusMsg& before = instruments_[i];
    changed_ = changed_ || m.state != before.state || m.commandId != before.commandId ||
               m.result != before.result || m.faultCode != before.faultCode ||
               m.lastRefusal != before.lastRefusal || m.lastRefusedCommandId != before.lastRefusedCommandId;
    instruments_[i] = m;
    return core::Status::kOk;
}

void InstrumentsTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot != kInstrumentsSlot && !changed_) {
        return;
    }
    changed_ = false;
    cmdtlm::INSTRUMENTS_Tlm tlm{};
    for (std::size_t i = 0; i < msg::kInstrumentCount; ++i) {
        const msg::InstrumentStatusMsg& m = instruments_[i];
        tlm.state[i] = static_cast<std::uint8_t>(m.state);
        tlm.action[i] = static_cast<std::uint8_t>(m.action);
        tlm.target[i] = m.targetId;
        tlm.command_id[i] = m.commandId;
        tlm.progress[i] = m.progressPct;
        tlm.result[i] = static_cast<std::uint8_t>(m.result);
        tlm.fault_code[i] = m.faultCode;
        tlm.last_refusal[i] = static_cast<std::uint8_t>(m.lastRefusal);
        tlm.last_refused_command[i] = m.lastRefusedCommandId;
        tlm.last_report[i] =
            static_cast<float>(static_cast<double>(m.lastReportNs) / static_cast<double>(core::kNsPerSec));
        tlm.commands_sent[i] = m.commandsSent;
        tlm.commands_accepted[i] = m.commandsAccepted;
        tlm.commands_refused[i] = m.commandsRefused;
        tlm.commands_not_sent[i] = m.commandsNotSent;
        tlm.frames_bad[i] = m.framesBad;
        tlm.offline_count[i] = m.offlineCount;
    }
    sink.send(tlm);
}

core::Status PowerTelemetry::routeInputs(core::InputPipe& pipe) {
    core::Status status = pipe.route<&PowerTelemetry::takeDrives>(this);
    if (core::isOk(status)) {
        status = pipe.route<&PowerTelemetry::takePower>(this);
    }
    return status;
}

void PowerTelemetry::pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) {
    if (frame.slot != kPowerSlot) {
        return;
    }
    cmdtlm::POWER_Tlm tlm{};
    tlm.battery_voltage = static_cast<float>(power_.busVoltageV);
    tlm.battery_current = static_cast<float>(power_.busCurrentA);
    tlm.state_of_charge = static_cast<float>(power_.stateOfCharge);
    tlm.solar_current = static_cast<float>(power_.solarCurrentA);
    tlm.power_sample_time =
        static_cast<float>(static_cast<double>(power_.timeNs) / static_cast<double>(core::kNsPerSec));
    static_assert(sizeof tlm.motor_temperature / sizeof tlm.motor_temperature[0] == msg::kWheelCount,
                  "POWER holds every wheel");
    for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
        const msg::WheelStatus& w = drives_.wheels[i];
        tlm.temperature_valid[i] = w.temperatureValid != 0 ? 1 : 0;
        tlm.motor_temperature[i] = w.temperatureValid != 0 ? w.temperatureC : 0.0F;
    }
    sink.send(tlm);
}

}  // namespace rse::io
