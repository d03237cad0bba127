#include "ground/mission_telemetry.hpp"

#include <cmath>
#include <cstdio>

#include "fsw/cmdtlm/dictionary.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/habitual/habitual_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/plan_executive/plan_executive_events.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {

namespace {

namespace dev = deliberative::events;
namespace fpev = fault_protection::events;

constexpr double kMinorFrameS = 0.01;  // rse-fsw's minor frame (app::kMinorFramePeriod): HK counts them
constexpr std::uint8_t kPlanExecFailed = 5;  // PLAN_EXEC.state: no method remains, operator called

double number(const DecodedPacket& p, const char* field, std::size_t index = 0) {
    return p.value(field, index).value_or(0.0);
}

std::string fixed(double value, int decimals) {
    char text[64];
    std::snprintf(text, sizeof text, "%.*f", decimals, value);
    return text;
}

std::string shortNumber(double value) {
    char text[32];
    std::snprintf(text, sizeof text, "%.3g", value);
    return text;
}

std::string eventLine(const TelemetryEvent& e) {
    return "EVT " + std::to_string(e.id) + " " + severityName(e.severity) + " " + e.text;
}

}  // namespace

const char* toString(TelemetryOutcome outcome) {
    switch (outcome) {
        case TelemetryOutcome::kNone: return "none";
        case TelemetryOutcome::kGoalReached: return "goal reached";
        case TelemetryOutcome::kCalledHome: return "called home";
    }
    return "?";
}

void MissionTelemetryReader::add(double receivedS, const std::vector<std::uint8_t>& bytes) {
    add(receivedS, decodeTelemetry(bytes));
}

void MissionTelemetryReader::add(double receivedS, const DecodedPacket& p) {
    MissionTelemetry& m = mission_;
    if (m.packets == 0) {
        firstReceivedS_ = receivedS;
    }
    ++m.packets;
    m.receivedSpanS = receivedS - firstReceivedS_;
    if (!p.ok) {
        ++m.undecoded;
        return;
    }
    m.firstMetS = m.firstMetS < 0.0 ? p.met : m.firstMetS;
    m.lastMetS = p.met;
    const std::string name = p.name();
    if (name == "EVENT") {
        onEvent(receivedS, p);
    } else if (name == "EVENT_DATA") {
        onEventData(p);
    } else if (name == "PLAN") {
        onPlan(p);
    } else if (name == "HK") {
        onHousekeeping(p);
    } else if (name == "ROVER_STATE") {
        if (number(p, "estimate_valid") != 0.0) {
            TelemetryPose pose;
            pose.metS = p.met;
            pose.xM = number(p, "x");
            pose.yM = number(p, "y");
            pose.headingRad = number(p, "heading");
            pose.sigmaM = number(p, "position_sigma");
            m.track.push_back(pose);
            m.finalPose = pose;
            m.poseKnown = true;
        }
    } else if (name == "HEALTH") {
        if (const DecodedField* f = p.field("active_faults"); f != nullptr && !f->raw.empty()) {
            const std::uint64_t mask = f->raw[0];
            for (unsigned id = 0; id < 64; ++id) {
                if (((mask >> id) & 1U) != 0) {
                    m.faultsSeen.insert(id);
                }
            }
        }
    } else if (name == "CMD_ACK") {
        (number(p, "reason") == 0.0 ? m.commandsAccepted : m.commandsRejected)++;
    } else if (name == "PLAN_EXEC") {
        if (sawGoal_ && static_cast<int>(number(p, "state")) == kPlanExecFailed) {
            decide(TelemetryOutcome::kCalledHome, p.met, static_cast<std::uint8_t>(number(p, "call_home")),
                   "plan executive");
        }
    }
}

void MissionTelemetryReader::onEvent(double receivedS, const DecodedPacket& p) {
    MissionTelemetry& m = mission_;
    TelemetryEvent e;
    e.metS = number(p, "event_time");
    e.receivedS = receivedS;
    e.sequence = static_cast<std::uint32_t>(number(p, "event_sequence"));
    e.id = static_cast<std::uint16_t>(number(p, "event_id"));
    e.severity = static_cast<std::uint8_t>(number(p, "severity"));
    if (const DecodedField* f = p.field("text"); f != nullptr) {
        e.text = f->text;
    }
    ++m.eventsReceived;
    if (haveEventSequence_ && e.sequence > nextEventSequence_) {
        m.eventsLost += e.sequence - nextEventSequence_;
    }
    if (!haveEventSequence_ || e.sequence >= nextEventSequence_) {
        nextEventSequence_ = e.sequence + 1;
        haveEventSequence_ = true;
    }
    m.plansMade += e.id == dev::kPlanFound ? 1U : 0U;
    m.legsSent += e.id == dev::kLegSent ? 1U : 0U;
    m.legsAchieved += e.id == dev::kLegAchieved ? 1U : 0U;
    m.goalsReached += e.id == dev::kGoalReached ? 1U : 0U;
    m.failUps += e.id == dev::kFailUpReceived ? 1U : 0U;
    m.habitualFailUps += e.id == habitual::events::kFailUp ? 1U : 0U;
    if (e.id == dev::kCallHome) {
        lastCallHomeEvent_ = eventLine(e);
    } else if (e.id == fpev::kGaveUp) {
        lastGaveUpEvent_ = eventLine(e);
    } else if (e.id == plan_executive::events::kOperatorCalled) {
        lastPlanExecEvent_ = eventLine(e);
    }
    pairing_.onEvent(e.sequence, e.id, m.events.size());
    m.eventsWithoutData = pairing_.missing();
    m.events.push_back(e);
    // The status that decided the outcome can come down before the event that
    // says why (both from one frame): the event completes it when it comes.
    if (m.outcome == TelemetryOutcome::kCalledHome && m.callHomeEvent.empty()) {
        m.callHomeEvent = callHomeWords(m.callHomeBy);
    }
    if (e.id == fpev::kCallHome && sawGoal_) {
        // Fault protection's call home: the give-up before it says why.
        decide(TelemetryOutcome::kCalledHome, e.metS, static_cast<std::uint8_t>(msg::CallHomeReason::kFaultUnrecovered),
               "fault protection");
    }
}

void MissionTelemetryReader::onEventData(const DecodedPacket& p) {
    MissionTelemetry& m = mission_;
    EventDataPacket data;
    if (!readEventData(p, &data)) {
        return;
    }
    if (const std::optional<std::size_t> event = pairing_.onData(data); event.has_value() && *event < m.events.size()) {
        m.events[*event].data = data.data;
    }
    m.eventDataPaired = pairing_.paired();
    m.eventDataStray = pairing_.stray();
    m.eventsWithoutData = pairing_.missing();
    m.eventDataWithheld = pairing_.withheld();
}

void MissionTelemetryReader::onPlan(const DecodedPacket& p) {
    MissionTelemetry& m = mission_;
    const int status = static_cast<int>(number(p, "status"));
    m.finalPlanStatus = status;
    if (number(p, "goal_count") > 0.0) {
        m.goalCount = static_cast<std::uint8_t>(number(p, "goal_count"));
        m.goalX = number(p, "goal_x", 0);
        m.goalY = number(p, "goal_y", 0);
        m.riskBound = number(p, "risk_bound");
        m.riskInForce = number(p, "risk_in_force");
        m.riskUsed = number(p, "risk_used");
        m.planLengthM = number(p, "plan_length");
    }
    m.replans = static_cast<std::uint32_t>(number(p, "replans"));
    m.boundRelaxations = static_cast<std::uint32_t>(number(p, "bound_relaxations"));
    m.riskRelaxations = static_cast<std::uint32_t>(number(p, "risk_relaxations"));
    m.callHomes = static_cast<std::uint32_t>(number(p, "call_homes"));
    m.siteMode = number(p, "site_mode") > 0.0;
    m.horizonsReached = static_cast<std::uint32_t>(number(p, "horizons_reached"));
    m.horizonsDrivenThrough = static_cast<std::uint32_t>(number(p, "horizons_driven_through"));
    m.horizonStops = static_cast<std::uint32_t>(number(p, "horizon_stops"));
    const auto state = static_cast<msg::DeliberativeState>(status);
    if (state == msg::DeliberativeState::kWaiting || state == msg::DeliberativeState::kPlanning ||
        state == msg::DeliberativeState::kExecuting) {
        sawGoal_ = true;
    } else if (sawGoal_ && state == msg::DeliberativeState::kComplete) {
        decide(TelemetryOutcome::kGoalReached, p.met, 0, "");
    } else if (sawGoal_ && state == msg::DeliberativeState::kCalledHome) {
        decide(TelemetryOutcome::kCalledHome, p.met, static_cast<std::uint8_t>(number(p, "call_home")),
               "deliberative layer");
    }
}

void MissionTelemetryReader::onHousekeeping(const DecodedPacket& p) {
    MissionTelemetry& m = mission_;
    m.finalMode = static_cast<int>(number(p, "mode"));
    m.timeScale = static_cast<std::uint32_t>(number(p, "time_scale"));
    m.timingKnown = true;
    if (const DecodedField* f = p.field("frames_run"); f != nullptr && !f->raw.empty()) {
        m.framesRun = f->raw[0];
    }
    m.frameOverruns = static_cast<std::uint32_t>(number(p, "frame_overruns"));
    m.framesSkipped = static_cast<std::uint32_t>(number(p, "frames_skipped"));
    m.frameLatenessMaxUs = static_cast<std::uint32_t>(number(p, "frame_lateness_max_us"));
    m.frameBusyMaxUs = static_cast<std::uint32_t>(number(p, "frame_busy_max_us"));
    m.telemetryDropped = static_cast<std::uint32_t>(number(p, "tlm_dropped"));
    m.eventLogLost = static_cast<std::uint32_t>(number(p, "events_lost"));
    if (!m.flightStartKnown) {
        // HK goes out at the start of a frame: the frames counted so far (run
        // and skipped) are the time since the executive started.
        m.flightStartMetS = p.met - static_cast<double>(m.framesRun + m.framesSkipped) * kMinorFrameS;
        m.flightStartKnown = true;
    }
}

void MissionTelemetryReader::decide(TelemetryOutcome outcome, double metS, std::uint8_t reason, const char* by) {
    MissionTelemetry& m = mission_;
    if (m.outcome != TelemetryOutcome::kNone) {
        return;  // the first outcome stands
    }
    m.outcome = outcome;
    m.outcomeMetS = metS;
    m.callHomeReason = reason;
    m.callHomeBy = by;
    if (outcome == TelemetryOutcome::kCalledHome) {
        m.callHomeEvent = callHomeWords(m.callHomeBy);
    }
}

// The CRIT event of whoever called home, the last one received (empty: none yet).
const std::string& MissionTelemetryReader::callHomeWords(const std::string& by) const {
    return by == "fault protection" ? lastGaveUpEvent_ : by == "plan executive" ? lastPlanExecEvent_ : lastCallHomeEvent_;
}

MissionTelemetry readMissionTelemetry(const SessionRecording& recording) {
    MissionTelemetryReader reader;
    for (const RecordedPacket& packet : recording.packets) {
        reader.add(packet.receivedS, packet.bytes);
    }
    MissionTelemetry m = reader.mission();
    m.link = recording.link;
    return m;
}

void printMissionTelemetry(const MissionTelemetry& m, std::ostream& out, bool eventsToo) {
    const auto t = [&](double metS) {
        return fixed(m.flightTime(metS), 2) + " s" + (m.flightStartKnown ? " (MET " + fixed(metS, 2) + ")" : "");
    };
    out << "=== mission from telemetry ===\n";
    out << "recording:  " << m.packets << " packets (" << m.undecoded << " undecoded) over " << fixed(m.receivedSpanS, 1)
        << " s on " << (m.link.empty() ? std::string("?") : m.link) << "\n";
    if (m.flightStartKnown) {
        out << "timeline:   flight time = MET - " << fixed(m.flightStartMetS, 2) << " s (rover start, from HK)";
        if (m.timeScale > 1) {
            out << "; time scale " << m.timeScale << ": 1 s of mission time every " << m.timeScale << " s";
        }
        out << "\n";
    }
    switch (m.outcome) {
        case TelemetryOutcome::kNone:
            out << "outcome:    none in the recording (PLAN status " << m.finalPlanStatus << ", mode " << m.finalMode
                << ")\n";
            break;
        case TelemetryOutcome::kGoalReached:
            out << "outcome:    goal reached at " << t(m.outcomeMetS) << "\n";
            break;
        case TelemetryOutcome::kCalledHome:
            out << "outcome:    called home at " << t(m.outcomeMetS) << ", reason " << unsigned{m.callHomeReason}
                << " (" << m.callHomeBy << ")\n";
            if (!m.callHomeEvent.empty()) {
                out << "            " << m.callHomeEvent << "\n";
            }
            break;
    }
    out << "goal:       " << unsigned{m.goalCount} << " goal(s), the first (" << fixed(m.goalX, 2) << ", "
        << fixed(m.goalY, 2) << "), risk bound " << shortNumber(m.riskBound) << " (in force "
        << shortNumber(m.riskInForce) << ", used " << shortNumber(m.riskUsed) << "), plan "
        << fixed(m.planLengthM, 2) << " m\n";
    if (m.poseKnown) {
        out << "final pose: (" << fixed(m.finalPose.xM, 2) << ", " << fixed(m.finalPose.yM, 2) << ") heading "
            << fixed(m.finalPose.headingRad * 180.0 / M_PI, 1) << " deg, sigma " << fixed(m.finalPose.sigmaM, 3)
            << " m at " << t(m.finalPose.metS) << " (estimate, ROVER_STATE); mode " << m.finalMode << "\n";
    } else {
        out << "final pose: no estimate received\n";
    }
    out << "legs:       " << m.plansMade << " plans, " << m.legsSent << " legs sent, " << m.legsAchieved
        << " reached, " << m.goalsReached << " goals reached; " << m.failUps << " fail-ups (" << m.habitualFailUps
        << " from the habitual layer), " << m.replans << " replans, " << m.boundRelaxations << " bound relaxations, "
        << m.riskRelaxations << " risk relaxations, " << m.callHomes << " call homes\n";
    if (m.siteMode) {
        out << "site:       " << m.horizonsReached << " horizon ends: " << m.horizonsDrivenThrough
            << " driven through (the next horizon planned while driving), " << m.horizonStops << " stops to plan\n";
    }
    out << "faults:     ";
    if (m.faultsSeen.empty()) {
        out << "none";
    }
    for (unsigned id : m.faultsSeen) {
        out << (id == *m.faultsSeen.begin() ? "" : " ") << id;
    }
    out << " (ids ever set in HEALTH.active_faults)\n";
    if (m.timingKnown) {
        out << "timing:     " << m.framesRun << " frames run, " << m.frameOverruns << " overruns, " << m.framesSkipped
            << " skipped; worst start lateness " << fixed(m.frameLatenessMaxUs / 1000.0, 3) << " ms, busiest frame "
            << fixed(m.frameBusyMaxUs / 1000.0, 3) << " ms (last HK, mission time)\n";
    }
    out << "link:       " << m.eventsReceived << " events received, " << m.eventsLost
        << " lost (event_sequence gaps); the rover dropped " << m.telemetryDropped
        << " packets (HK.tlm_dropped, since its start) and its event log overwrote " << m.eventLogLost
        << " events unsent (HK.events_lost); " << m.commandsAccepted << " commands acknowledged accepted, "
        << m.commandsRejected << " rejected\n";
    out << "event data: " << m.eventDataPaired << " EVENT_DATA paired with their events, " << m.eventsWithoutData
        << " events without their numbers (" << m.eventDataWithheld << " withheld by the rover), " << m.eventDataStray
        << " stray (their event never came)\n";
    if (eventsToo) {
        out << "events:\n";
        for (const TelemetryEvent& e : m.events) {
            out << "  [" << fixed(m.flightTime(e.metS), 3) << "] " << eventLine(e) << "\n";
        }
    }
}

void printMissionFacts(const MissionTelemetry& m, std::ostream& out) {
    const auto kv = [&](const char* key, const std::string& value) { out << key << "=" << value << "\n"; };
    const auto num = [&](const char* key, double value) { kv(key, formatNumber(value)); };
    kv("outcome", m.outcome == TelemetryOutcome::kGoalReached  ? "goal_reached"
                  : m.outcome == TelemetryOutcome::kCalledHome ? "called_home"
                                                               : "none");
    kv("outcome_time", m.outcome == TelemetryOutcome::kNone ? "-1" : fixed(m.flightTime(m.outcomeMetS), 3));
    num("call_home_reason", m.callHomeReason);
    kv("call_home_by", m.callHomeBy);
    kv("call_home_event", m.callHomeEvent);
    kv("flight_start_met", m.flightStartKnown ? fixed(m.flightStartMetS, 3) : "-1");
    num("time_scale", m.timeScale);
    num("goal_count", m.goalCount);
    num("goal_x", m.goalX);
    num("goal_y", m.goalY);
    num("risk_bound", m.riskBound);
    num("plan_length", m.planLengthM);
    kv("final_pose_known", m.poseKnown ? "1" : "0");
    kv("final_x", fixed(m.finalPose.xM, 3));
    kv("final_y", fixed(m.finalPose.yM, 3));
    num("final_mode", m.finalMode);
    num("plans", m.plansMade);
    num("legs_sent", m.legsSent);
    num("legs_achieved", m.legsAchieved);
    num("goals_reached", m.goalsReached);
    num("fail_ups", m.failUps);
    num("habitual_fail_ups", m.habitualFailUps);
    num("replans", m.replans);
    num("bound_relaxations", m.boundRelaxations);
    num("risk_relaxations", m.riskRelaxations);
    num("call_homes", m.callHomes);
    num("site_mode", m.siteMode ? 1 : 0);
    num("horizons_reached", m.horizonsReached);
    num("horizons_driven_through", m.horizonsDrivenThrough);
    num("horizon_stops", m.horizonStops);
    std::string faults;
    for (unsigned id : m.faultsSeen) {
        faults += (faults.empty() ? "" : ",") + std::to_string(id);
    }
    kv("faults", faults);
    num("frames_run", static_cast<double>(m.framesRun));
    num("frame_overruns", m.frameOverruns);
    num("frames_skipped", m.framesSkipped);
    num("frame_lateness_max_us", m.frameLatenessMaxUs);
    num("frame_busy_max_us", m.frameBusyMaxUs);
    num("packets", static_cast<double>(m.packets));
    num("undecoded", static_cast<double>(m.undecoded));
    num("events", m.eventsReceived);
    num("events_lost", m.eventsLost);
    num("tlm_dropped", m.telemetryDropped);
    num("event_log_lost", m.eventLogLost);
    num("event_data_paired", m.eventDataPaired);
    num("events_without_data", m.eventsWithoutData);
    num("event_data_stray", m.eventDataStray);
    num("event_data_withheld", m.eventDataWithheld);
    num("commands_accepted", m.commandsAccepted);
    num("commands_rejected", m.commandsRejected);
    num("track_points", static_cast<double>(m.track.size()));
}

}  // namespace rse::ground
