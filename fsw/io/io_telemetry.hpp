// The packets of the hardware CAN I/O drives (docs/icd.md §5.5), packed from
// what it publishes; three telemetry packers (cmdtlm/telemetry_packer.hpp),
// each scheduled in its own place of the frame's packet order:
//   DRIVES       slot kDrivesSlot of every second: each drive's state, speed,
//                current and last EMCY (DriveStatusMsg), the speed commanded
//                (WheelCommandMsg), the interlock, the software e-stop (ModeMsg),
//                and the contacts the follower felt (ContactMsg: count, the last one)
//   INSTRUMENTS  slot kInstrumentsSlot of every second, and in the run after an
//                instrument's state, command, result, fault code or last
//                refusal changed (not its progress) (InstrumentStatusMsg, one
//                per instrument; one naming no instrument is refused, counted
//                by the pipe)
//   POWER        slot kPowerSlot of every second: the battery and solar
//                (PowerMsg) and every motor's temperature (DriveStatusMsg)
#pragma once

#include <cstdint>

#include "fsw/cmdtlm/telemetry_packer.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"

namespace rse::io {

constexpr std::uint32_t kDrivesSlot = 50;
constexpr std::uint32_t kInstrumentsSlot = 90;
constexpr std::uint32_t kPowerSlot = 30;

class DrivesTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override;
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    void takeDrives(const msg::DriveStatusMsg& drives) { drives_ = drives; }
    void takeWheelCommand(const msg::WheelCommandMsg& command) { wheelCommand_ = command; }
    void takeMode(const msg::ModeMsg& mode) { mode_ = mode; }
    void takeContact(const msg::ContactMsg& contact) { contact_ = contact; }
    void takeFollowerStatus(const msg::FollowerStatusMsg& status) { follower_ = status; }

    msg::DriveStatusMsg drives_{};
    msg::WheelCommandMsg wheelCommand_{};
    msg::ModeMsg mode_{};
    msg::ContactMsg contact_{};
    msg::FollowerStatusMsg follower_{};
};

class InstrumentsTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override {
        return pipe.route<&InstrumentsTelemetry::takeStatus>(this);
    }
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    core::Status takeStatus(const msg::InstrumentStatusMsg& status);

    msg::InstrumentStatusMsg instruments_[msg::kInstrumentCount] = {};
    bool changed_ = false;  // INSTRUMENTS goes in the next run
};

class PowerTelemetry final : public cmdtlm::TelemetryPacker {
public:
    core::Status routeInputs(core::InputPipe& pipe) override;
    void pack(const core::FrameContext& frame, cmdtlm::TelemetrySink& sink) override;

private:
    void takeDrives(const msg::DriveStatusMsg& drives) { drives_ = drives; }
    void takePower(const msg::PowerMsg& power) { power_ = power; }

    msg::DriveStatusMsg drives_{};
    msg::PowerMsg power_{};
};

}  // namespace rse::io
