#include "sim_stub/lockstep/flight_watch.hpp"

#include <bitset>

#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/mission_points.hpp"
#include "sim_stub/lockstep/mission_recorder.hpp"

namespace rse::sim {

namespace {

namespace fp = fault_protection::events;
namespace pe = plan_executive::events;

double seconds(core::TimeNs t) { return static_cast<double>(t) * 1e-9; }

// The health monitor's fault ids by range (fsw/msg/health_msgs.hpp): the raise
// event of each (fsw/estimator/health_events.hpp) and whether the ids are per wheel.
struct FaultRange {
    std::uint8_t first;
    std::size_t count;
    core::EventId raiseEvent;
    bool perWheel;
};
constexpr FaultRange kFaultRanges[] = {
    {msg::fault::kDriveHeartbeatLost, msg::kWheelCount, estimator::events::kHealthDriveHeartbeatLost, true},
    {msg::fault::kDeviceHeartbeatLost, msg::kDeviceNodeCount, estimator::events::kHealthDeviceHeartbeatLost, false},
    {msg::fault::kDriveOvercurrent, msg::kWheelCount, estimator::events::kHealthDriveOvercurrent, true},
    {msg::fault::kBatteryLow, 1, estimator::events::kHealthBatteryLow, false},
    {msg::fault::kBusOvercurrent, 1, estimator::events::kHealthBusOvercurrent, false},
    {msg::fault::kPoseUncertain, 1, estimator::events::kHealthPoseUncertain, false},
    {msg::fault::kTaskStalled, msg::fault::kTaskStalledCount, estimator::events::kHealthTaskStalled, false},
    {msg::fault::kSensorStale, msg::kDeviceNodeCount, estimator::events::kHealthSensorStale, false},
    {msg::fault::kDriveOvertemp, msg::kWheelCount, estimator::events::kHealthDriveOvertemp, true},
    {msg::fault::kOffMap, 1, estimator::events::kHealthOffMap, false},
};

const FaultRange* rangeOf(std::uint8_t faultId) {
    for (const FaultRange& r : kFaultRanges) {
        if (faultId >= r.first && faultId < r.first + r.count) {
            return &r;
        }
    }
    return nullptr;
}

bool isRaiseEvent(core::EventId id) {
    for (const FaultRange& r : kFaultRanges) {
        if (r.raiseEvent == id) {
            return true;
        }
    }
    return false;
}

// The drive a fault id is about (kNoWheel: none).
std::uint8_t wheelOf(std::uint8_t faultId) {
    const FaultRange* r = rangeOf(faultId);
    return r != nullptr && r->perWheel ? static_cast<std::uint8_t>(faultId - r->first) : kNoWheel;
}

bool responseResting(msg::ResponseState s) {
    return s == msg::ResponseState::kIdle || s == msg::ResponseState::kRecovered;
}

bool isRecoveryAction(core::EventId id) {
    return id == fp::kDriveAction || id == fp::kTaskRestart || id == fp::kReplanRequested;
}

}  // namespace

bool FlightWatch::subscribe() {
    bool ok = core::isOk(bus_.createPipe("rse-demo", kPipeDepth, &pipe_));
    const core::MsgId ids[] = {msg::ids::kPlanStatus,    msg::ids::kMode,        msg::ids::kMissionHold,
                               msg::ids::kFaultStatus,   msg::ids::kFaultProtectionStatus,
                               msg::ids::kDriveRecovery, msg::ids::kTaskRestart, msg::ids::kReplanRequest,
                               msg::ids::kPoseEstimate, msg::ids::kPlanExecutiveStatus, msg::ids::kRouteChunk};
    for (core::MsgId id : ids) {
        ok = ok && core::isOk(bus_.subscribe(pipe_, id));
    }
    pending_.reserve(kPipeDepth + msg::fault::kCount);
    return ok;
}

void FlightWatch::drain() {
    while (core::isOk(bus_.receive(pipe_, &inbox_))) {
        if (recorder_ != nullptr) {
            recorder_->onMessage(inbox_);
        }
        onMessage(inbox_);
    }
    core::Event e;
    while (core::isOk(events_.read(&cursor_, &e))) {
        onEvent(e);
    }
    // The telemetry and the events of a frame are read together: what no
    // event of this frame took is not kept for a later one.
    pending_.clear();
}

void FlightWatch::onMessage(const core::Message& m) {
    msg::PlanStatusMsg p{};
    msg::ModeMsg mode{};
    msg::MissionHoldMsg h{};
    msg::FaultStatusMsg f{};
    msg::FaultProtectionStatusMsg fps{};
    msg::DriveRecoveryMsg d{};
    msg::TaskRestartMsg tr{};
    msg::ReplanRequestMsg rr{};
    msg::PlanExecutiveStatusMsg pes{};
    if (m.header.id == msg::ids::kFaultStatus && core::isOk(m.decode(&f))) {
        noteRaises(f);
    } else if (m.header.id == msg::ids::kFaultProtectionStatus && core::isOk(m.decode(&fps))) {
        noteResponses(fps);
    } else if (m.header.id == msg::ids::kDriveRecovery && core::isOk(m.decode(&d))) {
        if (d.action != msg::DriveRecoveryAction::kResetInterlock && d.wheel < msg::kWheelCount) {
            const auto id = static_cast<std::uint8_t>(msg::fault::kDriveHeartbeatLost + d.wheel);
            pending_.push_back(Attribution{fp::kDriveAction, d.timeNs, id, d.wheel});
        }
    } else if (m.header.id == msg::ids::kTaskRestart && core::isOk(m.decode(&tr))) {
        const auto id = static_cast<std::uint8_t>(msg::fault::kTaskStalled + tr.row);
        pending_.push_back(Attribution{fp::kTaskRestart, tr.timeNs, id, kNoWheel});
    } else if (m.header.id == msg::ids::kReplanRequest && core::isOk(m.decode(&rr))) {
        pending_.push_back(Attribution{fp::kReplanRequested, rr.timeNs, rr.faultId, wheelOf(rr.faultId)});
    } else if (m.header.id == msg::ids::kPlanStatus && core::isOk(m.decode(&p))) {
        plan_ = p;
    } else if (m.header.id == msg::ids::kPlanExecutiveStatus && core::isOk(m.decode(&pes))) {
        planExec_ = pes;
    } else if (m.header.id == msg::ids::kMode && core::isOk(m.decode(&mode))) {
        mode_ = mode;
        modeSeen_ = true;
    } else if (m.header.id == msg::ids::kMissionHold && core::isOk(m.decode(&h))) {
        onHold(h);
    }
}

void FlightWatch::onHold(const msg::MissionHoldMsg& h) {
    if (h.reasons != 0 && firstHoldNs_ < 0) {
        firstHoldNs_ = h.timeNs;
    }
    if ((h.reasons != 0) != (hold_.reasons != 0)) {
        mark(h.reasons != 0 ? MarkKind::kHoldSet : MarkKind::kHoldReleased, 0, h.timeNs);
    }
    if (h.resumeCount != hold_.resumeCount) {
        lastResumeNs_ = h.timeNs;
    }
    hold_ = h;
}

void FlightWatch::onEvent(const core::Event& e) {
    if (e.id == pe::kUploadRefused || e.id == pe::kParseRefused || e.id == pe::kSelectionRefused) {
        planRefusal_ = e.text;
    }
    if (e.id == deliberative::events::kCallHome || e.id == fp::kCallHome || e.id == fp::kGaveUp ||
        e.id == pe::kOperatorCalled) {
        // A give-up says why; fault protection's call home (941) follows it.
        if (e.id != fp::kCallHome || callHomeText_.empty()) {
            callHomeText_ = e.text;
        }
    }
    fpCalledHome_ = fpCalledHome_ || e.id == fp::kCallHome;
    if (e.id == fp::kResponseStarted) {
        ++responses_;
        firstResponseNs_ = firstResponseNs_ < 0 ? e.time : firstResponseNs_;
    }
    if (isRaiseEvent(e.id)) {
        markAttributed(MarkKind::kFaultRaised, e);
    } else if (e.id == fp::kResponseStarted) {
        markAttributed(MarkKind::kResponseStarted, e);
    } else if (isRecoveryAction(e.id)) {
        markAttributed(MarkKind::kRecoveryAction, e);
    } else if (e.id == fp::kGaveUp) {
        mark(MarkKind::kGaveUp, e.id, e.time);
    }
    recovered_ += e.id == fp::kRecovered ? 1 : 0;
    gaveUp_ += e.id == fp::kGaveUp ? 1 : 0;
    actions_ += isRecoveryAction(e.id) ? 1U : 0U;
}

void FlightWatch::fill(MissionSummary* s) const {
    s->faultProtectionCalledHome = fpCalledHome_;
    s->responsesStarted = responses_;
    s->responsesRecovered = recovered_;
    s->responsesGaveUp = gaveUp_;
    s->recoveryActions = actions_;
    s->holdsReleased = hold_.resumeCount;
    s->firstResponseTimeS = firstResponseNs_ < 0 ? -1.0 : seconds(firstResponseNs_);
    s->firstHoldTimeS = firstHoldNs_ < 0 ? -1.0 : seconds(firstHoldNs_);
    s->lastResumeTimeS = lastResumeNs_ < 0 ? -1.0 : seconds(lastResumeNs_);
    s->marks = marks_;
    s->markCount = markCount_;
    s->marksDropped = marksDropped_;
    s->marksUnattributed = unattributed_;
}

std::string FlightWatch::callHomeText() const { return ground::callHomeWords(callHomeText_); }

bool FlightWatch::ended(bool planMission) const {
    if (planMission) {
        return planExec_.state == msg::PlanExecutiveState::kComplete ||
               planExec_.state == msg::PlanExecutiveState::kFailed || fpCalledHome_;
    }
    return plan_.state == msg::DeliberativeState::kComplete || plan_.state == msg::DeliberativeState::kCalledHome ||
           fpCalledHome_;
}

// The fault ids newly active: one raise event each, in the health monitor's
// order within a raise event (ascending ids). When the raise count does not
// add up (a status missed), none is named.
void FlightWatch::noteRaises(const msg::FaultStatusMsg& f) {
    const std::uint64_t raised = f.activeMask & ~activeFaults_;
    if (std::bitset<64>(raised).count() == f.raisedTotal - raisedTotal_) {
        for (std::uint8_t id = 1; id < msg::fault::kCount; ++id) {
            const FaultRange* r = rangeOf(id);
            if (((raised >> id) & 1U) != 0 && r != nullptr) {
                pending_.push_back(Attribution{r->raiseEvent, f.timeNs, id, wheelOf(id)});
            }
        }
    }
    activeFaults_ = f.activeMask;
    raisedTotal_ = f.raisedTotal;
}

// The responses newly active (resting before, settling, waiting or given up
// now): one event 930 each, in the status's order (wheels, then fault ids),
// which is the order fault protection starts them in. A list cut at
// kResponseSlots keeps the unlisted ones as they were, and names only the
// starts it lists: the first ones in that order (the events after them stay
// unattributed). When the count of starts does not add up otherwise, none is
// named.
void FlightWatch::noteResponses(const msg::FaultProtectionStatusMsg& s) {
    const bool cut = s.activeCount >= msg::kResponseSlots;
    std::array<msg::ResponseState, msg::fault::kCount> now{};
    if (cut) {
        now = responseState_;
    }
    std::uint8_t started[msg::kResponseSlots] = {};
    std::size_t startedCount = 0;
    for (std::size_t i = 0; i < s.activeCount && i < msg::kResponseSlots; ++i) {
        const msg::ResponseTlm& r = s.responses[i];
        if (r.faultId == 0 || r.faultId >= msg::fault::kCount) {
            continue;
        }
        now[r.faultId] = r.state;
        if (responseResting(responseState_[r.faultId]) && !responseResting(r.state)) {
            started[startedCount++] = r.faultId;
        }
    }
    const std::uint32_t starts = s.responsesStarted - responsesStartedTlm_;
    if (startedCount == starts || (cut && startedCount < starts)) {
        for (std::size_t i = 0; i < startedCount; ++i) {
            pending_.push_back(Attribution{fp::kResponseStarted, s.timeNs, started[i], wheelOf(started[i])});
        }
    }
    responseState_ = now;
    responsesStartedTlm_ = s.responsesStarted;
}

void FlightWatch::markAttributed(MarkKind kind, const core::Event& e) {
    for (auto it = pending_.begin(); it != pending_.end(); ++it) {
        if (it->eventId == e.id && it->timeNs == e.time) {
            mark(kind, e.id, e.time, it->faultId, it->wheel);
            pending_.erase(it);
            return;
        }
    }
    ++unattributed_;
    mark(kind, e.id, e.time);
}

void FlightWatch::mark(MarkKind kind, std::uint16_t id, core::TimeNs t, std::uint8_t faultId, std::uint8_t wheel) {
    if (markCount_ < marks_.size()) {
        marks_[markCount_++] = MissionMark{kind, id, seconds(t), faultId, wheel};
    } else {
        ++marksDropped_;
    }
}

}  // namespace rse::sim
