// What a mission was, as the ground saw it: read from the telemetry a ground
// station received (a session recording, ground/session_recording.hpp), not
// from the flight software's memory or the simulator. A plain data record:
// the outcome (every goal reached, or called home with the reason and the
// flight software's words), the goal and risk bound the rover took, the final
// estimated position, the counts (plans, legs sent and reached, fail-ups,
// replans, relaxations, call homes) and the events in order, with the pose
// track; the frame timing housekeeping reported; and what the link lost.
// Printers write it for people (`rse-ground summary`) and as key=value facts
// for scripts (`--facts`). A report or map writer, or a reading of the
// demonstration's points, takes the same record.
//
// Where each part comes from (docs/ground.md, "summary"):
//   outcome      PLAN.status 5 (every goal reached) or 4 (called home, reason
//                PLAN.call_home); EVENT 941 (fault protection called home: reason 6);
//                PLAN_EXEC.state 5 (no plan method remains: reason 7, PLAN_EXEC.call_home).
//                The first of these the recording holds, after the recording saw the
//                rover with a goal (PLAN.status 1..3); its time is the packet's MET.
//   counts       plans made: events 902; legs sent / reached: 905 / 906; goals
//                reached: 907; fail-ups: 909 (the deliberative layer's), 807 (the
//                habitual layer's); replans, relaxations, call homes: the last PLAN's
//                counters (the rover's own totals since it started).
//   faults       every fault id HEALTH.active_faults showed set.
//   timing       the last HK: frames run, overruns, frames skipped, worst frame
//                start lateness and busy time; time_scale (rse-fsw --time-scale);
//                tlm_dropped (what a link refused) and events_lost (events the
//                rover's event log overwrote while they waited for the CAN link).
//   event data   each EVENT_DATA paired with its EVENT (event_sequence): the
//                event's numbers; those paired, stray and missing are counted.
//   flight start the MET at which the rover's executive started: an HK's MET less
//                (frames_run + frames_skipped) minor frames; mission times are also
//                given from there ("flight time"), the timeline rse-demo prints.
//
// Host code (ground/): full language.
#pragma once

#include <cstdint>
#include <ostream>
#include <set>
#include <string>
#include <vector>

#include "fsw/core/event_log.hpp"
#include "ground/event_data_pairing.hpp"
#include "ground/session_recording.hpp"
#include "ground/telemetry_decoder.hpp"

namespace rse::ground {

// One EVENT packet, with its numbers when its EVENT_DATA came (paired by
// event_sequence: ground/event_data_pairing.hpp).
struct TelemetryEvent {
    double metS = 0.0;        // the event's own time (EVENT.event_time)
    double receivedS = 0.0;   // when the ground received it (since the recording started)
    std::uint32_t sequence = 0;
    std::uint16_t id = 0;
    std::uint8_t severity = 0;  // 0 DEBUG .. 4 CRIT
    std::string text;
    core::EventData data;     // count 0: none (the event carries none, or they were lost)
};

// One ROVER_STATE packet with an estimate.
struct TelemetryPose {
    double metS = 0.0;
    double xM = 0.0;
    double yM = 0.0;
    double headingRad = 0.0;
    double sigmaM = 0.0;
};

enum class TelemetryOutcome : std::uint8_t {
    kNone = 0,         // the recording holds no outcome
    kGoalReached = 1,  // every goal reached
    kCalledHome = 2,   // the rover called home (callHomeReason says why)
};
const char* toString(TelemetryOutcome outcome);

struct MissionTelemetry {
    // The recording.
    std::string link;
    std::size_t packets = 0;         // packets recorded
    std::size_t undecoded = 0;       // packets the dictionary could not decode
    double receivedSpanS = 0.0;      // first to last packet, ground time
    double firstMetS = -1.0;         // the first and last decoded packet's MET (-1: none)
    double lastMetS = -1.0;

    // The rover's timeline.
    bool flightStartKnown = false;
    double flightStartMetS = 0.0;    // MET when its executive started (from HK)
    std::uint32_t timeScale = 0;     // HK.time_scale (0: no HK)

    // The outcome.
    TelemetryOutcome outcome = TelemetryOutcome::kNone;
    double outcomeMetS = 0.0;
    std::uint8_t callHomeReason = 0;  // msg::CallHomeReason: 1..5 deliberative, 6 fault protection, 7 plan executive
    std::string callHomeBy;           // "deliberative layer", "fault protection", "plan executive"
    std::string callHomeEvent;        // the CRIT event that said why (912, 933 or 941, 966), as received

    // The goal, as the rover took it (the last PLAN with a goal).
    std::uint8_t goalCount = 0;
    double goalX = 0.0;
    double goalY = 0.0;
    double riskBound = 0.0;
    double riskInForce = 0.0;
    double riskUsed = 0.0;
    double planLengthM = 0.0;

    // The last state seen.
    bool poseKnown = false;
    TelemetryPose finalPose;
    int finalMode = -1;               // HK.mode (-1: no HK)
    int finalPlanStatus = -1;         // PLAN.status (-1: no PLAN)

    // Counts.
    std::uint32_t plansMade = 0;        // events 902
    std::uint32_t legsSent = 0;         // 905
    std::uint32_t legsAchieved = 0;     // 906
    std::uint32_t goalsReached = 0;     // 907
    std::uint32_t failUps = 0;          // 909
    std::uint32_t habitualFailUps = 0;  // 807
    std::uint32_t replans = 0;          // PLAN.replans
    std::uint32_t boundRelaxations = 0; // PLAN.bound_relaxations
    std::uint32_t riskRelaxations = 0;  // PLAN.risk_relaxations
    std::uint32_t callHomes = 0;        // PLAN.call_homes
    // Site mode (PLAN.site_mode and its counters).
    bool siteMode = false;
    std::uint32_t horizonsReached = 0;        // PLAN.horizons_reached
    std::uint32_t horizonsDrivenThrough = 0;  // PLAN.horizons_driven_through
    std::uint32_t horizonStops = 0;           // PLAN.horizon_stops
    std::set<unsigned> faultsSeen;      // fault ids set in any HEALTH.active_faults

    // Frame timing, as the last HK reported it.
    bool timingKnown = false;
    std::uint64_t framesRun = 0;
    std::uint32_t frameOverruns = 0;
    std::uint32_t framesSkipped = 0;
    std::uint32_t frameLatenessMaxUs = 0;
    std::uint32_t frameBusyMaxUs = 0;
    std::uint32_t telemetryDropped = 0;  // HK.tlm_dropped: packets the rover's links could not take, since its start
    std::uint32_t eventLogLost = 0;      // HK.events_lost: events the event log overwrote before telemetry sent them

    // The link.
    std::uint32_t eventsReceived = 0;
    std::uint32_t eventsLost = 0;       // gaps in event_sequence after the first event received
    std::uint32_t eventDataPaired = 0;  // EVENT_DATA packets paired with their EVENT
    std::uint32_t eventDataStray = 0;   // ... whose EVENT never came (their numbers dropped)
    std::uint32_t eventsWithoutData = 0;  // events whose id carries numbers that never came
    std::uint32_t eventDataWithheld = 0;  // EVENT_DATA.data_withheld: the rover's own count, as last received
    std::uint32_t commandsAccepted = 0; // CMD_ACKs received
    std::uint32_t commandsRejected = 0;

    std::vector<TelemetryEvent> events;  // in the order received
    std::vector<TelemetryPose> track;    // every ROVER_STATE with an estimate

    // A time on the rover's timeline from its start (flight time): MET less
    // flightStartMetS when that is known, else the MET.
    double flightTime(double metS) const { return flightStartKnown ? metS - flightStartMetS : metS; }
};

// Builds the record a packet at a time (a recorder uses it to stop at the
// outcome; the summary feeds it the whole recording).
class MissionTelemetryReader {
public:
    void add(double receivedS, const std::vector<std::uint8_t>& bytes);
    void add(double receivedS, const DecodedPacket& packet);
    // An outcome has been seen.
    bool ended() const { return mission_.outcome != TelemetryOutcome::kNone; }
    const MissionTelemetry& mission() const { return mission_; }

private:
    void onEvent(double receivedS, const DecodedPacket& p);
    void onEventData(const DecodedPacket& p);
    void onPlan(const DecodedPacket& p);
    void onHousekeeping(const DecodedPacket& p);
    void decide(TelemetryOutcome outcome, double metS, std::uint8_t reason, const char* by);
    const std::string& callHomeWords(const std::string& by) const;

    MissionTelemetry mission_;
    EventDataPairing pairing_;         // handles: indices into mission_.events
    double firstReceivedS_ = 0.0;
    bool sawGoal_ = false;             // a PLAN with status 1..3 (the rover had a goal) during the recording
    bool haveEventSequence_ = false;
    std::uint32_t nextEventSequence_ = 0;
    std::string lastCallHomeEvent_;    // the last 912 / 933 / 966 received
    std::string lastGaveUpEvent_;      // the last 933 received
    std::string lastPlanExecEvent_;    // the last 966 received
};

MissionTelemetry readMissionTelemetry(const SessionRecording& recording);

// For people: the outcome, the final position, the counts, the timing, the link,
// then every event (unless eventsToo is false).
void printMissionTelemetry(const MissionTelemetry& mission, std::ostream& out, bool eventsToo = true);
// For scripts: one key=value a line (docs/ground.md lists the keys).
void printMissionFacts(const MissionTelemetry& mission, std::ostream& out);

}  // namespace rse::ground
