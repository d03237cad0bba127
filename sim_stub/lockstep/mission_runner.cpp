#include "sim_stub/lockstep/mission_runner.hpp"

#include <arpa/inet.h>

#include <algorithm>
#include <bitset>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <sstream>
#include <thread>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/estimator/health_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/command_encoder.hpp"
#include "ground/mission_points.hpp"
#include "ground/mission_report.hpp"
#include "ground/plan_transfer.hpp"
#include "hal/link/udp_packet_link.hpp"
#include "sim_stub/lockstep/lockstep_rig.hpp"
#include "sim_stub/lockstep/map_upload.hpp"
#include "sim_stub/lockstep/mission_recorder.hpp"
#include "sim_stub/lockstep/memory_ground.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim {

namespace {

constexpr core::TimeNs kDrivesUpLimitNs = 3 * core::kNsPerSec;
constexpr core::TimeNs kModeAckLimitNs = core::kNsPerSec;

double seconds(core::TimeNs t) { return static_cast<double>(t) * 1e-9; }

// A whole string as a finite number.
bool parseNumber(const std::string& text, double* value) {
    if (text.empty()) {
        return false;
    }
    char* end = nullptr;
    *value = std::strtod(text.c_str(), &end);
    return *end == '\0' && std::isfinite(*value);
}

// name=value for the ground's encoder: the shortest text that reads back as v.
std::string argument(const char* name, double v) {
    char text[40];
    for (int digits = 15; digits <= 17; ++digits) {
        std::snprintf(text, sizeof text, "%.*g", digits, v);
        if (std::strtod(text, nullptr) == v) {
            break;
        }
    }
    return std::string(name) + "=" + text;
}

// GOTO x, y, risk into the options, checked against the dictionary's ranges
// by the ground's encoder (*error: its reason).
bool encodeGoto(double x, double y, double risk, MissionOptions* o, std::string* error) {
    try {
        o->gotoArgs = ground::encodeArguments(*ground::lookupCommand("GOTO"),
                                              {argument("x", x), argument("y", y), argument("risk", risk)});
    } catch (const ground::CommandError& e) {
        *error = e.what();
        return false;
    }
    o->goalX = x;
    o->goalY = y;
    o->risk = risk;
    return true;
}

// "X,Y[,RISK]" into the options, checked against the dictionary's GOTO ranges.
bool parseGoto(const std::string& text, MissionOptions* o, std::string* error) {
    std::vector<std::string> fields;
    std::size_t start = 0;
    for (std::size_t comma = text.find(','); comma != std::string::npos; comma = text.find(',', start)) {
        fields.push_back(text.substr(start, comma - start));
        start = comma + 1;
    }
    fields.push_back(text.substr(start));
    if (fields.size() < 2 || fields.size() > 3) {
        *error = "--goto '" + text + "': expected X,Y or X,Y,RISK";
        return false;
    }
    if (fields.size() == 2) {
        fields.push_back("1e-3");
    }
    double v[3] = {};
    for (std::size_t i = 0; i < 3; ++i) {
        if (!parseNumber(fields[i], &v[i])) {
            *error = "--goto '" + text + "': '" + fields[i] + "' is not a number";
            return false;
        }
    }
    if (!encodeGoto(v[0], v[1], v[2], o, error)) {
        *error = "--goto '" + text + "': " + *error;
        return false;
    }
    return true;
}

// A UDP port, 1..65535, as a whole number.
bool parsePort(const std::string& text, std::uint16_t* port) {
    if (text.empty() || text.size() > 5 || text.find_first_not_of("0123456789") != std::string::npos) {
        return false;
    }
    const unsigned long value = std::strtoul(text.c_str(), nullptr, 10);
    if (value == 0 || value > 65535) {
        return false;
    }
    *port = static_cast<std::uint16_t>(value);
    return true;
}

// A numeric IPv4 address, as hal::UdpPacketLink takes it (it looks up no names).
bool isIpv4(const std::string& text) {
    in_addr parsed{};
    return inet_pton(AF_INET, text.c_str(), &parsed) == 1;
}

// "HOST:PORT" (or, hostOptional, "PORT" alone: *host left as it is) for the
// option `option`; *error says what is wrong.
bool parseUdpAddress(const std::string& option, const std::string& text, bool hostOptional, std::string* host,
                     std::uint16_t* port, std::string* error) {
    const std::size_t colon = text.rfind(':');
    if (colon == std::string::npos && !hostOptional) {
        *error = option + " '" + text + "': expected HOST:PORT (e.g. 127.0.0.1:1235)";
        return false;
    }
    const std::string address = colon == std::string::npos ? *host : text.substr(0, colon);
    const std::string number = colon == std::string::npos ? text : text.substr(colon + 1);
    if (!isIpv4(address)) {
        *error = option + " '" + text + "': '" + address + "' is not a numeric IPv4 address (no names are looked up)";
        return false;
    }
    if (!parsePort(number, port)) {
        *error = option + " '" + text + "': '" + number + "' is not a port in 1..65535";
        return false;
    }
    *host = address;
    return true;
}

// --pace: frame k of the run is due at wall time start + k x period / factor,
// the start being the first frame paced. Each frame is waited for, not each
// period: lateness in one frame does not shift the later ones, so a machine that
// falls behind (a planner's long frame, a factor beyond what it can run) runs
// the frames that are due at once until it has caught up; those are counted
// with the latest one's lateness. Factor 0: no pacing.
class FramePacer {
public:
    explicit FramePacer(double factor) : factor_(factor) {}
    // Before `frame` runs (the executive's next frame); called again for the
    // same frame, it does nothing.
    void beforeFrame(std::uint64_t frame) {
        using Clock = std::chrono::steady_clock;
        if (!(factor_ > 0.0) || (started_ && frame == lastFrame_)) {
            return;
        }
        const Clock::time_point now = Clock::now();
        if (!started_) {
            started_ = true;
            firstFrame_ = frame;
            start_ = now;
        }
        lastFrame_ = frame;
        ++frames_;
        const double dueS = static_cast<double>(frame - firstFrame_) * seconds(app::kMinorFramePeriod) / factor_;
        const Clock::time_point due =
            start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dueS));
        if (now < due) {
            std::this_thread::sleep_until(due);
        } else if (now > due) {
            ++behind_;
            behindMaxMs_ = std::max(behindMaxMs_, std::chrono::duration<double, std::milli>(now - due).count());
        }
    }
    void fill(MissionSummary* s) const {
        s->pace = factor_;
        s->pacedFrames = frames_;
        s->framesBehind = behind_;
        s->behindMaxMs = behindMaxMs_;
    }

private:
    double factor_;
    bool started_ = false;
    std::uint64_t firstFrame_ = 0;
    std::uint64_t lastFrame_ = 0;
    std::chrono::steady_clock::time_point start_{};
    std::uint64_t frames_ = 0;
    std::uint64_t behind_ = 0;
    double behindMaxMs_ = 0.0;
};

const char* stateName(msg::DeliberativeState s) {
    switch (s) {
        case msg::DeliberativeState::kIdle: return "IDLE";
        case msg::DeliberativeState::kWaiting: return "WAITING";
        case msg::DeliberativeState::kPlanning: return "PLANNING";
        case msg::DeliberativeState::kExecuting: return "EXECUTING";
        case msg::DeliberativeState::kCalledHome: return "CALLED HOME";
        case msg::DeliberativeState::kComplete: return "COMPLETE";
    }
    return "?";
}

const char* modeName(std::uint8_t mode) {
    return mode < cmdtlm::kModeCount ? cmdtlm::toString(static_cast<cmdtlm::Mode>(mode)) : "?";
}

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

// What the operator sees of the flight software: its published plan status
// and mode (a pipe on the software bus) and its events (a reader of its own on
// the event log), read once per frame; nothing is sent. The fault status, fault
// protection's status and its requests (drive recovery, task restart, replan)
// on the same pipe name the fault of each raise, response and action mark
// (MissionMark::faultId, wheel): each is published in the frame of its event.
class FlightWatch {
public:
    FlightWatch(core::SoftwareBus& bus, const core::EventLog& events) : bus_(bus), events_(events) {}
    bool subscribe() {
        bool ok = core::isOk(bus_.createPipe("rse-demo", kPipeDepth, &pipe_));
        const core::MsgId ids[] = {msg::ids::kPlanStatus,    msg::ids::kMode,        msg::ids::kMissionHold,
                                   msg::ids::kFaultStatus,   msg::ids::kFaultProtectionStatus,
                                   msg::ids::kDriveRecovery, msg::ids::kTaskRestart, msg::ids::kReplanRequest,
                                   msg::ids::kPoseEstimate, msg::ids::kPlanExecutiveStatus};
        for (core::MsgId id : ids) {
            ok = ok && core::isOk(bus_.subscribe(pipe_, id));
        }
        pending_.reserve(kPipeDepth + msg::fault::kCount);
        return ok;
    }
    // Every message read is also handed to the mission recorder (the bus has
    // no slots left for a pipe of its own).
    void forwardTo(MissionRecorder* recorder) { recorder_ = recorder; }
    void drain() {
        while (core::isOk(bus_.receive(pipe_, &inbox_))) {
            if (recorder_ != nullptr) {
                recorder_->onMessage(inbox_);
            }
            msg::PlanStatusMsg p{};
            msg::ModeMsg m{};
            msg::MissionHoldMsg h{};
            msg::FaultStatusMsg f{};
            msg::FaultProtectionStatusMsg fps{};
            msg::DriveRecoveryMsg d{};
            msg::TaskRestartMsg tr{};
            msg::ReplanRequestMsg rr{};
            msg::PlanExecutiveStatusMsg pe{};
            namespace fp = fault_protection::events;
            if (inbox_.header.id == msg::ids::kFaultStatus && core::isOk(inbox_.decode(&f))) {
                noteRaises(f);
            } else if (inbox_.header.id == msg::ids::kFaultProtectionStatus && core::isOk(inbox_.decode(&fps))) {
                noteResponses(fps);
            } else if (inbox_.header.id == msg::ids::kDriveRecovery && core::isOk(inbox_.decode(&d))) {
                if (d.action != msg::DriveRecoveryAction::kResetInterlock && d.wheel < msg::kWheelCount) {
                    const auto id = static_cast<std::uint8_t>(msg::fault::kDriveHeartbeatLost + d.wheel);
                    pending_.push_back(Attribution{fp::kDriveAction, d.timeNs, id, d.wheel});
                }
            } else if (inbox_.header.id == msg::ids::kTaskRestart && core::isOk(inbox_.decode(&tr))) {
                const auto id = static_cast<std::uint8_t>(msg::fault::kTaskStalled + tr.row);
                pending_.push_back(Attribution{fp::kTaskRestart, tr.timeNs, id, kNoWheel});
            } else if (inbox_.header.id == msg::ids::kReplanRequest && core::isOk(inbox_.decode(&rr))) {
                pending_.push_back(Attribution{fp::kReplanRequested, rr.timeNs, rr.faultId, wheelOf(rr.faultId)});
            } else if (inbox_.header.id == msg::ids::kPlanStatus && core::isOk(inbox_.decode(&p))) {
                plan_ = p;
            } else if (inbox_.header.id == msg::ids::kPlanExecutiveStatus && core::isOk(inbox_.decode(&pe))) {
                planExec_ = pe;
            } else if (inbox_.header.id == msg::ids::kMode && core::isOk(inbox_.decode(&m))) {
                mode_ = m;
                modeSeen_ = true;
            } else if (inbox_.header.id == msg::ids::kMissionHold && core::isOk(inbox_.decode(&h))) {
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
        }
        core::Event e;
        namespace fp = fault_protection::events;
        namespace pe = plan_executive::events;
        while (core::isOk(events_.read(&cursor_, &e))) {
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
        // The telemetry and the events of a frame are read together: what no
        // event of this frame took is not kept for a later one.
        pending_.clear();
    }
    static bool isRecoveryAction(core::EventId id) {
        namespace fp = fault_protection::events;
        return id == fp::kDriveAction || id == fp::kTaskRestart || id == fp::kReplanRequested;
    }
    void fill(MissionSummary* s) const {
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
    bool faultProtectionCalledHome() const { return fpCalledHome_; }
    // The call home in the flight software's words (its CRITICAL event).
    std::string callHomeText() const { return ground::callHomeWords(callHomeText_); }
    const msg::PlanStatusMsg& plan() const { return plan_; }
    // The plan executive's latest status, and the text of its latest refusal (event 952, 953 or 954).
    const msg::PlanExecutiveStatusMsg& planExec() const { return planExec_; }
    const std::string& planRefusal() const { return planRefusal_; }
    bool modeIs(std::uint8_t mode) const { return modeSeen_ && mode_.mode == mode; }
    std::uint8_t mode() const { return mode_.mode; }
    // A goal mission ends with the deliberative layer's goal reached or its
    // call home; a plan mission with the plan complete or no method left
    // (the deliberative layer's call home fails a drive, which the plan may
    // redo); either with fault protection's call home.
    bool ended(bool planMission) const {
        if (planMission) {
            return planExec_.state == msg::PlanExecutiveState::kComplete ||
                   planExec_.state == msg::PlanExecutiveState::kFailed || fpCalledHome_;
        }
        return plan_.state == msg::DeliberativeState::kComplete || plan_.state == msg::DeliberativeState::kCalledHome ||
               fpCalledHome_;
    }

private:
    core::SoftwareBus& bus_;
    const core::EventLog& events_;
    MissionRecorder* recorder_ = nullptr;
    core::EventLog::Cursor cursor_{};
    std::string callHomeText_;
    core::PipeId pipe_ = 0;
    core::Message inbox_{};
    msg::PlanStatusMsg plan_{};
    msg::PlanExecutiveStatusMsg planExec_{};
    std::string planRefusal_;
    msg::ModeMsg mode_{};
    bool modeSeen_ = false;
    msg::MissionHoldMsg hold_{};
    bool fpCalledHome_ = false;
    std::uint32_t responses_ = 0, recovered_ = 0, gaveUp_ = 0, actions_ = 0;
    core::TimeNs firstResponseNs_ = -1, firstHoldNs_ = -1, lastResumeNs_ = -1;
    std::array<MissionMark, kMissionMarks> marks_{};
    std::size_t markCount_ = 0;
    std::size_t marksDropped_ = 0;
    std::size_t unattributed_ = 0;

    // Who the event `eventId` of the frame at timeNs is about, from the
    // telemetry published in that frame; taken by the first such event.
    struct Attribution {
        core::EventId eventId;
        core::TimeNs timeNs;
        std::uint8_t faultId;
        std::uint8_t wheel;
    };
    static constexpr std::uint16_t kPipeDepth = 32;
    std::vector<Attribution> pending_;
    std::uint64_t activeFaults_ = 0;  // FaultStatusMsg last seen
    std::uint32_t raisedTotal_ = 0;
    std::array<msg::ResponseState, msg::fault::kCount> responseState_{};  // by fault id, FaultProtectionStatusMsg last seen
    std::uint32_t responsesStartedTlm_ = 0;

    // The fault ids newly active: one raise event each, in the health
    // monitor's order within a raise event (ascending ids). When the raise
    // count does not add up (a status missed), none is named.
    void noteRaises(const msg::FaultStatusMsg& f) {
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

    // The responses newly active (resting before, settling, waiting or given
    // up now): one event 930 each, in the status's order (wheels, then fault
    // ids), which is the order fault protection starts them in. A list cut at
    // kResponseSlots keeps the unlisted ones as they were, and names only the
    // starts it lists: the first ones in that order (the events after them stay
    // unattributed). When the count of starts does not add up otherwise, none
    // is named.
    void noteResponses(const msg::FaultProtectionStatusMsg& s) {
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
                pending_.push_back(Attribution{fault_protection::events::kResponseStarted, s.timeNs, started[i],
                                               wheelOf(started[i])});
            }
        }
        responseState_ = now;
        responsesStartedTlm_ = s.responsesStarted;
    }

    void markAttributed(MarkKind kind, const core::Event& e) {
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

    void mark(MarkKind kind, std::uint16_t id, core::TimeNs t, std::uint8_t faultId = 0,
              std::uint8_t wheel = kNoWheel) {
        if (markCount_ < marks_.size()) {
            marks_[markCount_++] = MissionMark{kind, id, seconds(t), faultId, wheel};
        } else {
            ++marksDropped_;
        }
    }
};

// The demo's own lines, stamped like the console's.
void say(std::FILE* out, LockstepRig& rig, const std::string& text) {
    if (out != nullptr) {
        std::fprintf(out, "[%10.3f] DEMO %s\n", seconds(rig.clock().now()), text.c_str());
        std::fflush(out);
    }
}

std::string describeScenario(const Scenario& s, const MissionOptions& o) {
    std::size_t hidden = 0;
    for (const Obstacle& ob : s.obstacles) {
        hidden += ob.known ? 0 : 1;
    }
    char line[512];
    char mission[160];
    if (o.planText.empty()) {
        std::snprintf(mission, sizeof mission, "goal (%.2f, %.2f)", o.goalX, o.goalY);
    } else {
        std::snprintf(mission, sizeof mission, "plan %s (%zu B)", o.planFile.c_str(), o.planText.size());
    }
    std::snprintf(line, sizeof line, "scenario %s (%s): start (%.2f, %.2f), %zu rocks (%zu hidden), %s risk bound "
                  "%.3g, up to %.0f s",
                  s.name.c_str(), o.scenarioPath.c_str(), s.start.x, s.start.y, s.obstacles.size(), hidden, mission,
                  o.risk, o.durationS);
    std::string text = line;
    if (o.clearFaults) {
        text += "; faults cleared (--no-faults)";
    } else if (s.faults.empty()) {
        text += "; no faults";
    }
    for (const FaultSpec& f : s.faults) {
        const bool onWheel = f.type == FaultType::kMotorDegradation || f.type == FaultType::kMotorFailure ||
                             f.type == FaultType::kDriveHeartbeatLoss || f.type == FaultType::kDriveCrash;
        if (f.type == FaultType::kTaskStall) {
            const std::string task = f.taskName.empty() ? "row " + std::to_string(f.taskRow) : f.taskName;
            std::snprintf(line, sizeof line, "; fault task_stall of %s at %.1f s", task.c_str(), seconds(f.at));
        } else {
            std::snprintf(line, sizeof line, "; fault %s%s%s at %.1f s", toString(f.type), onWheel ? " on " : "",
                          onWheel && f.wheel < msg::kWheelCount ? msg::wheelName(f.wheel) : "", seconds(f.at));
        }
        text += line;
    }
    return text;
}

// The scenario's task stalls as the operator's commands: each is sent as
// EXEC_SET_TASK through the ground link (MemoryGround), narrated and timed.
class ScheduledTaskCommands final : public FlightTaskCommander {
public:
    ScheduledTaskCommands(MemoryGround& ground, LockstepRig& rig, std::FILE* out)
        : ground_(ground), rig_(rig), out_(out) {}
    bool setFlightTaskEnabled(std::size_t row, const std::string& name, bool enabled) override {
        const bool sent = ground_.setFlightTaskEnabled(row, name, enabled);
        const std::size_t sentRow = ground_.lastTaskRow();
        char line[160];
        if (!sent) {
            std::snprintf(line, sizeof line, "scenario task_stall: EXEC_SET_TASK for %s%s NOT sent (task unknown to "
                          "the ground, or the link full)", name.empty() ? "row " : "", name.empty()
                          ? std::to_string(row).c_str() : name.c_str());
            say(out_, rig_, line);
            return false;
        }
        std::snprintf(line, sizeof line, "ground: EXEC_SET_TASK row=%zu (%s) enabled=%d (scenario task_stall)", sentRow,
                      ground_.task(sentRow).name, enabled ? 1 : 0);
        say(out_, rig_, line);
        if (!enabled && disabledAtS_ < 0.0) {
            disabledAtS_ = seconds(rig_.clock().now());
            row_ = sentRow;
            runsAtDisable_ = ground_.task(sentRow).runs;
        }
        return true;
    }
    void fill(MissionSummary* s) const {
        s->taskStallCommands = ground_.taskCommandsSent();
        s->taskStallTimeS = disabledAtS_;
        if (disabledAtS_ >= 0.0) {
            s->stalledRow = static_cast<int>(row_);
            s->stalledRowRunsAtStall = runsAtDisable_;
            s->stalledRowRunsAtEnd = ground_.task(row_).runs;
        }
    }

private:
    MemoryGround& ground_;
    LockstepRig& rig_;
    std::FILE* out_;
    double disabledAtS_ = -1.0;
    std::size_t row_ = 0;
    std::uint32_t runsAtDisable_ = 0;
};

const char* planStateName(msg::PlanExecutiveState s) {
    switch (s) {
        case msg::PlanExecutiveState::kIdle: return "idle";
        case msg::PlanExecutiveState::kSelecting: return "selecting";
        case msg::PlanExecutiveState::kDispatching: return "dispatching";
        case msg::PlanExecutiveState::kRegenerating: return "regenerating";
        case msg::PlanExecutiveState::kComplete: return "complete";
        case msg::PlanExecutiveState::kFailed: return "failed";
    }
    return "?";
}

std::string planName(const msg::PlanExecutiveStatusMsg& s) {
    return std::string(s.planName, strnlen(s.planName, sizeof s.planName));
}

// A plan mission's plan, checked on the ground before anything is sent, as
// `rse-ground plan load` does: its size, the flight parser and method
// selection with every component ok. False with the reason in *error.
bool planPassesGroundCheck(const MissionOptions& o, std::string* error) {
    std::ostringstream checkOut;
    std::ostringstream checkErr;
    const auto components = std::make_unique<plan_executive::SelectionInput>();
    if (ground::checkPlanForUplink(o.planText, o.planFile, ground::kPlanUploadBytes, *components, false, checkOut,
                                   checkErr) != 0) {
        *error = "the plan did not pass the ground check: " + checkErr.str();
        return false;
    }
    return true;
}

// A plan mission's uplink, as `rse-ground plan load` does it once the plan
// passed the ground's check: the operator's risk bound (SET_RISK_BOUND: the
// one the plan's drives get), PLAN_LOAD chunks (one every 20 ms: at most one a
// frame, a few between two runs of the executive), PLAN_START with the text's
// length and CRC-32, and the executive's verdict. False with the reason in
// *error.
bool uplinkPlan(const MissionOptions& o, MemoryGround& ground, LockstepRig& rig, const FlightWatch& watch,
                const std::function<void()>& service, std::string* error) {
    std::vector<std::uint8_t> risk;
    try {
        risk = ground::encodeArguments(*ground::lookupCommand("SET_RISK_BOUND"), {argument("risk", o.risk)});
    } catch (const ground::CommandError& e) {
        *error = e.what();
        return false;
    }
    const std::uint32_t accepted = watch.planExec().plansAccepted;
    const std::uint32_t refused = watch.planExec().plansRefused;
    const auto step = [&](core::TimeNs t) { (void)rig.runUntil([&] { service(); return false; }, t); };
    if (!ground.send("SET_RISK_BOUND", risk.data(), risk.size())) {
        *error = "SET_RISK_BOUND could not be sent";
        return false;
    }
    step(20 * core::kNsPerMs);
    for (const std::vector<std::uint8_t>& chunk : ground::planLoadChunks(o.planText)) {
        if (!ground.send("PLAN_LOAD", chunk.data(), chunk.size())) {
            *error = "PLAN_LOAD could not be sent";
            return false;
        }
        step(20 * core::kNsPerMs);
    }
    const std::vector<std::uint8_t> start = ground::planStartArgs(o.planText);
    if (!ground.send("PLAN_START", start.data(), start.size())) {
        *error = "PLAN_START could not be sent";
        return false;
    }
    const auto verdict = static_cast<core::TimeNs>(ground::kPlanVerdictSeconds * 1e9);
    (void)rig.runUntil(
        [&] {
            service();
            return watch.planExec().plansAccepted != accepted || watch.planExec().plansRefused != refused;
        },
        verdict);
    if (watch.planExec().plansRefused != refused) {
        *error = "the plan executive refused the plan: " + watch.planRefusal();
        return false;
    }
    if (watch.planExec().plansAccepted == accepted) {
        char why[80];
        std::snprintf(why, sizeof why, "no verdict from the plan executive within %.0f s", ground::kPlanVerdictSeconds);
        *error = why;
        return false;
    }
    return true;
}

MissionSummary setupFailed(MissionSummary summary, const std::string& why) {
    summary.outcome = MissionOutcome::kSetupFailed;
    summary.setupError = why;
    return summary;
}

}  // namespace

const MissionMark* MissionSummary::firstMark(MarkKind kind, double timeS) const {
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].kind == kind && marks[i].timeS >= timeS) {
            return &marks[i];
        }
    }
    return nullptr;
}

const MissionMark* MissionSummary::firstMark(MarkKind kind, double timeS, std::uint8_t faultId) const {
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].kind == kind && marks[i].timeS >= timeS && marks[i].faultId == faultId) {
            return &marks[i];
        }
    }
    return nullptr;
}

std::size_t MissionSummary::countMarks(MarkKind kind, std::uint8_t faultId) const {
    std::size_t n = 0;
    for (std::size_t i = 0; i < markCount; ++i) {
        n += marks[i].kind == kind && marks[i].faultId == faultId ? 1U : 0U;
    }
    return n;
}

bool MissionSummary::heldBefore(double timeS) const {
    bool held = false;
    for (std::size_t i = 0; i < markCount; ++i) {
        if (marks[i].timeS < timeS && (marks[i].kind == MarkKind::kHoldSet || marks[i].kind == MarkKind::kHoldReleased)) {
            held = marks[i].kind == MarkKind::kHoldSet;
        }
    }
    return held;
}

const char* toString(MissionOutcome outcome) {
    switch (outcome) {
        case MissionOutcome::kSetupFailed: return "setup failed";
        case MissionOutcome::kGoalReached: return "goal reached";
        case MissionOutcome::kCalledHome: return "called home";
        case MissionOutcome::kTimedOut: return "timed out";
        case MissionOutcome::kPlanComplete: return "plan complete";
    }
    return "?";
}

void printMissionUsage(std::FILE* out) {
    std::fprintf(out,
                 "usage: rse-demo [--scenario FILE] [--no-faults] [--goto X,Y[,RISK]] [--duration SECONDS] [--quiet]\n"
                 "                [--command-at SECONDS] [--report DIR | --no-report] [--any-outcome]\n"
                 "                [--pace F] [--udp-telemetry HOST:PORT [--udp-commands [ADDR:]PORT]]\n"
                 "  --scenario FILE     TOML scenario (default %s);\n"
                 "                      its [mission] (a goal and risk bound, or a plan) is flown\n"
                 "                      unless --goto is given\n"
                 "  --no-faults         leave the scenario's faults out\n"
                 "  --goto X,Y[,RISK]   the goal in metres and the risk bound (RISK default 1e-3; without\n"
                 "                      --goto: the scenario's [mission], else 20,0,1e-3)\n"
                 "  --duration SECONDS  simulated seconds at most, boot included (default: the scenario's\n"
                 "                      duration_s when it has a [mission], else 180)\n"
                 "  --command-at SECONDS  SET_MODE and GOTO (or the plan) at this simulated time at the\n"
                 "                      earliest (default: once the drives are up and the map uploaded)\n"
                 "  --quiet             no console lines, only the points and the summary\n"
                 "  --report DIR        write the mission report and map to DIR/report.md, DIR/map.svg\n"
                 "                      (default %s); --no-report writes none\n"
                 "  --any-outcome       exit 0 whatever the mission showed (else 3 when the ten points\n"
                 "                      of the RSE demonstration were not all seen, in order)\n"
                 "  --pace F            run F times faster than real time against the wall clock (1: real\n"
                 "                      time, 10: ten times; %g..%g; default: as fast as the CPU allows);\n"
                 "                      frames reached late run at once and are reported (\"behind by up to\")\n"
                 "  --udp-telemetry HOST:PORT  also send every telemetry packet and event as UDP datagrams\n"
                 "                      to HOST:PORT (numeric IPv4), rse-fsw --udp's link, e.g. for\n"
                 "                      rse-ground --tlm-port PORT watch or serve\n"
                 "  --udp-commands [ADDR:]PORT  that link's command port (ADDR default %s; default:\n"
                 "                      an unannounced port the kernel picks on 127.0.0.1)\n"
                 "Runs rse-fsw and rse-sim in lockstep, sends SET_MODE AUTONOMOUS and GOTO through the\n"
                 "authenticated ground link and runs until the rover reaches the goal, calls home or the\n"
                 "duration passes, printing the ten points as the flight software shows them.\n"
                 "Exit status: 0 the mission ran and showed the ten points in order, 3 it ran but did not,\n"
                 "1 setup failure (or the report not written), 2 bad usage.\n",
                 kDefaultMissionScenario, kDefaultReportDir, kMinPace, kMaxPace, kDefaultUdpCommandHost);
}

ParseOutcome parseMissionArgs(int argc, const char* const* argv, MissionOptions* o, std::string* error) {
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--scenario" && hasValue) {
            o->scenarioPath = argv[++i];
        } else if (a == "--no-faults") {
            o->clearFaults = true;
        } else if (a == "--goto" && hasValue) {
            if (!parseGoto(argv[++i], o, error)) {
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--duration" && hasValue) {
            const std::string v = argv[++i];
            if (!parseNumber(v, &o->durationS) || !(o->durationS > 0.0) || o->durationS > 1e6) {
                *error = "--duration '" + v + "' is not a number of seconds in (0, 1e6]";
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--command-at" && hasValue) {
            const std::string v = argv[++i];
            if (!parseNumber(v, &o->commandAtS) || !(o->commandAtS >= 0.0) || o->commandAtS > 1e5) {
                *error = "--command-at '" + v + "' is not a number of seconds in [0, 1e5]";
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--quiet") {
            o->quiet = true;
        } else if (a == "--report" && hasValue) {
            o->reportDir = argv[++i];
            if (o->reportDir.empty()) {
                *error = "--report wants a folder";
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--no-report") {
            o->reportDir.clear();
            o->noReport = true;
        } else if (a == "--any-outcome") {
            o->anyOutcome = true;
        } else if (a == "--pace" && hasValue) {
            const std::string v = argv[++i];
            if (!parseNumber(v, &o->pace) || !(o->pace >= kMinPace) || o->pace > kMaxPace) {
                char range[64];
                std::snprintf(range, sizeof range, "[%g, %g]", kMinPace, kMaxPace);
                *error = "--pace '" + v + "' is not a factor over real time in " + range +
                         " (1: real time; leave --pace out to run as fast as the CPU allows)";
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--udp-telemetry" && hasValue) {
            if (!parseUdpAddress(a, argv[++i], false, &o->udpTelemetryHost, &o->udpTelemetryPort, error)) {
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--udp-commands" && hasValue) {
            if (!parseUdpAddress(a, argv[++i], true, &o->udpCommandHost, &o->udpCommandPort, error)) {
                return ParseOutcome::kUsageError;
            }
        } else if (a == "--help" || a == "-h") {
            return ParseOutcome::kHelp;
        } else {
            *error = "unknown or incomplete option '" + a + "'";
            return ParseOutcome::kUsageError;
        }
    }
    if (o->udpCommandPort != 0 && o->udpTelemetryHost.empty()) {
        *error = "--udp-commands is the UDP link's command port: it wants --udp-telemetry HOST:PORT too";
        return ParseOutcome::kUsageError;
    }
    // The link would read its own telemetry as commands (each refused, counted).
    if (o->udpCommandPort != 0 && o->udpCommandPort == o->udpTelemetryPort &&
        (o->udpCommandHost == o->udpTelemetryHost || o->udpCommandHost == "0.0.0.0")) {
        *error = "--udp-commands and --udp-telemetry name the same address: telemetry would come back as commands";
        return ParseOutcome::kUsageError;
    }
    return ParseOutcome::kRun;
}

bool applyScenarioMission(const Scenario& scenario, MissionOptions* o, std::string* error) {
    const MissionSpec& m = scenario.mission;
    if (!(o->durationS > 0.0)) {
        o->durationS = m.present ? scenario.durationS : kDefaultMissionDurationS;
    }
    if (!o->gotoArgs.empty() || !o->planText.empty()) {
        return true;  // the command line's goal (or already applied)
    }
    if (m.present && !m.hasGoal) {
        o->planText = m.planText;
        o->planFile = m.planFile;
        o->risk = m.riskBound;
        return true;
    }
    const bool own = m.present && m.hasGoal;
    if (!encodeGoto(own ? m.goalX : kDefaultGoalX, own ? m.goalY : kDefaultGoalY,
                    own ? m.riskBound : kDefaultMissionRiskBound, o, error)) {
        *error = scenario.source + ": [mission]: " + *error;
        return false;
    }
    return true;
}

MissionSummary runMission(const MissionOptions& options, std::FILE* out) {
    const auto wallStart = std::chrono::steady_clock::now();
    MissionSummary summary;
    Scenario scenario;
    std::string error;
    if (!tryLoadScenarioFile(options.scenarioPath, &scenario, &error)) {
        return setupFailed(summary, error);
    }
    // The scenario's own mission where the command line did not say.
    MissionOptions o = options;
    if (!applyScenarioMission(scenario, &o, &error)) {
        return setupFailed(summary, error);
    }
    summary.planMission = !o.planText.empty();
    if (summary.planMission && !planPassesGroundCheck(o, &error)) {
        return setupFailed(summary, o.planFile + ": " + error);
    }
    summary.goalX = summary.planMission ? scenario.start.x : o.goalX;  // a plan's: its drives' (below)
    summary.goalY = summary.planMission ? scenario.start.y : o.goalY;
    if (o.clearFaults) {
        scenario.faults.clear();
    }
    if (o.editScenario) {
        o.editScenario(scenario);
    }
    const core::TimeNs durationNs = static_cast<core::TimeNs>(o.durationS * 1e9);

    // --udp-telemetry's link (on the heap: its receive batch is 20 kB). Held
    // here, before the rig, whose flight software keeps a pointer to it: it is
    // destroyed after the rig.
    std::unique_ptr<hal::UdpPacketLink> udpLink;
    // About 2.5 MB (the flight software's planners and the console buffer): on the heap.
    auto rig = std::make_unique<LockstepRig>(scenario);
    MemoryGround ground;
    app::FswApp& fsw = rig->fsw();
    if (!core::isOk(fsw.addGroundLink(&ground.link()))) {
        return setupFailed(summary, "the in-memory ground link could not be added");
    }
    const bool udp = !o.udpTelemetryHost.empty();
    if (udp) {
        // rse-fsw --udp's link, opened and added as rse-fsw does it
        // (fsw/app/main.cpp), after the in-memory ground: every telemetry
        // packet goes to both. It counts as always having room (a datagram
        // leaves at once), so events are still offered only as fast as the
        // in-memory ground's queue takes them, as without it.
        udpLink = std::make_unique<hal::UdpPacketLink>(fsw.events());
        if (!core::isOk(udpLink->open(o.udpCommandHost.c_str(), o.udpCommandPort, o.udpTelemetryHost.c_str(),
                                      o.udpTelemetryPort))) {
            return setupFailed(summary, "cannot open the UDP ground link (commands on " + o.udpCommandHost + ":" +
                                            std::to_string(o.udpCommandPort) + ", telemetry to " +
                                            o.udpTelemetryHost + ":" + std::to_string(o.udpTelemetryPort) +
                                            "): " + std::strerror(udpLink->lastErrno()));
        }
        if (!core::isOk(fsw.addGroundLink(udpLink.get()))) {
            return setupFailed(summary, "the UDP ground link could not be added");
        }
        summary.udpLink = true;
        summary.udpTelemetry = o.udpTelemetryHost + ":" + std::to_string(o.udpTelemetryPort);
        summary.udpCommands = o.udpCommandHost + ":" + std::to_string(udpLink->boundPort());
    }
    if (!core::isOk(rig->init(o.quiet ? nullptr : out))) {
        return setupFailed(summary, "the flight software did not initialise");
    }
    FlightWatch watch(fsw.bus(), fsw.events());
    if (!watch.subscribe()) {
        return setupFailed(summary, "no software-bus pipe for the plan status");
    }
    MissionRecorder recorder(*rig, out);
    watch.forwardTo(&recorder);
    say(out, *rig, describeScenario(rig->scenario(), o));
    if (udp) {
        say(out, *rig, "telemetry and events also as UDP datagrams to " + summary.udpTelemetry +
                           " (rse-fsw's UDP link; its commands on " + summary.udpCommands +
                           (o.udpCommandPort == 0 ? ", a port the kernel picked)" : ")"));
    }
    FramePacer pacer(o.pace);
    if (o.pace > 0.0) {
        char paceText[120];
        std::snprintf(paceText, sizeof paceText, "paced at %gx real time: a frame every %.3f ms of wall time", o.pace,
                      seconds(app::kMinorFramePeriod) * 1e3 / o.pace);
        say(out, *rig, paceText);
    }
    ScheduledTaskCommands taskCommands(ground, *rig, out);
    rig->rover().attachFlightTasks(&taskCommands);
    // A plan mission's goal is its latest drive's (the executive's PlanGoalMsg).
    std::uint32_t planGoals = rig->planGoalCount();
    const auto service = [&] {
        ground.drainDownlink();
        watch.drain();
        if (rig->planGoalCount() != planGoals && summary.planMission) {
            planGoals = rig->planGoalCount();
            const msg::GoalListMsg& g = rig->planGoal().goals;
            if (g.count > 0) {
                summary.goalX = g.goals[0].xM;
                summary.goalY = g.goals[0].yM;
            }
        }
        recorder.frame();
        if (o.onFrame) {
            o.onFrame(*rig);
        }
        // Last, so the wait is right before the next frame.
        pacer.beforeFrame(fsw.executive().nextFrame());
    };

    if (!rig->runUntil([&] { service(); return rig->allDrivesOperational(); }, kDrivesUpLimitNs)) {
        return setupFailed(summary, "the drives did not become operational");
    }
    // The scenario's site and known rocks, as the operator uplinks them.
    Scenario uplinked = rig->scenario();
    if (o.editUplinkedMap) {
        o.editUplinkedMap(uplinked);
    }
    const MapUploadResult map = uploadCoarseMap(uplinked, ground, *rig, service);
    if (!map.ok) {
        return setupFailed(summary, "the scenario's coarse map was not uploaded: " + map.error);
    }
    char mapLine[200];
    std::snprintf(mapLine, sizeof mapLine,
                  "ground: COARSE_MAP of the scenario (%zu known obstacles, %zu B, CRC-32 0x%08x) loaded in %zu "
                  "TABLE_LOAD chunks, validated, activated",
                  map.obstacles, map.bytes, static_cast<unsigned>(map.crc), map.chunks);
    say(out, *rig, mapLine);
    const auto commandAtNs = static_cast<core::TimeNs>(o.commandAtS * static_cast<double>(core::kNsPerSec));
    if (commandAtNs > rig->clock().now() &&
        !rig->runUntil([&] { service(); return rig->clock().now() >= commandAtNs; },
                       commandAtNs - rig->clock().now() + core::kNsPerSec)) {
        return setupFailed(summary, "the run did not reach --command-at");
    }
    say(out, *rig, "all six drives operational; ground: SET_MODE AUTONOMOUS");
    if (!ground.setMode(static_cast<std::uint8_t>(cmdtlm::Mode::kAutonomous)) ||
        !rig->runUntil([&] { service(); return watch.modeIs(static_cast<std::uint8_t>(cmdtlm::Mode::kAutonomous)); },
                       kModeAckLimitNs)) {
        return setupFailed(summary, "SET_MODE AUTONOMOUS was not sent or not taken");
    }
    char line[200];
    if (summary.planMission) {
        if (!uplinkPlan(o, ground, *rig, watch, service, &error)) {
            return setupFailed(summary, o.planFile + ": " + error);
        }
        std::snprintf(line, sizeof line, "ground: SET_RISK_BOUND risk=%.3g, plan %s loaded (%zu B, PLAN_LOAD and "
                      "PLAN_START, authenticated, lab key): accepted", o.risk, o.planFile.c_str(), o.planText.size());
    } else {
        if (!ground.send("GOTO", o.gotoArgs.data(), o.gotoArgs.size())) {
            return setupFailed(summary, "GOTO could not be sent");
        }
        std::snprintf(line, sizeof line, "ground: GOTO x=%.2f y=%.2f risk=%.3g (authenticated, lab key)", o.goalX,
                      o.goalY, o.risk);
    }
    say(out, *rig, line);

    const core::TimeNs left = durationNs - rig->clock().now();
    const bool ended = left > 0 && rig->runUntil([&] { service(); return watch.ended(summary.planMission); }, left);
    summary.outcomeTimeS = seconds(rig->clock().now());
    const msg::PlanStatusMsg plan = watch.plan();
    const msg::PlanExecutiveStatusMsg planExec = watch.planExec();
    const bool fpCalledHome = watch.faultProtectionCalledHome();
    if (ended) {
        if (summary.planMission) {
            summary.outcome = planExec.state == msg::PlanExecutiveState::kComplete && !fpCalledHome
                                  ? MissionOutcome::kPlanComplete
                                  : MissionOutcome::kCalledHome;
            summary.callHome = fpCalledHome ? msg::CallHomeReason::kFaultUnrecovered
                                            : static_cast<msg::CallHomeReason>(planExec.callHomeReason);
        } else {
            summary.outcome = plan.state == msg::DeliberativeState::kComplete && !fpCalledHome
                                  ? MissionOutcome::kGoalReached
                                  : MissionOutcome::kCalledHome;
            summary.callHome = fpCalledHome ? msg::CallHomeReason::kFaultUnrecovered : plan.callHome;
        }
        say(out, *rig, fpCalledHome           ? std::string("fault protection called home")
                       : summary.planMission ? "plan executive: plan " + planName(planExec) + " " +
                                                   planStateName(planExec.state)
                                             : std::string("deliberative layer: ") + stateName(plan.state));
        // The console task writes events at 10 Hz; the downlink is still drained.
        (void)rig->runUntil([&] { service(); return false; }, kMissionTailNs);
    } else {
        summary.outcome = MissionOutcome::kTimedOut;
        std::snprintf(line, sizeof line, "duration over; deliberative layer %s, plan executive %s", stateName(plan.state),
                      planStateName(planExec.state));
        say(out, *rig, line);
    }
    service();
    fsw.shutdown("mission demo over");
    pacer.fill(&summary);
    if (udp) {
        summary.udpStats = udpLink->stats();
        summary.udpUndeliverable = udpLink->undeliverableReports();
    }
    summary.callHomeText = watch.callHomeText();
    watch.fill(&summary);
    taskCommands.fill(&summary);
    rig->rover().attachFlightTasks(nullptr);  // the commander goes out of scope before the rig

    const msg::PlanStatusMsg& last = watch.plan();
    const deliberative::DeliberativeCounters& c = fsw.deliberative().counters();
    summary.endTimeS = seconds(rig->clock().now());
    summary.finalState = last.state;
    summary.planExec = watch.planExec();
    summary.finalMode = watch.mode();
    summary.interlockTripped = fsw.canIo().interlock().tripped();
    summary.plansMade = last.plansMade;
    summary.planLengthM = last.planLengthM;
    summary.riskBound = last.riskBound;
    summary.riskInForce = last.riskInForce;
    summary.riskUsed = last.riskUsed;
    summary.legsSent = c.legsSent;
    summary.legsAchieved = c.legsAchieved;
    summary.failUps = c.failUps;
    summary.replans = last.replans;
    summary.boundRelaxations = last.boundRelaxations;
    summary.riskRelaxations = last.riskRelaxations;
    summary.callHomes = last.callHomes;
    summary.habitualReplans = fsw.habitual().counters().replans;
    summary.commandsAccepted = fsw.commands().counters().accepted;
    summary.commandsRejected = fsw.commands().counters().rejected;

    const TruthRecord& truth = rig->rover().truth();
    summary.finalX = truth.pose.x;
    summary.finalY = truth.pose.y;
    summary.finalHeadingDeg = truth.pose.theta * 180.0 / kPi;
    summary.goalDistanceM = std::hypot(truth.pose.x - summary.goalX, truth.pose.y - summary.goalY);
    summary.distanceM = truth.distanceM;
    summary.collisions = truth.collisions;
    summary.leastClearanceM = truth.leastClearanceM;
    summary.energyWh = truth.energyDrawnWh;
    summary.stateOfCharge = truth.stateOfCharge;
    summary.wallTimeS = std::chrono::duration<double>(std::chrono::steady_clock::now() - wallStart).count();

    ground::MissionRecord& record = summary.record;
    record = recorder.record();
    record.scenario = rig->scenario().name + " (" + o.scenarioPath + ")";
    record.goalX = summary.goalX;
    record.goalY = summary.goalY;
    record.riskBound = o.risk;
    record.endTimeS = summary.endTimeS;
    char outcome[256];
    if (summary.outcome == MissionOutcome::kGoalReached) {
        std::snprintf(outcome, sizeof outcome, "goal reached at %.1f s", summary.outcomeTimeS);
    } else if (summary.outcome == MissionOutcome::kPlanComplete) {
        std::snprintf(outcome, sizeof outcome, "plan %s complete at %.1f s", planName(summary.planExec).c_str(),
                      summary.outcomeTimeS);
    } else if (summary.outcome == MissionOutcome::kCalledHome) {
        std::snprintf(outcome, sizeof outcome, "called home at %.1f s, reason %u: %s", summary.outcomeTimeS,
                      static_cast<unsigned>(summary.callHome), summary.callHomeText.c_str());
    } else {
        std::snprintf(outcome, sizeof outcome, "timed out at %.1f s", summary.outcomeTimeS);
    }
    record.outcome = outcome;
    record.legsSent = summary.legsSent;
    record.legsAchieved = summary.legsAchieved;
    record.failUps = summary.failUps;
    record.replans = summary.replans;
    record.boundRelaxations = summary.boundRelaxations;
    record.riskRelaxations = summary.riskRelaxations;
    record.callHomes = summary.callHomes;
    record.habitualReplans = summary.habitualReplans;
    summary.tenPointsInOrder = record.allInOrder;
    if (!o.reportDir.empty() &&
        !ground::writeMissionFiles(record, o.reportDir, &summary.reportPath, &summary.mapPath, &summary.reportError)) {
        summary.reportPath.clear();
        summary.mapPath.clear();
    }

    if (out != nullptr) {
        printMissionSummary(summary, out);
        fsw.printSummary(out);
        if (!summary.reportPath.empty()) {
            std::fprintf(out, "\nmission report: %s\nmission map:    %s\n", summary.reportPath.c_str(),
                         summary.mapPath.c_str());
        } else if (!summary.reportError.empty()) {
            std::fprintf(out, "\nmission report NOT written: %s\n", summary.reportError.c_str());
        }
        std::fflush(out);
    }
    return summary;
}

void printMissionSummary(const MissionSummary& s, std::FILE* out) {
    std::fprintf(out, "\n=== rse-demo mission summary ===\n");
    switch (s.outcome) {
        case MissionOutcome::kSetupFailed:
            std::fprintf(out, "outcome:    setup failed: %s\n", s.setupError.c_str());
            return;
        case MissionOutcome::kGoalReached:
            std::fprintf(out, "outcome:    goal (%.2f, %.2f) reached at %.1f s\n", s.goalX, s.goalY, s.outcomeTimeS);
            break;
        case MissionOutcome::kPlanComplete:
            std::fprintf(out, "outcome:    plan %s complete at %.1f s, the last drive's goal (%.2f, %.2f)\n",
                         planName(s.planExec).c_str(), s.outcomeTimeS, s.goalX, s.goalY);
            break;
        case MissionOutcome::kCalledHome:
            std::fprintf(out, "outcome:    called home at %.1f s, reason %u: %s (mode %s%s)\n", s.outcomeTimeS,
                         static_cast<unsigned>(s.callHome), s.callHomeText.c_str(), modeName(s.finalMode),
                         s.interlockTripped ? ", drive interlock tripped" : "");
            break;
        case MissionOutcome::kTimedOut:
            std::fprintf(out, "outcome:    timed out at %.1f s (deliberative layer %s, mode %s)\n", s.outcomeTimeS,
                         stateName(s.finalState), modeName(s.finalMode));
            break;
    }
    std::fprintf(out, "time:       %.1f s simulated in %.1f s wall (%.1fx real time)\n", s.endTimeS, s.wallTimeS,
                 s.wallTimeS > 0.0 ? s.endTimeS / s.wallTimeS : 0.0);
    if (s.pace > 0.0) {
        std::fprintf(out, "pace:       %gx real time: %llu frames paced, %llu reached after their due time; behind by "
                          "up to %.1f ms\n",
                     s.pace, static_cast<unsigned long long>(s.pacedFrames),
                     static_cast<unsigned long long>(s.framesBehind), s.behindMaxMs);
    }
    if (s.udpLink) {
        std::fprintf(out, "udp link:   telemetry to %s: %u packets sent, %u dropped, %u errors (%u undeliverable: "
                          "ICMP port unreachable, nothing listening there); commands on %s: %u received\n",
                     s.udpTelemetry.c_str(), s.udpStats.txPackets, s.udpStats.txDropped, s.udpStats.errors,
                     s.udpUndeliverable, s.udpCommands.c_str(), s.udpStats.rxPackets);
    }
    std::fprintf(out, "truth:      final position (%.2f, %.2f) heading %.1f deg, %.2f m from the goal; driven %.2f m; "
                      "collisions %u, least clearance %.2f m; energy %.2f Wh, state of charge %.1f %%\n",
                 s.finalX, s.finalY, s.finalHeadingDeg, s.goalDistanceM, s.distanceM, s.collisions,
                 s.leastClearanceM, s.energyWh,
                 100.0 * s.stateOfCharge);
    std::fprintf(out, "plan:       %u plans made; the last %.2f m, risk used %.3g (bound %.3g, in force %.3g)\n", s.plansMade,
                 s.planLengthM, s.riskUsed, s.riskBound, s.riskInForce);
    if (s.planMission) {
        const msg::PlanExecutiveStatusMsg& p = s.planExec;
        std::fprintf(out, "plan exec:  %s %s: cost %.2f (before the last regeneration %.2f), %u regenerations, %u "
                          "options deprecated; activities %u started, %u completed (%u early, %u late), %u failed; "
                          "%u operator calls\n",
                     planName(p).c_str(), planStateName(p.state), p.cost, p.costBefore, p.regenerations,
                     static_cast<unsigned>(p.deprecatedCount), p.activitiesStarted, p.activitiesCompleted,
                     p.activitiesEarly, p.activitiesLate, p.activitiesFailed, p.operatorCalls);
    }
    std::fprintf(out, "legs:       %u sent, %u achieved, %u fail-ups; %u replans, %u bound relaxations, %u risk "
                      "relaxations, %u call homes; habitual replans %u\n",
                 s.legsSent, s.legsAchieved, s.failUps, s.replans, s.boundRelaxations, s.riskRelaxations, s.callHomes,
                 s.habitualReplans);
    std::fprintf(out, "fault prot: %u responses, %u recovered, %u gave up, %u recovery actions, %u holds released",
                 s.responsesStarted, s.responsesRecovered, s.responsesGaveUp, s.recoveryActions, s.holdsReleased);
    if (s.firstResponseTimeS >= 0.0) {
        std::fprintf(out, "; first response %.2f s, first hold %.2f s, last resume %.2f s", s.firstResponseTimeS,
                     s.firstHoldTimeS, s.lastResumeTimeS);
    }
    std::fprintf(out, "\n");
    if (s.taskStallCommands > 0) {
        std::fprintf(out, "task stall: %u EXEC_SET_TASK sent; row %d disabled at %.2f s; its TASK_TIMING runs %u "
                          "then, %u at the end\n",
                     s.taskStallCommands, s.stalledRow, s.taskStallTimeS, s.stalledRowRunsAtStall,
                     s.stalledRowRunsAtEnd);
    }
    std::fprintf(out, "commands:   %u accepted, %u rejected\n", s.commandsAccepted, s.commandsRejected);
    std::fprintf(out, "points:     %s\n", s.record.verdict.c_str());
    for (const ground::MissionPoint& p : s.record.points) {
        if (p.seen) {
            std::fprintf(out, "            %2d at %8.2f s  %s\n", p.number, p.timeS, p.layer.c_str());
        } else {
            std::fprintf(out, "            %2d not seen\n", p.number);
        }
    }
    std::fprintf(out, "\n");
}

int missionMain(int argc, const char* const* argv, std::FILE* out, std::FILE* err) {
    MissionOptions options;
    std::string error;
    switch (parseMissionArgs(argc, argv, &options, &error)) {
        case ParseOutcome::kHelp:
            printMissionUsage(out);
            return 0;
        case ParseOutcome::kUsageError:
            std::fprintf(err, "rse-demo: %s\n", error.c_str());
            printMissionUsage(err);
            return 2;
        case ParseOutcome::kRun:
            break;
    }
    if (options.reportDir.empty() && !options.noReport) {
        options.reportDir = kDefaultReportDir;
    }
    const MissionSummary summary = runMission(options, out);
    if (summary.outcome == MissionOutcome::kSetupFailed) {
        std::fprintf(err, "rse-demo: setup failed: %s\n", summary.setupError.c_str());
        return 1;
    }
    if (!options.reportDir.empty() && summary.reportPath.empty()) {
        std::fprintf(err, "rse-demo: mission report not written: %s\n", summary.reportError.c_str());
        return 1;
    }
    if (!summary.tenPointsInOrder && !options.anyOutcome) {
        std::fprintf(err, "rse-demo: %s\n", summary.record.verdict.c_str());
        return 3;
    }
    return 0;
}

}  // namespace rse::sim
