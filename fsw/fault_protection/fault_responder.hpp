// Fault protection's decisions (pure logic; FaultProtectionTask feeds it from
// the bus and publishes what it decides). One small state machine per
// response in progress: per wheel for the drive classes (lost, faulted), per
// fault id for the others. Each run it reads the active faults, the drives'
// states, the interlock and the mode, and writes the mission hold, the drive
// recovery and task restart requests, and whether to call home.
//
// A response (FAULT_PROTECTION.response of its class):
//   event only       the fault is evented when it starts and when it clears.
//   hold until clear the mission is held (wheels at zero, no new legs) while the
//                    fault is active, in AUTONOMOUS only; each try waits
//                    max_wait_ms; after `attempts` tries it calls home.
//   recover drive    hold; give the drive its own recovery first (a lost
//                    drive FAULT_RESPONSE.heartbeat_loss_ms, a faulted one until
//                    the CAN master's fault resets end or max_wait_ms), then
//                    try: CiA 402 fault reset (first try on a faulted drive),
//                    else NMT reset node, each given max_wait_ms; healthy again
//                    -> interlock reset -> hold released -> driving resumes.
//                    After `attempts` tries the drive is declared failed, the
//                    hold released, and the deliberative layer decides
//                    (replan or call home; the interlock still holds).
//   restart task     the stalled rate-group row is run again (TaskRestartMsg),
//                    the mission held meanwhile; `attempts` tries, then call home.
//   replan from pose the deliberative layer cancels the waypoint and replans the
//                    unfinished goals from where the rover stands
//                    (ReplanRequestMsg), in AUTONOMOUS only; no hold (the
//                    rover must drive to get back on); each try waits
//                    max_wait_ms; after `attempts` tries it calls home.
//   safe, call home  at once.
// A fault that clears after a response keeps its attempt count for
// attempt_memory_ms, so a fault that comes back at once cannot retry forever.
//
// Precedence when reports conflict in one cycle: a fault wins. A drive whose
// heartbeat-lost fault is active counts as lost whatever its drive status
// says; a drive the status calls faulted is faulted whatever else is said.
// Conflicts are counted and evented (937, throttled).
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/static_vector.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/node_msgs.hpp"
#include "fsw/tables/table_types.hpp"

namespace rse::fault_protection {

// Rate-group rows a task restart can name (the task-stall fault ids).
constexpr std::size_t kRestartableRows = msg::fault::kTaskStalledCount;
// An interlock reset asked for and not yet seen is asked again after this.
constexpr core::TimeNs kInterlockResetRetry = 100 * core::kNsPerMs;

struct ResponderInputs {
    core::TimeNs now = 0;
    std::uint64_t activeFaults = 0;  // FaultStatusMsg::activeMask (0 until the first one)
    bool haveDrives = false;         // a DriveStatusMsg has arrived
    msg::DriveHealth health[msg::kWheelCount] = {};
    bool interlockTripped = false;
    bool autonomous = false;         // rover mode AUTONOMOUS (holds apply only then)
};

struct ResponderLimits {
    msg::FaultResponseKind response[msg::kFaultClassCount] = {};
    std::uint8_t attempts[msg::kFaultClassCount] = {};
    core::TimeNs maxWait[msg::kFaultClassCount] = {};
    core::TimeNs attemptMemory = 0;
    core::TimeNs driveLostSettle = 0;  // FAULT_RESPONSE.heartbeat_loss_ms
};
ResponderLimits responderLimitsFrom(const tables::FaultProtectionTable& protection,
                                    const tables::FaultResponseTable& faults);

struct ResponderActions {
    std::uint32_t holdReasons = 0;  // bit per msg::hold:: reason
    core::StaticVector<msg::DriveRecoveryMsg, msg::kWheelCount + 1> driveActions;
    core::StaticVector<std::uint8_t, kRestartableRows> taskRestarts;
    core::StaticVector<msg::ReplanRequestMsg, 1> replans;  // only the off-map fault asks for one
    bool callHome = false;
};

// The class a fault id belongs to (drive heartbeat ids: kDriveLost). False for
// an id no class covers.
bool classOf(std::uint8_t faultId, msg::FaultClass* out);
const char* toString(msg::FaultClass c);
const char* toString(msg::FaultResponseKind k);

class FaultResponder {
public:
    explicit FaultResponder(core::EventLog& events) : events_(events) {}

    void step(const ResponderInputs& in, const ResponderLimits& limits, ResponderActions* out);

    // Responses not idle, wheels first, at most kResponseSlots.
    void fillStatus(msg::FaultProtectionStatusMsg* status) const;
    const msg::ResponseTlm* wheel(std::size_t w) const { return w < msg::kWheelCount ? &wheels_[w].tlm : nullptr; }
    const msg::ResponseTlm* fault(std::uint8_t id) const { return id < msg::fault::kCount ? &faults_[id].tlm : nullptr; }

    std::uint32_t responsesStarted() const { return started_; }
    std::uint32_t recoveries() const { return recoveries_; }
    std::uint32_t gaveUp() const { return gaveUp_; }
    std::uint32_t actionsSent() const { return actions_; }
    std::uint32_t conflicts() const { return conflicts_; }

private:
    struct Response {
        msg::ResponseTlm tlm{};
        core::TimeNs clearSince = 0;  // kRecovered: when the fault cleared
    };

    // One wheel's inputs in one run, as its response reads them.
    struct WheelReading {
        std::uint8_t lostId = 0;                 // its heartbeat-lost fault id
        msg::DriveHealth health{};               // as the drive status says
        bool trouble = false;                    // lost or faulted
        bool healthy = false;                    // operational and not heartbeat-lost
        msg::FaultClass faultClass{};            // lost wins over faulted
        msg::FaultResponseKind kind{};           // the class's response as it applies to a drive
    };

    // A wheel's response each run: read the wheel (counting conflicting
    // reports), begin a response for a drive newly in trouble, judge the
    // response in progress, hold while it recovers.
    void stepWheel(std::size_t w, const ResponderInputs& in, const ResponderLimits& limits, ResponderActions* out);
    WheelReading readWheel(std::size_t w, const ResponderInputs& in, const ResponderLimits& limits);
    void beginWheel(Response& r, const WheelReading& d, const ResponderInputs& in, const ResponderLimits& limits,
                    ResponderActions* out);
    void judgeWheel(std::size_t w, Response& r, const WheelReading& d, const ResponderInputs& in,
                    const ResponderLimits& limits, ResponderActions* out);
    void driveAct(std::size_t w, Response& r, const ResponderInputs& in, const ResponderLimits& limits,
                  ResponderActions* out);
    void stepFault(std::uint8_t id, msg::FaultClass c, const ResponderInputs& in, const ResponderLimits& limits,
                   ResponderActions* out);
    void begin(Response& r, msg::FaultClass c, std::uint8_t faultId, msg::ResponseState state,
               const ResponderLimits& limits, core::TimeNs now);
    void enter(Response& r, msg::ResponseState state, core::TimeNs now);
    void recovered(Response& r, core::TimeNs now, const char* what);
    void giveUp(Response& r, core::TimeNs now, const char* what, ResponderActions* out, bool callHome);
    void askInterlockReset(const ResponderInputs& in, ResponderActions* out);

    core::EventLog& events_;
    Response wheels_[msg::kWheelCount];
    Response faults_[msg::fault::kCount];
    core::TimeNs interlockAskedAt_ = -1;
    std::uint32_t interlockAsks_ = 0;  // while the interlock stays tripped (events throttled)
    std::uint32_t started_ = 0;
    std::uint32_t recoveries_ = 0;
    std::uint32_t gaveUp_ = 0;
    std::uint32_t actions_ = 0;
    std::uint32_t conflicts_ = 0;
};

}  // namespace rse::fault_protection
