// What the operator sees of the flight software in a lockstep mission
// (rse-demo's watch): its published plan status, plan executive status and
// mode (a pipe on the software bus) and its events (a reader of its own on the
// event log), read once per frame; nothing is sent. The fault status, fault
// protection's status and its requests (drive recovery, task restart, replan)
// on the same pipe name the fault of each raise, response and action mark
// (MissionMark::faultId, wheel): each is published in the frame of its event.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "sim_stub/lockstep/mission_summary.hpp"

namespace rse::sim {

class MissionRecorder;

class FlightWatch {
public:
    FlightWatch(core::SoftwareBus& bus, const core::EventLog& events) : bus_(bus), events_(events) {}
    // The pipe ("rse-demo") and its subscriptions; false when the bus has no room.
    bool subscribe();
    // Every message read is also handed to the mission recorder (the bus has
    // no slots left for a pipe of its own).
    void forwardTo(MissionRecorder* recorder) { recorder_ = recorder; }
    // Once a frame: the pipe's messages, then the events.
    void drain();
    // Fault protection's counts, times and the marks, into the summary.
    void fill(MissionSummary* s) const;

    bool faultProtectionCalledHome() const { return fpCalledHome_; }
    // The call home in the flight software's words (its CRITICAL event).
    std::string callHomeText() const;
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
    bool ended(bool planMission) const;

private:
    // Who the event `eventId` of the frame at timeNs is about, from the
    // telemetry published in that frame; taken by the first such event.
    struct Attribution {
        core::EventId eventId;
        core::TimeNs timeNs;
        std::uint8_t faultId;
        std::uint8_t wheel;
    };
    static constexpr std::uint16_t kPipeDepth = 32;

    void onMessage(const core::Message& m);
    void onHold(const msg::MissionHoldMsg& h);
    void onEvent(const core::Event& e);
    void noteRaises(const msg::FaultStatusMsg& f);
    void noteResponses(const msg::FaultProtectionStatusMsg& s);
    void markAttributed(MarkKind kind, const core::Event& e);
    void mark(MarkKind kind, std::uint16_t id, core::TimeNs t, std::uint8_t faultId = 0,
              std::uint8_t wheel = kNoWheel);

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

    std::vector<Attribution> pending_;
    std::uint64_t activeFaults_ = 0;  // FaultStatusMsg last seen
    std::uint32_t raisedTotal_ = 0;
    std::array<msg::ResponseState, msg::fault::kCount> responseState_{};  // by fault id, FaultProtectionStatusMsg last seen
    std::uint32_t responsesStartedTlm_ = 0;
};

}  // namespace rse::sim
