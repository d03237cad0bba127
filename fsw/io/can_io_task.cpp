#include "fsw/io/can_io_task.hpp"

#include <cmath>

#include "fsw/io/io_events.hpp"
#include "hal/devices/rse_device_ids.hpp"

namespace rse::io {

// DriveHealth in telemetry mirrors hal::DriveState value for value.
static_assert(static_cast<int>(msg::DriveHealth::kWaitingBootUp) == static_cast<int>(hal::DriveState::kWaitingBootUp) &&
                  static_cast<int>(msg::DriveHealth::kOperational) == static_cast<int>(hal::DriveState::kOperational) &&
                  static_cast<int>(msg::DriveHealth::kFaulted) == static_cast<int>(hal::DriveState::kFaulted) &&
                  static_cast<int>(msg::DriveHealth::kFailed) == static_cast<int>(hal::DriveState::kFailed) &&
                  static_cast<int>(msg::DriveHealth::kLost) == static_cast<int>(hal::DriveState::kLost),
              "msg::DriveHealth must mirror hal::DriveState");

// The instrument enums on the bus mirror hal/devices/instrument_protocol.hpp value for value.
namespace inst = hal::instrument;
static_assert(static_cast<int>(msg::Instrument::kGrinder) == static_cast<int>(inst::Kind::kGrinder) &&
                  static_cast<int>(msg::Instrument::kCamera) == static_cast<int>(inst::Kind::kCamera) &&
                  msg::kInstrumentCount == inst::kCount,
              "msg::Instrument must mirror hal::instrument::Kind");
static_assert(static_cast<int>(msg::InstrumentAction::kSample) == static_cast<int>(inst::Action::kSample) &&
                  static_cast<int>(msg::InstrumentAction::kDig) == static_cast<int>(inst::Action::kDig) &&
                  static_cast<int>(msg::InstrumentAction::kImage) == static_cast<int>(inst::Action::kImage) &&
                  static_cast<int>(msg::InstrumentAction::kCancel) == static_cast<int>(inst::Action::kCancel) &&
                  static_cast<int>(msg::InstrumentAction::kExtend) == static_cast<int>(inst::Action::kExtend),
              "msg::InstrumentAction must mirror hal::instrument::Action");
static_assert(static_cast<int>(msg::InstrumentResult::kAborted) == static_cast<int>(inst::Result::kAborted) &&
                  static_cast<int>(msg::InstrumentResult::kCancelled) == static_cast<int>(inst::Result::kCancelled) &&
                  static_cast<int>(msg::InstrumentResult::kTimedOut) == static_cast<int>(inst::Result::kTimedOut) &&
                  static_cast<int>(msg::InstrumentResult::kOutOfReach) == static_cast<int>(inst::Result::kOutOfReach),
              "msg::InstrumentResult must mirror hal::instrument::Result");
static_assert(static_cast<int>(msg::InstrumentRefusal::kBusy) == static_cast<int>(inst::Refusal::kBusy) &&
                  static_cast<int>(msg::InstrumentRefusal::kUnsupportedAction) ==
                      static_cast<int>(inst::Refusal::kUnsupportedAction) &&
                  static_cast<int>(msg::InstrumentRefusal::kUnknownTarget) ==
                      static_cast<int>(inst::Refusal::kUnknownTarget) &&
                  static_cast<int>(msg::InstrumentRefusal::kOutOfReach) == static_cast<int>(inst::Refusal::kOutOfReach) &&
                  static_cast<int>(msg::InstrumentRefusal::kFaulted) == static_cast<int>(inst::Refusal::kFaulted) &&
                  static_cast<int>(msg::InstrumentRefusal::kMalformed) == static_cast<int>(inst::Refusal::kMalformed) &&
                  static_cast<int>(msg::InstrumentRefusal::kNoSuchCommand) ==
                      static_cast<int>(inst::Refusal::kNoSuchCommand) &&
                  static_cast<int>(msg::InstrumentRefusal::kOffline) == static_cast<int>(inst::Refusal::kOffline) &&
                  static_cast<int>(msg::InstrumentRefusal::kNotSent) == static_cast<int>(inst::Refusal::kNotSent),
              "msg::InstrumentRefusal must mirror hal::instrument::Refusal");

namespace {
constexpr double kMrad = 1e-3;

// The bus state of an instrument: offline unless it reported lately, else its
// reported state (msg::InstrumentState is the wire state + 1).
msg::InstrumentState busState(const hal::InstrumentStatus& s) {
    return s.online ? static_cast<msg::InstrumentState>(static_cast<int>(s.state) + 1) : msg::InstrumentState::kOffline;
}
static_assert(static_cast<int>(msg::InstrumentState::kFailed) == static_cast<int>(inst::State::kFailed) + 1 &&
                  static_cast<int>(msg::InstrumentState::kIdle) == static_cast<int>(inst::State::kIdle) + 1,
              "msg::InstrumentState must be the wire state + 1");
}  // namespace

CanIoTask::CanIoTask(hal::CanBus& can, const core::Clock& clock, core::SoftwareBus& bus, core::EventLog& events,
                     const tables::TableService& tables)
    : can_(can),
      bus_(bus),
      events_(events),
      tables_(tables),
      master_(can, events),
      link_(can, events, "rover"),
      // Node ids are set from the node map table in init().
      drives_{{can, events, master_.heartbeats(), 0, msg::wheelName(0)},
              {can, events, master_.heartbeats(), 0, msg::wheelName(1)},
              {can, events, master_.heartbeats(), 0, msg::wheelName(2)},
              {can, events, master_.heartbeats(), 0, msg::wheelName(3)},
              {can, events, master_.heartbeats(), 0, msg::wheelName(4)},
              {can, events, master_.heartbeats(), 0, msg::wheelName(5)}},
      imu_(events),
      power_(events),
      hazard_(events),
      fix_(events),
      instruments_{{can, events, inst::Kind::kGrinder}, {can, events, inst::Kind::kCamera}},
      interlock_(events),
      groundLink_(can, clock, events),
      input_(bus, events, core::InputPipeConfig{"can_io", kCanIoPipeDepth, events::kBusMessageMalformed, "can_io"}) {}

core::Status CanIoTask::initNodes() {
    // Read once: the master is configured at start-up (the node map table says
    // an activated map applies at the next start).
    const tables::CanNodeMapTable& map = tables_.canNodeMap();
    const tables::FaultResponseTable& response = tables_.faultResponse();
    heartbeatTimeout_ = static_cast<core::TimeNs>(map.heartbeat_timeout_ms) * core::kNsPerMs;
    const core::TimeNs bootTimeout = static_cast<core::TimeNs>(map.drive_boot_timeout_ms) * core::kNsPerMs;
    hal::DriveConfig config;
    config.sdoRetries = response.sdo_retries;
    config.sdoTimeout = static_cast<core::TimeNs>(response.sdo_timeout_ms) * core::kNsPerMs;
    config.faultResets = response.drive_restart_attempts;
    config.faultResetWait = static_cast<core::TimeNs>(response.drive_fault_reset_wait_ms) * core::kNsPerMs;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        core::Status s = drives_[w].configure(map.drive_node_id[w], config);
        if (core::isOk(s)) {
            s = master_.addNode(&drives_[w], heartbeatTimeout_, bootTimeout);
        }
        if (!core::isOk(s)) {
            // The table's own check refuses duplicates; this catches what gets past it.
            events_.report(events::kNodeMapRefused, core::Severity::kCritical,
                           "app: node map refused: drive %s node %u (%s)", msg::wheelName(w),
                           static_cast<unsigned>(map.drive_node_id[w]), core::toString(s));
            return s;
        }
    }
    deviceNodes_[0] = map.imu_node_id;
    deviceNodes_[1] = map.power_node_id;
    deviceNodes_[2] = map.hazard_node_id;
    deviceNodes_[3] = map.position_fix_node_id;
    for (std::uint8_t node : deviceNodes_) {
        const core::Status st = master_.monitor(node, heartbeatTimeout_);
        if (!core::isOk(st)) {
            events_.report(events::kNodeMapRefused, core::Severity::kCritical,
                           "app: node map refused: device node %u (%s)", static_cast<unsigned>(node),
                           core::toString(st));
            return st;
        }
    }
    return core::Status::kOk;
}

core::Status CanIoTask::init() {
    core::Status st = initNodes();
    if (!core::isOk(st)) {
        return st;
    }
    namespace ids = hal::device_ids;
    const struct {
        std::uint32_t cob;
        hal::canopen::CanFrameSink* sink;
    } sinks[] = {{ids::kImuRates, &imu_},
                 {ids::kPower, &power_},
                 {ids::kHazard, &hazard_},
                 {ids::kFixX, &fix_},
                 {ids::kFixY, &fix_},
                 {inst::idsOf(inst::Kind::kGrinder).statusCobId, &instruments_[0]},
                 {inst::idsOf(inst::Kind::kCamera).statusCobId, &instruments_[1]},
                 {kGroundUplinkCobId, &groundLink_}};
    for (const auto& s : sinks) {
        st = master_.addSink(s.cob, s.sink);
        if (!core::isOk(st)) {
            return st;
        }
    }
    return routeInputs();
}

core::Status CanIoTask::routeInputs() {
    core::Status st = input_.create();
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeWheelCommand>(this);
    }
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeInterlockReset>(this);
    }
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeMode>(this);
    }
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeRecovery>(this);
    }
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeHold>(this);
    }
    if (core::isOk(st)) {
        st = input_.route<&CanIoTask::takeInstrumentCommand>(this);
    }
    return st;
}

void CanIoTask::fillHousekeeping(cmdtlm::HK_Tlm& hk) const {
    const hal::CanBusStats& can = can_.stats();
    hk.can_rx_frames = can.rxFrames;
    hk.can_tx_frames = can.txFrames;
    hk.can_tx_refused = can.txInvalid + can.txUnavailable + can.txBufferFull;
    hk.can_rx_overruns = can.rxOverruns;
    hk.can_error_frames = can.errorFrames;
    hk.can_bus_off = can.busOffCount;
}

std::uint8_t CanIoTask::monitoredNodeId(std::size_t i) const {
    if (i < msg::kWheelCount) {
        return drives_[i].nodeId();
    }
    return i < msg::kMonitoredNodeCount ? deviceNodes_[i - msg::kWheelCount] : 0;
}

void CanIoTask::refuseRecovery(const char* why, unsigned wheel) {
    ++recoveriesRefused_;
    if (core::isReportableOccurrence(recoveriesRefused_)) {
        events_.report(events::kDriveRecoveryRefused, core::Severity::kError,
                       "app: drive recovery refused: %s (wheel %u, %u so far)", why, wheel,
                       static_cast<unsigned>(recoveriesRefused_));
    }
}

void CanIoTask::takeRecovery(const msg::DriveRecoveryMsg& r) {
    const auto action = static_cast<unsigned>(r.action);
    const char* what = nullptr;
    core::Status st = core::Status::kOk;
    if (r.action == msg::DriveRecoveryAction::kResetInterlock) {
        what = "interlock reset";
        (void)interlock_.resetIfHealthy(status_);  // evented either way (605/606)
    } else if (r.action != msg::DriveRecoveryAction::kFaultReset && r.action != msg::DriveRecoveryAction::kResetNode) {
        refuseRecovery(action == 0 ? "no action" : "unknown action", r.wheel);
        return;
    } else if (r.wheel >= msg::kWheelCount) {
        refuseRecovery("wheel out of range", r.wheel);
        return;
    } else if (r.action == msg::DriveRecoveryAction::kFaultReset) {
        what = "fault reset";
        st = drives_[r.wheel].requestFaultReset(now_);
        if (!core::isOk(st)) {
            refuseRecovery("fault reset: drive neither faulted nor failed", r.wheel);
            return;
        }
    } else {
        what = "NMT reset node";
        st = master_.sendNmt(hal::canopen::NmtCommand::kResetNode, drives_[r.wheel].nodeId());
        if (!core::isOk(st)) {
            refuseRecovery("NMT reset node not sent (CAN refused it)", r.wheel);
            return;
        }
    }
    ++recoveriesTaken_;
    events_.report(events::kDriveRecoveryTaken, core::Severity::kWarning, "app: drive recovery: %s, wheel %s",
                   what, r.action == msg::DriveRecoveryAction::kResetInterlock ? "-" : msg::wheelName(r.wheel));
}

void CanIoTask::takeHold(const msg::MissionHoldMsg& hold) {
    if (!msg::holdUsable(hold)) {
        refuse("malformed mission hold (hold state unchanged)");
        return;
    }
    const bool held = hold.estop != 0;
    if (held != holdEstop_) {
        events_.report(events::kHoldEstopChanged, held ? core::Severity::kWarning : core::Severity::kInfo,
                       held ? "app: fault protection hold: every drive to zero (reasons 0x%02X)"
                            : "app: fault protection hold released (reasons 0x%02X)",
                       static_cast<unsigned>(hold.reasons));
    }
    holdEstop_ = held;
    if (holdEstop_) {
        for (double& c : commanded_) {
            c = 0.0;
        }
    }
}

void CanIoTask::takeInstrumentCommand(const msg::InstrumentCommandMsg& c) {
    const auto which = static_cast<std::size_t>(c.instrument);
    if (which >= msg::kInstrumentCount) {
        ++instrumentCommandsDropped_;
        if (core::isReportableOccurrence(instrumentCommandsDropped_)) {
            events_.report(events::kBusMessageMalformed, core::Severity::kError,
                           "app: CAN I/O dropped an instrument command: no such instrument %u (%u so far)",
                           static_cast<unsigned>(which),
                           static_cast<unsigned>(instrumentCommandsDropped_));
        }
        return;
    }
    // Checked and counted by the instrument client (refusals are in its status).
    (void)instruments_[which].command(static_cast<inst::Action>(c.action), c.targetId, c.commandId, c.maxDurationS,
                                      c.extendsCommandId);
}

void CanIoTask::refuse(const char* why) {
    ++commandsRejected_;
    if (core::isReportableOccurrence(commandsRejected_)) {
        events_.report(events::kWheelCommandRejected, core::Severity::kError,
                       "app: wheel command refused: %s (%u so far); previous command kept", why,
                       static_cast<unsigned>(commandsRejected_));
    }
}

bool CanIoTask::anyWheelCommanded() const {
    for (double c : commanded_) {
        if (c != 0.0) {
            return true;
        }
    }
    return false;
}

void CanIoTask::takeMode(const msg::ModeMsg& mode) {
    if (mode.estop != 0 && !estop_) {
        estopWatching_ = true;
        estopOverrunReported_ = false;
        estopSince_ = -1;
    }
    estop_ = mode.estop != 0;
    estopWatching_ = estopWatching_ && estop_;
    // A mode change takes driving authority from the layer that had it
    // (manual drive, the trajectory follower), so wheels left turning by
    // it are stopped here, where no task can forget to.
    const bool modeChanged = mode.mode != mode_;
    mode_ = mode.mode;
    if (modeChanged && anyWheelCommanded()) {
        events_.report(events::kWheelsStoppedOnModeChange, core::Severity::kInfo,
                       "app: mode changed to %u: every wheel commanded to zero", static_cast<unsigned>(mode_));
    }
    if (estop_ || modeChanged) {
        for (double& c : commanded_) {
            c = 0.0;
        }
    }
}

void CanIoTask::takeInterlockReset(const msg::InterlockResetMsg&) {
    (void)interlock_.resetIfHealthy(status_);  // evented either way
}

void CanIoTask::takeWheelCommand(const msg::WheelCommandMsg& cmd) {
    const double maxSpeed = static_cast<double>(tables_.roverGeometry().max_wheel_speed_rad_s);
    const char* why = nullptr;
    for (double v : cmd.velocityRadS) {
        // Written so that NaN fails too (every comparison with NaN is false).
        if (!(v >= -maxSpeed && v <= maxSpeed)) {
            why = "wheel speed not finite or beyond the geometry table's limit";
        }
    }
    if (why == nullptr && estop_) {
        ++heldByEstop_;
        if (core::isReportableOccurrence(heldByEstop_)) {
            events_.report(events::kWheelCommandHeld, core::Severity::kWarning,
                           "app: wheel command ignored: software e-stop set (%u so far)",
                           static_cast<unsigned>(heldByEstop_));
        }
        return;
    }
    if (why == nullptr && holdEstop_) {
        ++heldByHold_;
        if (core::isReportableOccurrence(heldByHold_)) {
            events_.report(events::kWheelCommandHeld, core::Severity::kWarning,
                           "app: wheel command ignored: fault protection hold (%u so far)",
                           static_cast<unsigned>(heldByHold_));
        }
        return;
    }
    if (why != nullptr) {
        refuse(why);
        return;
    }
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        commanded_[w] = cmd.velocityRadS[w];
    }
}

void CanIoTask::run(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    now_ = now;
    (void)input_.drain();  // in arrival order; bounded by the pipe's depth
    double safe[msg::kWheelCount];
    interlock_.apply(status_, commanded_, safe);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        // Commands were range-checked on arrival, so this always fits an int32.
        drives_[w].setTargetVelocity(static_cast<std::int32_t>(safe[w] / kMrad));
    }
    master_.cycle(now);
    groundLink_.service();
    link_.check();
    hazard_.expire(now);
    for (hal::Instrument& instrument : instruments_) {
        instrument.step(now);
    }
    publishStatus(now);
    watchEstopStop(now);
    publishSensors(frame);
    publishInstruments(frame);
}

void CanIoTask::publishInstruments(const core::FrameContext& frame) {
    for (std::size_t i = 0; i < msg::kInstrumentCount; ++i) {
        const hal::Instrument& device = instruments_[i];
        const hal::InstrumentStatus& s = device.status();
        const std::uint32_t framesBad = device.frameStats().badLength + device.frameStats().badValue;
        if (s.changes == instrumentPublished_[i] && framesBad == instrumentBadFrames_[i] && frame.frame % 100 != 0) {
            continue;
        }
        instrumentPublished_[i] = s.changes;
        instrumentBadFrames_[i] = framesBad;
        msg::InstrumentStatusMsg& m = instrumentMsg_;
        m = msg::InstrumentStatusMsg{};
        m.timeNs = frame.actualStart;
        m.lastReportNs = s.everHeard ? s.lastHeard : 0;
        m.instrument = static_cast<msg::Instrument>(i);
        m.state = busState(s);
        m.action = static_cast<msg::InstrumentAction>(s.action);
        m.targetId = s.target;
        m.commandId = s.commandId;
        m.progressPct = s.progressPct;
        m.result = static_cast<msg::InstrumentResult>(s.result);
        m.faultCode = s.faultCode;
        m.lastRefusal = static_cast<msg::InstrumentRefusal>(s.lastRefusal);
        m.lastRefusedCommandId = s.lastRefusedCommandId;
        m.commandsSent = s.commandsSent;
        m.commandsAccepted = s.commandsAccepted;
        m.commandsRefused = s.commandsRefused;
        m.commandsNotSent = s.commandsNotSent;
        m.framesBad = framesBad;
        m.offlineCount = s.offlineCount;
        (void)bus_.publish(m);
    }
}

void CanIoTask::watchEstopStop(core::TimeNs now) {
    if (!estopWatching_) {
        return;
    }
    if (estopSince_ < 0) {
        estopSince_ = now;
    }
    bool stopped = true;
    double fastest = 0.0;
    for (const msg::WheelStatus& w : status_.wheels) {
        const double speed = std::fabs(w.velocityRadS);
        stopped = stopped && speed < kEstopStoppedRadS;
        fastest = speed > fastest ? speed : fastest;
    }
    const core::TimeNs elapsed = now - estopSince_;
    if (stopped) {
        estopWatching_ = false;
        lastEstopStopTime_ = elapsed;
        events_.report(events::kEstopWheelsStopped, core::Severity::kInfo,
                       "app: e-stop: every wheel below %.2f rad/s %lld ms after it was taken", kEstopStoppedRadS,
                       static_cast<long long>(elapsed / core::kNsPerMs));
        return;
    }
    const core::TimeNs allowed =
        static_cast<core::TimeNs>(tables_.faultResponse().estop_stop_time_ms) * core::kNsPerMs;
    if (elapsed > allowed && !estopOverrunReported_) {
        estopOverrunReported_ = true;
        ++estopOverruns_;
        events_.report(events::kEstopStopOverrun, core::Severity::kCritical,
                       "app: e-stop overrun: a wheel still turns at %.2f rad/s %lld ms after it was taken (limit %u ms)",
                       fastest, static_cast<long long>(elapsed / core::kNsPerMs),
                       static_cast<unsigned>(tables_.faultResponse().estop_stop_time_ms));
    }
}

void CanIoTask::publishStatus(core::TimeNs now) {
    status_.timeNs = now;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const hal::WheelDrive& d = drives_[w];
        msg::WheelStatus& s = status_.wheels[w];
        s.targetRadS = static_cast<double>(d.targetVelocityMradS()) * kMrad;
        s.velocityRadS = static_cast<double>(d.feedback().velocityMradS) * kMrad;
        s.currentA = static_cast<double>(d.feedback().currentMa) * 1e-3;
        s.feedbackTimeNs = d.feedback().time;
        s.feedbackCount = d.feedback().count;
        s.statusword = d.feedback().statusword;
        s.lastEmcyCode = d.lastEmcyCode();
        s.health = static_cast<msg::DriveHealth>(d.state());
        s.temperatureValid = d.feedback().temperatureCount > 0 ? 1 : 0;
        s.temperatureC = static_cast<float>(d.feedback().temperatureDeciC) * 0.1F;
    }
    status_.interlockTripped = interlock_.tripped() ? 1 : 0;
    (void)bus_.publish(status_);
    publishNodes(now);
}

void CanIoTask::publishNodes(core::TimeNs now) {
    nodes_.timeNs = now;
    nodes_.heartbeatTimeoutNs = heartbeatTimeout_;
    for (std::size_t i = 0; i < msg::kMonitoredNodeCount; ++i) {
        const std::uint8_t id = monitoredNodeId(i);
        const hal::canopen::NodeHealth* h = master_.heartbeats().node(id);
        msg::NodeLiveness& n = nodes_.nodes[i];
        n.nodeId = id;
        n.lastSeenNs = h != nullptr ? h->lastSeen : 0;
        n.losses = h != nullptr ? h->losses : 0;
        n.nmtState = h != nullptr ? static_cast<std::uint8_t>(h->state) : 0;
        n.lost = h != nullptr && h->lost ? 1 : 0;
        n.everSeen = h != nullptr && h->everSeen ? 1 : 0;
    }
    (void)bus_.publish(nodes_);
}

void CanIoTask::publishSensors(const core::FrameContext& frame) {
    const core::TimeNs now = frame.actualStart;
    if (imu_.latest().count != imuSeen_) {
        imuSeen_ = imu_.latest().count;
        const msg::ImuMsg m{imu_.latest().time, imu_.latest().yawRateRadS,
                            static_cast<std::uint8_t>(imu_.latest().valid ? 1 : 0), {}};
        (void)bus_.publish(m);
    }
    if (power_.latest().count != powerSeen_) {
        powerSeen_ = power_.latest().count;
        const hal::PowerSample& p = power_.latest();
        (void)bus_.publish(msg::PowerMsg{p.time, p.busVoltageV, p.busCurrentA, p.stateOfCharge, p.solarCurrentA});
    }
    if (fix_.latest().count != fixSeen_) {
        fixSeen_ = fix_.latest().count;
        const hal::PositionFix& f = fix_.latest();
        (void)bus_.publish(msg::PositionFixMsg{f.time, f.xM, f.yM, f.headingRad, f.sigmaM});
    }
    if (frame.frame % 10 == 0) {
        msg::HazardMsg h{};
        h.timeNs = now;
        h.detectorFrames = hazard_.frameStats().accepted;
        for (const hal::HazardSighting& s : hazard_.sightings()) {
            if (h.count < msg::kMaxHazardsInMsg) {
                h.sightings[h.count++] = msg::HazardSightingTlm{s.rangeM, s.bearingRad, s.halfWidthM, s.obstacleId, {}};
            }
        }
        (void)bus_.publish(h);
    }
}

}  // namespace rse::io
