// Science instruments (docs/icd.md §1.7; the protocol and its codec:
// hal/devices/instrument_protocol.hpp):
//   grinder/sampler  node 0x24, reports 0x6A5, commands 0x6B5: sample, dig, cancel, extend
//   camera           node 0x25, reports 0x6A6, commands 0x6B6: image, cancel, extend
// One class, parameterised by the instrument. Like the other RSE devices it
// boots, heartbeats every 100 ms and answers NMT (DeviceEmulator).
//
// Commands. A command frame is acted on at the step after it arrives (the
// frames of a step are held, at most kInstrumentRxQueue; more are counted and
// dropped). It is refused with a refusal report naming it when it is malformed,
// the instrument is faulted, the action is not this instrument's, another
// command is running, the target is not one of the scenario's (unknown), or
// the target is farther than reachM from the rover centre (truth). Otherwise it
// runs: a status report says busy at once, then every 100 ms with its progress,
// and at once when it ends:
//   done     after its duration: the nominal time of the action (sample_s,
//            dig_s, image_s) times (1 + durationSigma * N(0, 1)), one draw per
//            command from the instrument's own noise stream, at least 10 % of
//            the nominal;
//   failed   timed out: the command's max duration passed first (0: no limit);
//            out of reach: the rover moved the target beyond reachM meanwhile;
//   idle     cancelled: a cancel naming it (a cancel naming anything else is
//            refused, no such command).
// Extend (a follow-on request) naming the command running, on its target: the
// work goes on for the extra time asked (added to its duration, no new draw),
// under the follow-on's id from then on (the status names it at once); its max
// duration, from the original start, is unchanged, so a follow-on past it times
// out there. An extend naming anything else is refused (no such command).
// Between commands it reports its state every 100 ms: idle, or done / failed
// with the last command.
//
// Faults (scenario: instrument_failure): fail(code) stops the command running
// (result aborted) and the instrument reports failed with the fault code,
// refusing every command (faulted), until clearFault() (idle); fail(code,
// silent) instead sends nothing (no report, no refusal: commands ignored) while
// its heartbeat goes on. A sensor_dropout silences its reports while it keeps
// working; a device_crash silences everything (a restart boots it idle: the
// command in progress is lost, an instrument fault is not: it is hardware). NMT
// stopped: no reports, commands ignored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "hal/devices/instrument_protocol.hpp"
#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

// A point of scientific interest on the site (scenario [[targets]]).
struct ScienceTarget {
    std::uint8_t id = 0;  // 1..255, unique
    Vec2 position;        // map frame, m
};

struct InstrumentParams {
    double sampleS = 150.0;       // grinder: nominal time to grind and collect a sample
    double digS = 240.0;          // grinder: nominal time to dig a trench
    double imageS = 40.0;         // camera: nominal time to take an image
    double durationSigma = 0.05;  // relative 1-sigma of a command's duration, [0, 0.5]
    double reachM = 1.5;          // target within this of the rover centre (the camera's range: 5 m)
};
InstrumentParams defaultInstrumentParams(hal::instrument::Kind kind);

constexpr std::size_t kInstrumentRxQueue = 16;  // command frames held from one step to the next

struct InstrumentStats {
    std::uint32_t accepted = 0;
    std::uint32_t refused = 0;     // refusal reports sent (or due while a dropout silenced them)
    std::uint32_t completed = 0;   // done
    std::uint32_t failed = 0;      // timed out, out of reach, aborted
    std::uint32_t cancelled = 0;
    std::uint32_t extended = 0;    // follow-ons taken (extend)
    std::uint32_t ignored = 0;     // command frames ignored: silent fault, NMT stopped
    std::uint32_t rxOverflow = 0;  // command frames beyond kInstrumentRxQueue in one step
};

class InstrumentEmulator final : public DeviceEmulator {
public:
    InstrumentEmulator(hal::CanBus& bus, const World& world, hal::instrument::Kind kind,
                       const InstrumentParams& params, const std::vector<ScienceTarget>& targets, std::uint64_t seed,
                       bool pollsBus = true);

    // The instrument fails with faultCode (1..255; 0: false, nothing changes).
    bool fail(std::uint8_t faultCode, bool silent);
    // Healthy again: idle, reporting (a no-op when not faulted).
    void clearFault();

    hal::instrument::Kind kind() const { return kind_; }
    hal::instrument::State state() const { return state_; }
    hal::instrument::Result result() const { return result_; }
    std::uint16_t commandId() const { return commandId_; }
    std::uint8_t progressPct() const { return progress_; }
    std::uint8_t faultCode() const { return faultCode_; }
    bool silent() const { return silent_; }
    // The duration drawn for the command running or the last one, s.
    double workDurationS() const { return static_cast<double>(durationNs_) * 1e-9; }
    const InstrumentStats& instrumentStats() const { return stats_; }
    const InstrumentParams& params() const { return params_; }

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;
    void onDataFrame(const hal::CanFrame& frame) override;

    void take(const hal::CanFrame& frame, core::TimeNs now);
    void accept(const hal::instrument::Command& command, core::TimeNs now);
    void extend(const hal::instrument::Command& command, core::TimeNs now);
    void work(core::TimeNs now);
    void finish(hal::instrument::State state, hal::instrument::Result result);
    void refuse(const hal::instrument::Command& command, hal::instrument::Refusal why);
    void report();
    void send(const hal::instrument::Report& report);  // a report, unless stopped or in dropout
    const ScienceTarget* findTarget(std::uint8_t id) const;
    bool inReach(const ScienceTarget& target) const;
    double nominalS(hal::instrument::Action action) const;

    const World& world_;
    const hal::instrument::Kind kind_;
    InstrumentParams params_;
    std::vector<ScienceTarget> targets_;  // copied at construction
    SimRng rng_;
    PeriodicSchedule schedule_;
    hal::CanFrame rx_[kInstrumentRxQueue];
    std::size_t rxCount_ = 0;
    // The command running, or the last one.
    hal::instrument::State state_ = hal::instrument::State::kIdle;
    hal::instrument::Action action_ = hal::instrument::Action::kNone;
    std::uint8_t target_ = 0;
    std::uint16_t commandId_ = 0;
    std::uint8_t progress_ = 0;
    hal::instrument::Result result_ = hal::instrument::Result::kNone;
    core::TimeNs started_ = 0;
    core::TimeNs durationNs_ = 0;
    core::TimeNs maxDurationNs_ = 0;  // 0: no limit
    std::uint8_t faultCode_ = 0;
    bool silent_ = false;
    InstrumentStats stats_;
};

}  // namespace rse::sim
