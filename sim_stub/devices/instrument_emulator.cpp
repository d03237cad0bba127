#include "sim_stub/devices/instrument_emulator.hpp"

#include <cmath>

namespace rse::sim {

namespace inst = hal::instrument;
using inst::Action;
using inst::Refusal;
using inst::Result;
using inst::State;

InstrumentParams defaultInstrumentParams(inst::Kind kind) {
    InstrumentParams p;
    if (kind == inst::Kind::kCamera) {
        p.reachM = 5.0;
    }
    return p;
}

InstrumentEmulator::InstrumentEmulator(hal::CanBus& bus, const World& world, inst::Kind kind,
                                       const InstrumentParams& params, const std::vector<ScienceTarget>& targets,
                                       std::uint64_t seed, bool pollsBus)
    : DeviceEmulator(bus, inst::idsOf(kind).node, pollsBus),
      world_(world),
      kind_(kind),
      params_(params),
      targets_(targets),
      rng_(seed, kind == inst::Kind::kGrinder ? RngStream::kGrinder : RngStream::kCamera) {}

bool InstrumentEmulator::fail(std::uint8_t faultCode, bool silent) {
    if (faultCode == 0) {
        return false;
    }
    faultCode_ = faultCode;
    silent_ = silent;
    if (state_ == State::kBusy) {
        ++stats_.failed;
        result_ = Result::kAborted;
    }
    state_ = State::kFailed;
    report();
    return true;
}

void InstrumentEmulator::clearFault() {
    if (faultCode_ == 0) {
        return;
    }
    faultCode_ = 0;
    silent_ = false;
    state_ = State::kIdle;
    report();
}

void InstrumentEmulator::onBoot(core::TimeNs now, bool resetApplication) {
    if (resetApplication) {
        // The command in progress is lost with the reset; a fault is hardware and stays.
        rxCount_ = 0;
        state_ = faultCode_ != 0 ? State::kFailed : State::kIdle;
        action_ = Action::kNone;
        target_ = 0;
        commandId_ = 0;
        progress_ = 0;
        result_ = Result::kNone;
        durationNs_ = 0;
    }
    schedule_.start(now + inst::kStatusPeriodNs, inst::kStatusPeriodNs);
    report();
}

void InstrumentEmulator::onDataFrame(const hal::CanFrame& frame) {
    if (frame.id != inst::idsOf(kind_).commandCobId || frame.extended()) {
        return;
    }
    if (rxCount_ >= kInstrumentRxQueue) {
        ++stats_.rxOverflow;
        return;
    }
    rx_[rxCount_++] = frame;
}

void InstrumentEmulator::produce(core::TimeNs now) {
    for (std::size_t i = 0; i < rxCount_; ++i) {
        take(rx_[i], now);
    }
    rxCount_ = 0;
    work(now);
    if (schedule_.take(now, 1, &mutableStats().samplesSkipped) > 0) {
        report();  // a late report is one report
    }
}

void InstrumentEmulator::take(const hal::CanFrame& frame, core::TimeNs now) {
    if (silent_ || nmtState() == hal::canopen::NmtState::kStopped) {
        ++stats_.ignored;
        return;
    }
    inst::Command c;
    Refusal why = Refusal::kNone;
    if (!inst::decodeCommand(frame, &c, &why)) {
        refuse(c, why);
    } else if (faultCode_ != 0) {
        refuse(c, Refusal::kFaulted);
    } else if (c.action == Action::kCancel) {
        if (state_ != State::kBusy || c.commandId != commandId_) {
            refuse(c, Refusal::kNoSuchCommand);
        } else {
            ++stats_.cancelled;
            finish(State::kIdle, Result::kCancelled);
        }
    } else if (c.action == Action::kExtend) {
        if (state_ != State::kBusy || c.extendsCommandId != commandId_ || c.target != target_) {
            refuse(c, Refusal::kNoSuchCommand);
        } else {
            extend(c, now);
        }
    } else if (!inst::doesWork(kind_, c.action)) {
        refuse(c, Refusal::kUnsupportedAction);
    } else if (state_ == State::kBusy) {
        refuse(c, Refusal::kBusy);
    } else if (const ScienceTarget* target = findTarget(c.target); target == nullptr) {
        refuse(c, Refusal::kUnknownTarget);
    } else if (!inReach(*target)) {
        refuse(c, Refusal::kOutOfReach);
    } else {
        accept(c, now);
    }
}

void InstrumentEmulator::accept(const inst::Command& c, core::TimeNs now) {
    ++stats_.accepted;
    state_ = State::kBusy;
    action_ = c.action;
    target_ = c.target;
    commandId_ = c.commandId;
    progress_ = 0;
    result_ = Result::kNone;
    started_ = now;
    const double nominal = nominalS(c.action);
    const double factor = std::fmax(0.1, 1.0 + params_.durationSigma * rng_.gaussian());
    durationNs_ = static_cast<core::TimeNs>(std::llround(nominal * factor * 1e9));
    durationNs_ = durationNs_ > 0 ? durationNs_ : 1;
    maxDurationNs_ = static_cast<core::TimeNs>(c.maxDurationDs) * (core::kNsPerSec / 10);
    report();
}

void InstrumentEmulator::extend(const inst::Command& c, core::TimeNs now) {
    ++stats_.extended;
    commandId_ = c.commandId;
    durationNs_ += static_cast<core::TimeNs>(c.maxDurationDs) * (core::kNsPerSec / 10);
    const auto pct = static_cast<std::int64_t>(100.0 * static_cast<double>(now - started_) /
                                               static_cast<double>(durationNs_));
    progress_ = static_cast<std::uint8_t>(pct < 0 ? 0 : (pct > 99 ? 99 : pct));
    report();
}

void InstrumentEmulator::work(core::TimeNs now) {
    if (state_ != State::kBusy) {
        return;
    }
    const ScienceTarget* target = findTarget(target_);
    const core::TimeNs elapsed = now - started_;
    if (target == nullptr || !inReach(*target)) {
        ++stats_.failed;
        finish(State::kFailed, Result::kOutOfReach);
    } else if (elapsed >= durationNs_) {
        ++stats_.completed;
        finish(State::kDone, Result::kNone);
    } else if (maxDurationNs_ > 0 && elapsed >= maxDurationNs_) {
        ++stats_.failed;
        finish(State::kFailed, Result::kTimedOut);
    } else {
        const auto pct = static_cast<std::int64_t>(100.0 * static_cast<double>(elapsed) / static_cast<double>(durationNs_));
        progress_ = static_cast<std::uint8_t>(pct < 0 ? 0 : (pct > 99 ? 99 : pct));
    }
}

void InstrumentEmulator::finish(State state, Result result) {
    state_ = state;
    result_ = result;
    if (state == State::kDone) {
        progress_ = 100;
    }
    report();
}

void InstrumentEmulator::refuse(const inst::Command& c, Refusal why) {
    ++stats_.refused;
    send(inst::Report{inst::ReportKind::kRefusal, state_, c.action, c.target, c.commandId, 0, Result::kNone, why,
                      faultCode_});
}

void InstrumentEmulator::report() {
    if (silent_ || crashed()) {
        return;
    }
    send(inst::Report{inst::ReportKind::kStatus, state_, action_, target_, commandId_, progress_, result_,
                      Refusal::kNone, faultCode_});
}

void InstrumentEmulator::send(const inst::Report& report) {
    hal::CanFrame f;
    inst::encodeReport(kind_, report, &f);
    sendData(f);
}

const ScienceTarget* InstrumentEmulator::findTarget(std::uint8_t id) const {
    for (const ScienceTarget& t : targets_) {
        if (id != 0 && t.id == id) {
            return &t;
        }
    }
    return nullptr;
}

bool InstrumentEmulator::inReach(const ScienceTarget& target) const {
    const Pose2& pose = world_.truth().pose;
    return norm(target.position - Vec2{pose.x, pose.y}) <= params_.reachM;
}

double InstrumentEmulator::nominalS(Action action) const {
    switch (action) {
        case Action::kSample:
            return params_.sampleS;
        case Action::kDig:
            return params_.digS;
        case Action::kImage:
            return params_.imageS;
        default:
            return 0.0;
    }
}

}  // namespace rse::sim
