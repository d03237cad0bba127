#include "fsw/app/telemetry_task.hpp"

#include <algorithm>
#include <cstring>

#include "fsw/app/app_events.hpp"

namespace rse::app {

core::Status TelemetryTask::init() {
    // This task runs every frame, so the pipe holds one frame's messages at
    // most (kTelemetryPipeDepth).
    core::Status status = bus_.createPipe("telemetry", kTelemetryPipeDepth, &pipe_);
    const core::MsgId ids[] = {msg::ids::kDriveStatus, msg::ids::kWheelCommand, msg::ids::kPoseEstimate,
                               msg::ids::kFaultStatus, msg::ids::kDriveModes, msg::ids::kMode,
                               msg::ids::kGoalList, msg::ids::kPlanStatus, msg::ids::kFaultProtectionStatus,
                               msg::ids::kMissionHold, msg::ids::kInstrumentStatus,
                               msg::ids::kPlanExecutiveStatus, msg::ids::kPlanPath,
                               msg::ids::kPower, msg::ids::kKnownHazards};
    for (const core::MsgId id : ids) {
        if (core::isOk(status)) {
            status = bus_.subscribe(pipe_, id);
        }
    }
    return status;
}

void TelemetryTask::run(const core::FrameContext& frame) {
    takeBusMessages();
    sendEvents();
    if (frame.slot == 0 || hkRequested_) {
        hkRequested_ = false;
        sendHousekeeping(frame.actualStart);
    }
    if (frame.slot >= kTaskTimingSlot && frame.slot < kTaskTimingSlot + hkMsg_.taskCount) {
        sendTaskTiming(frame.slot - kTaskTimingSlot);
    }
    if (frame.slot == kDrivesSlot) {
        sendDrives();
    }
    if (frame.slot == kRoverStateSlot) {
        sendRoverState();
    }
    if (frame.slot == kHealthSlot || healthChanged_) {
        healthChanged_ = false;
        sendHealth();
    }
    if (frame.slot == kFaultProtectionSlot || protectionChanged_) {
        protectionChanged_ = false;
        sendFaultProtection();
    }
    if (frame.slot == kInstrumentsSlot || instrumentsChanged_) {
        instrumentsChanged_ = false;
        sendInstruments();
    }
    if (frame.slot == kPlanExecSlot || planExecChanged_) {
        planExecChanged_ = false;
        sendPlanExec();
    }
    if (frame.slot == kPowerSlot) {
        sendPower();
    }
    if (frame.slot == kHazardsSlot && (hazardsChanged_ || frame.frame % kHazardsPeriodFrames == kHazardsSlot)) {
        hazardsChanged_ = false;
        sendHazards();
    }
    if (planChanged_ || frame.frame % kPlanPeriodFrames == 0) {
        planChanged_ = false;
        sendPlan();
    }
}

void TelemetryTask::takeBusMessages() {
    // Bounded by the pipe depth.
    while (core::isOk(bus_.receive(pipe_, &inbox_))) {
        // A message that does not decode leaves the last good one in place.
        core::Status status = core::Status::kWrongType;
        switch (inbox_.header.id) {
            case msg::ids::kDriveStatus: status = inbox_.decode(&drives_); break;
            case msg::ids::kWheelCommand: status = inbox_.decode(&wheelCommand_); break;
            case msg::ids::kPoseEstimate: status = inbox_.decode(&pose_); break;
            case msg::ids::kFaultStatus: {
                const std::uint64_t before = faults_.activeMask;
                status = inbox_.decode(&faults_);
                healthChanged_ = healthChanged_ || (core::isOk(status) && faults_.activeMask != before);
                break;
            }
            case msg::ids::kDriveModes: {
                msg::DriveMode before[msg::kWheelCount];
                for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
                    before[w] = driveModes_.drives[w].declared;
                }
                status = inbox_.decode(&driveModes_);
                for (std::size_t w = 0; w < msg::kWheelCount && core::isOk(status); ++w) {
                    healthChanged_ = healthChanged_ || driveModes_.drives[w].declared != before[w];
                }
                break;
            }
            case msg::ids::kMode: status = inbox_.decode(&mode_); break;
            case msg::ids::kMissionHold: status = inbox_.decode(&hold_); break;
            case msg::ids::kFaultProtectionStatus: {
                // Published at 1 Hz and on every change: each one is news here.
                status = inbox_.decode(&protection_);
                protectionChanged_ = protectionChanged_ || core::isOk(status);
                break;
            }
            case msg::ids::kInstrumentStatus: {
                msg::InstrumentStatusMsg m{};
                status = inbox_.decode(&m);
                const auto i = static_cast<std::size_t>(m.instrument);
                if (core::isOk(status) && i >= msg::kInstrumentCount) {
                    status = core::Status::kInvalidArgument;
                }
                if (core::isOk(status)) {
                    const msg::InstrumentStatusMsg& before = instruments_[i];
                    instrumentsChanged_ = instrumentsChanged_ || m.state != before.state ||
                                          m.commandId != before.commandId || m.result != before.result ||
                                          m.faultCode != before.faultCode || m.lastRefusal != before.lastRefusal ||
                                          m.lastRefusedCommandId != before.lastRefusedCommandId;
                    instruments_[i] = m;
                }
                break;
            }
            case msg::ids::kPlanExecutiveStatus: {
                // Published at 1 Hz and on change; slack and plan time alone are not news.
                msg::PlanExecutiveStatusMsg m{};
                status = inbox_.decode(&m);
                if (core::isOk(status)) {
                    msg::PlanExecutiveStatusMsg a = m;
                    msg::PlanExecutiveStatusMsg b = planExec_;
                    a.timeNs = b.timeNs = 0;
                    a.slackMs = b.slackMs = 0;
                    a.planTimeMs = b.planTimeMs = 0;
                    planExecChanged_ = planExecChanged_ || std::memcmp(&a, &b, sizeof a) != 0;
                    planExec_ = m;
                }
                break;
            }
            case msg::ids::kPlanPath:
                // News every time: one PLAN_PATH per plan made, sent at once.
                status = inbox_.decode(&planPath_);
                if (core::isOk(status) && planPath_.steps >= msg::kPlanPathMeans) {
                    status = core::Status::kInvalidArgument;  // more means than the message holds
                }
                if (core::isOk(status)) {
                    sendPlanPath(planPath_);
                }
                break;
            case msg::ids::kPower: status = inbox_.decode(&power_); break;
            case msg::ids::kKnownHazards: {
                msg::KnownHazardsMsg m{};
                status = inbox_.decode(&m);
                if (core::isOk(status) && m.count > msg::kMaxKnownHazards) {
                    status = core::Status::kInvalidArgument;  // more hazards than the message holds
                }
                if (core::isOk(status)) {
                    // Published at 1 Hz and on change: only a new revision is news.
                    hazardsChanged_ = hazardsChanged_ || m.revision != hazards_.revision;
                    hazards_ = m;
                }
                break;
            }
            case msg::ids::kGoalList:
                status = inbox_.decode(&goals_);
                planChanged_ = planChanged_ || core::isOk(status);
                break;
            case msg::ids::kPlanStatus: {
                // Published at 1 Hz and on change; PLAN goes out when what it shows changes.
                const msg::PlanStatusMsg before = planStatus_;
                status = inbox_.decode(&planStatus_);
                planChanged_ = planChanged_ ||
                               (core::isOk(status) &&
                                (planStatus_.state != before.state || planStatus_.legIndex != before.legIndex ||
                                 planStatus_.plansMade != before.plansMade || planStatus_.callHomes != before.callHomes ||
                                 planStatus_.currentLegId != before.currentLegId ||
                                 planStatus_.riskInForce != before.riskInForce));
                break;
            }
            default: break;
        }
        if (!core::isOk(status)) {
            ++malformed_;
            if (core::isReportableOccurrence(malformed_)) {
                events_.report(events::kBusMessageMalformed, core::Severity::kError,
                               "app: telemetry ignored a malformed bus message 0x%04x (%u so far)",
                               static_cast<unsigned>(inbox_.header.id), static_cast<unsigned>(malformed_));
            }
        }
    }
}

void TelemetryTask::sendEvents() {
    // No more than the slowest link's event queue takes: the rest wait in the
    // event log (kEventRingDepth), so a burst on the CAN link goes down late
    // instead of being refused; only a backlog beyond the log is lost (counted,
    // HK.events_lost).
    const std::size_t budget = std::min(kEventsPerFrame, output_.room(hal::TxPriority::kEvent));
    core::Event event;
    for (std::size_t i = 0; i < budget && core::isOk(events_.pop(&event)); ++i) {
        cmdtlm::EVENT_Tlm tlm{};
        tlm.event_sequence = event.sequence;
        tlm.event_time = static_cast<double>(event.time) / static_cast<double>(core::kNsPerSec);
        tlm.event_id = event.id;
        tlm.severity = static_cast<std::uint8_t>(event.severity);
        std::memcpy(tlm.text, event.text, std::min(sizeof tlm.text, sizeof event.text));
        output_.send(tlm);
        ++eventsSent_;
    }
}

void TelemetryTask::sendHousekeeping(core::TimeNs now) {
    sources_.housekeeping.collect(&hkMsg_, now);
    const cmdtlm::CommandCounters& c = sources_.commands.counters();
    const hal::CanBusStats& can = sources_.can.stats();
    hk_ = cmdtlm::HK_Tlm{};
    hk_.utc_at_met_zero = sources_.utcAtMetZero;
    hk_.mode = mode_.mode;
    hk_.estop = mode_.estop;
    hk_.auth_required = sources_.commands.authRequired() ? 1 : 0;
    hk_.lab_key_in_use = sources_.commands.labKeyInUse() ? 1 : 0;
    hk_.time_scale = sources_.timeScale;
    hk_.cmd_queue_depth = c.queueDepth;
    hk_.cmd_accepted = c.accepted;
    hk_.cmd_rejected = c.rejected;
    for (std::size_t i = 0; i < cmdtlm::kRejectReasonCount; ++i) {
        hk_.cmd_rejected_by_reason[i] = c.byReason[i];
    }
    hk_.last_cmd_apid = c.lastApid;
    hk_.last_cmd_fc = c.lastFunctionCode;
    hk_.last_cmd_result = static_cast<std::uint8_t>(c.lastResult);
    hk_.frames_run = hkMsg_.framesRun;
    hk_.frame_overruns = hkMsg_.frameOverruns;
    hk_.frames_skipped = hkMsg_.framesSkipped;
    hk_.frame_busy_last_us = hkMsg_.frameBusyLastUs;
    hk_.frame_busy_max_us = hkMsg_.frameBusyMaxUs;
    hk_.frame_lateness_max_us = hkMsg_.frameLatenessMaxUs;
    hk_.task_count = hkMsg_.taskCount;
    hk_.bus_published = hkMsg_.busPublished;
    hk_.bus_dropped = hkMsg_.busDropped;
    hk_.bus_rejected = hkMsg_.busRejectedTooLarge;
    hk_.events_total = hkMsg_.eventsTotal;
    hk_.events_lost = hkMsg_.eventsLost;
    for (std::size_t i = 0; i < core::kSeverityCount; ++i) {
        hk_.events_by_severity[i] = hkMsg_.eventsBySeverity[i];
    }
    hk_.can_rx_frames = can.rxFrames;
    hk_.can_tx_frames = can.txFrames;
    hk_.can_tx_refused = can.txInvalid + can.txUnavailable + can.txBufferFull;
    hk_.can_rx_overruns = can.rxOverruns;
    hk_.can_error_frames = can.errorFrames;
    hk_.can_bus_off = can.busOffCount;
    hk_.tlm_sent = output_.sent();
    hk_.tlm_dropped = output_.dropped();
    hk_.table_activations = sources_.tables.activations();
    hk_.table_rejects = sources_.tables.rejects();
    const cmdtlm::AntiReplayState& replay = sources_.commands.antiReplay();
    hk_.auth_store_state = static_cast<std::uint8_t>(replay.state());
    hk_.auth_keys_unsynced = sources_.commands.keysUnsynced();
    hk_.auth_challenge_high = static_cast<std::uint32_t>(replay.challenge() >> 32);
    hk_.auth_challenge_low = static_cast<std::uint32_t>(replay.challenge());
    hk_.auth_store_writes = replay.writes();
    hk_.auth_store_write_failures = replay.writeFailures();
    hk_.auth_store_wait_frames = c.storeWaitFrames;
    hk_.link_rx_packets = c.linkRxPackets;
    hk_.link_rx_dropped = c.linkRxDropped;
    hk_.link_rx_kernel_drops = c.linkRxKernelDropped;
    hk_.cmd_ingest_limited = c.ingestLimited;
    hk_.cmd_acks_suppressed = c.acksSuppressed;
    output_.send(hk_);
    ++housekeepingSent_;
}

// From the housekeeping collection of the last HK, so all rows are of one instant.
void TelemetryTask::sendTaskTiming(std::size_t index) {
    if (index >= hkMsg_.taskCount || index >= core::kMaxTasks) {
        return;
    }
    const msg::TaskTimingTlm& t = hkMsg_.tasks[index];
    cmdtlm::TASK_TIMING_Tlm tlm{};
    tlm.task_index = static_cast<std::uint8_t>(index);
    std::memcpy(tlm.task_name, t.name, std::min(sizeof tlm.task_name, sizeof t.name));
    tlm.runs = t.runs;
    tlm.over_budget = t.overBudget;
    tlm.last_us = t.lastUs;
    tlm.mean_us = t.meanUs;
    tlm.max_us = t.maxUs;
    tlm.cpu_mean_us = t.hostMeanUs;
    tlm.cpu_max_us = t.hostMaxUs;
    tlm.cpu_timed = t.cpuTimed ? 1 : 0;
    tlm.cpu_over_budget = t.cpuOverBudget;
    output_.send(tlm);
}

void TelemetryTask::sendDrives() {
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
    output_.send(tlm);
}

void TelemetryTask::sendRoverState() {
    cmdtlm::ROVER_STATE_Tlm tlm{};
    tlm.estimate_valid = pose_.initialised;
    tlm.yaw_from_imu = pose_.yawFromImu;
    tlm.x = pose_.xM;
    tlm.y = pose_.yM;
    tlm.heading = pose_.headingRad;
    for (std::size_t i = 0; i < 9; ++i) {
        tlm.covariance[i] = static_cast<float>(pose_.covariance[i]);
    }
    tlm.position_sigma = static_cast<float>(pose_.positionSigmaM);
    tlm.speed = static_cast<float>(pose_.speedMS);
    tlm.turn_rate = static_cast<float>(pose_.yawRateRadS);
    tlm.gyro_bias = static_cast<float>(pose_.gyroBiasRadS);
    tlm.fixes_accepted = pose_.fixesAccepted;
    tlm.fixes_rejected = pose_.fixesRejected;
    tlm.fixes_invalid = pose_.fixesInvalid;
    output_.send(tlm);
}

void TelemetryTask::sendHealth() {
    cmdtlm::HEALTH_Tlm tlm{};
    tlm.active_faults = faults_.activeMask;
    tlm.faults_raised = faults_.raisedTotal;
    tlm.faults_cleared = faults_.clearedTotal;
    tlm.last_fault_id = faults_.lastFaultId;
    tlm.last_fault_raised = faults_.lastRaised;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        const msg::DriveModeBelief& b = driveModes_.drives[w];
        tlm.drive_mode[w] = static_cast<std::uint8_t>(b.declared);
        tlm.p_nominal[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kNominal)];
        tlm.p_degraded[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kDegraded)];
        tlm.p_failed[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kFailed)];
        tlm.p_unknown[w] = b.probability[static_cast<std::size_t>(msg::DriveMode::kUnknown)];
        tlm.power_factor[w] = b.powerFactor;
    }
    output_.send(tlm);
}

void TelemetryTask::sendPlan() {
    plan_ = cmdtlm::PLAN_Tlm{};
    const msg::PlanStatusMsg& p = planStatus_;
    plan_.status = static_cast<std::uint8_t>(p.state);
    plan_.plan_status = p.planStatus;
    plan_.call_home = static_cast<std::uint8_t>(p.callHome);
    plan_.goal_count = goals_.count;
    plan_.goal_index = p.goalIndex;
    plan_.leg_count = p.legCount;
    plan_.leg_index = p.legIndex;
    plan_.waypoint_count = p.shownLegs;
    plan_.risk_bound = goals_.riskBound;
    plan_.risk_in_force = p.riskInForce;
    plan_.risk_used = p.riskUsed;
    plan_.plan_length = static_cast<float>(p.planLengthM);
    plan_.plan_gap = static_cast<float>(p.planGap);
    plan_.current_leg_id = p.currentLegId;
    plan_.replans = p.replans;
    plan_.risk_relaxations = p.riskRelaxations;
    plan_.bound_relaxations = p.boundRelaxations;
    plan_.call_homes = p.callHomes;
    for (std::size_t i = 0; i < goals_.count && i < msg::kMaxGoals; ++i) {
        plan_.goal_x[i] = static_cast<float>(goals_.goals[i].xM);
        plan_.goal_y[i] = static_cast<float>(goals_.goals[i].yM);
        plan_.priority[i] = goals_.goals[i].priority;
    }
    for (std::size_t i = 0; i < p.shownLegs && i < msg::kPlanStatusLegs; ++i) {
        plan_.waypoint_x[i] = static_cast<float>(p.legs[i].xM);
        plan_.waypoint_y[i] = static_cast<float>(p.legs[i].yM);
        plan_.leg_risk[i] = static_cast<float>(p.legs[i].risk);
        plan_.leg_length_bound[i] = static_cast<float>(p.legs[i].lengthM);
        plan_.leg_energy_bound[i] = static_cast<float>(p.legs[i].energyJ / 3600.0);
    }
    output_.send(plan_);
}

void TelemetryTask::sendPlanPath(const msg::PlanPathMsg& m) {
    planPathTlm_ = cmdtlm::PLAN_PATH_Tlm{};
    cmdtlm::PLAN_PATH_Tlm& t = planPathTlm_;
    t.plan_number = m.planNumber;
    t.plan_time = static_cast<double>(m.timeNs) / static_cast<double>(core::kNsPerSec);
    t.status = m.status;
    static_assert(sizeof t.mean_x / sizeof t.mean_x[0] == msg::kPlanPathMeans, "PLAN_PATH holds every mean");
    const std::size_t steps = m.steps < msg::kPlanPathMeans ? m.steps : msg::kPlanPathMeans - 1;  // checked on receipt
    t.steps = static_cast<std::uint8_t>(steps);
    t.risk_bound = m.riskBound;
    t.risk_used = m.riskUsed;
    t.length = static_cast<float>(m.lengthM);
    t.process_sigma = static_cast<float>(m.processSigmaM);
    for (std::size_t i = 0; i < 4; ++i) {
        t.start_cov[i] = static_cast<float>(m.startCov[i]);
    }
    t.goal_x = static_cast<float>(m.goalX);
    t.goal_y = static_cast<float>(m.goalY);
    for (std::size_t i = 0; i <= steps; ++i) {
        t.mean_x[i] = static_cast<float>(m.meanX[i]);
        t.mean_y[i] = static_cast<float>(m.meanY[i]);
    }
    output_.send(t);
    ++planPathsSent_;
}

void TelemetryTask::sendPower() {
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
    output_.send(tlm);
}

void TelemetryTask::sendHazards() {
    static_assert(sizeof hazardsTlm_.x / sizeof hazardsTlm_.x[0] == msg::kMaxKnownHazards,
                  "HAZARDS holds every hazard the message can carry");
    static_assert(cmdtlm::kHAZARDS_TlmSize + cmdtlm::kTelemetryHeaderSize <= cmdtlm::kMaxTelemetryPacket,
                  "HAZARDS fits in one telemetry packet");
    hazardsTlm_ = cmdtlm::HAZARDS_Tlm{};
    cmdtlm::HAZARDS_Tlm& t = hazardsTlm_;
    t.revision = hazards_.revision;
    const std::size_t count = std::min<std::size_t>(hazards_.count, msg::kMaxKnownHazards);  // checked on receipt
    t.count = static_cast<std::uint8_t>(count);
    for (std::size_t i = 0; i < count; ++i) {
        const msg::KnownHazard& h = hazards_.hazards[i];
        t.x[i] = h.xM;
        t.y[i] = h.yM;
        t.radius[i] = h.radiusM;
        t.obstacle_id[i] = h.obstacleId;
    }
    output_.send(t);
    ++hazardsSent_;
}

void TelemetryTask::sendTableStatus(tables::TableId id, const tables::TableCheck& check) {
    const tables::TableStatus s = sources_.tables.status(id);
    cmdtlm::TABLE_STATUS_Tlm tlm{};
    tlm.table_id = static_cast<std::uint16_t>(id);
    tlm.inactive_state = static_cast<std::uint8_t>(s.inactiveState);
    tlm.inactive_length = static_cast<std::uint16_t>(s.inactiveLength);
    tlm.active_version = s.activeVersion;
    tlm.active_crc = s.activeCrc;
    tlm.last_reject = static_cast<std::uint8_t>(check.reason);
    tlm.last_reject_field = check.field;
    tlm.activations = s.activations;
    output_.send(tlm);
}

core::Status TelemetryTask::sendTableDump(tables::TableId id, bool inactive) {
    std::size_t length = 0;
    const tables::TableCheck check = sources_.tables.dump(id, inactive, image_, sizeof image_, &length);
    if (check.reason != tables::TableReject::kNone) {
        return core::Status::kNotFound;
    }
    // Bounded: kMaxTableImageSize / sizeof data chunks.
    for (std::size_t offset = 0; offset < length; offset += sizeof dump_.data) {
        dump_ = cmdtlm::TABLE_DUMP_Tlm{};
        dump_.table_id = static_cast<std::uint16_t>(id);
        dump_.buffer = inactive ? 1 : 0;
        dump_.total_length = static_cast<std::uint16_t>(length);
        dump_.offset = static_cast<std::uint16_t>(offset);
        const std::size_t chunk = std::min(sizeof dump_.data, length - offset);
        dump_.length = static_cast<std::uint16_t>(chunk);
        std::memcpy(dump_.data, image_ + offset, chunk);
        output_.send(dump_);
    }
    return core::Status::kOk;
}

void TelemetryTask::sendFaultProtection() {
    cmdtlm::FAULT_PROTECTION_Tlm tlm{};
    const msg::FaultProtectionStatusMsg& p = protection_;
    tlm.hold_reasons = p.holdReasons;
    tlm.hold_estop = hold_.estop;
    tlm.resume_count = hold_.resumeCount;
    tlm.responses_started = p.responsesStarted;
    tlm.recoveries = p.recoveries;
    tlm.gave_up = p.gaveUp;
    tlm.actions_sent = p.actionsSent;
    tlm.response_count = std::min<std::uint8_t>(p.activeCount, static_cast<std::uint8_t>(msg::kResponseSlots));
    for (std::size_t i = 0; i < tlm.response_count; ++i) {
        const msg::ResponseTlm& r = p.responses[i];
        tlm.fault_id[i] = r.faultId;
        tlm.fault_class[i] = static_cast<std::uint8_t>(r.faultClass);
        tlm.state[i] = static_cast<std::uint8_t>(r.state);
        tlm.attempts_used[i] = r.attemptsUsed;
        tlm.last_action[i] = r.lastAction;
        tlm.state_since[i] = static_cast<float>(static_cast<double>(r.sinceNs) / static_cast<double>(core::kNsPerSec));
    }
    output_.send(tlm);
}

void TelemetryTask::sendPlanExec() {
    cmdtlm::PLAN_EXEC_Tlm tlm{};
    const msg::PlanExecutiveStatusMsg& m = planExec_;
    tlm.state = static_cast<std::uint8_t>(m.state);
    std::memcpy(tlm.plan_name, m.planName, std::min(sizeof tlm.plan_name, sizeof m.planName));
    tlm.selection_status = m.selectionStatus;
    tlm.cost = m.cost;
    tlm.cost_before = m.costBefore;
    tlm.choice_count = m.choiceCount;
    std::memcpy(tlm.options, m.options, std::min(sizeof tlm.options, sizeof m.options));
    tlm.activity_count = m.activityCount;
    tlm.running = m.running;
    std::memcpy(tlm.activity_states, m.activityStates, std::min(sizeof tlm.activity_states, sizeof m.activityStates));
    tlm.deprecated = m.deprecatedCount;
    tlm.slack = m.slackMs;
    tlm.plan_time = m.planTimeMs;
    tlm.plans_accepted = m.plansAccepted;
    tlm.plans_refused = m.plansRefused;
    tlm.regenerations = m.regenerations;
    tlm.started = m.activitiesStarted;
    tlm.completed = m.activitiesCompleted;
    tlm.early = m.activitiesEarly;
    tlm.late = m.activitiesLate;
    tlm.failed = m.activitiesFailed;
    tlm.operator_calls = m.operatorCalls;
    tlm.last_refusal = static_cast<std::uint8_t>(m.lastRefusal);
    tlm.parse_error = m.lastParseError;
    tlm.refusal_line = m.refusalLine;
    std::memcpy(tlm.refusal_token, m.refusalToken, std::min(sizeof tlm.refusal_token, sizeof m.refusalToken));
    tlm.last_regeneration = static_cast<std::uint8_t>(m.lastRegeneration);
    tlm.call_home = m.callHomeReason;
    tlm.extensions = m.extensionsAccepted;
    tlm.extensions_refused = m.extensionsRefused;
    tlm.last_extension_refusal = static_cast<std::uint8_t>(m.lastExtensionRefusal);
    output_.send(tlm);
}

void TelemetryTask::sendInstruments() {
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
    output_.send(tlm);
}

}  // namespace rse::app
