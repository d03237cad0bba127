// The session recorder and the mission read from telemetry: a recording
// round-trips packet for packet with its times, bad lines are named and
// skipped; the outcome, the counts, the final pose, the faults, the timing and
// the events come from the packets the flight encodes (PLAN, EVENT, HK,
// ROVER_STATE, HEALTH, CMD_ACK, PLAN_EXEC); `rse-ground record` stops at the
// outcome and `summary` prints what the recording shows.
#include <cstring>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/deliberative/deliberative_events.hpp"
#include "fsw/fault_protection/fault_protection_events.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "ground/mission_telemetry.hpp"
#include "ground/session_recording.hpp"
#include "unit_test/ground/ground_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

core::TimeNs at(double seconds) { return static_cast<core::TimeNs>(seconds * 1e9); }

std::vector<std::uint8_t> event(std::uint32_t sequence, double metS, std::uint16_t id, std::uint8_t severity,
                                const char* text) {
    cmdtlm::EVENT_Tlm e{};
    e.event_sequence = sequence;
    e.event_time = metS;
    e.event_id = id;
    e.severity = severity;
    std::strncpy(e.text, text, sizeof e.text - 1);
    return test::telemetryPacket(e, static_cast<std::uint16_t>(sequence), at(metS));
}

std::vector<std::uint8_t> plan(double metS, msg::DeliberativeState state, std::uint8_t callHome = 0,
                               std::uint32_t replans = 0, std::uint32_t callHomes = 0) {
    cmdtlm::PLAN_Tlm p{};
    p.status = static_cast<std::uint8_t>(state);
    p.call_home = callHome;
    p.goal_count = 1;
    p.goal_x[0] = 20.0F;
    p.goal_y[0] = -1.5F;
    p.risk_bound = 1e-3;
    p.risk_in_force = 1e-3;
    p.risk_used = 9e-6;
    p.plan_length = 19.96F;
    p.replans = replans;
    p.call_homes = callHomes;
    return test::telemetryPacket(p, 0, at(metS));
}

std::vector<std::uint8_t> housekeeping(double metS, std::uint64_t framesRun, std::uint8_t mode,
                                       std::uint8_t timeScale = 1) {
    cmdtlm::HK_Tlm hk{};
    hk.mode = mode;
    hk.frames_run = framesRun;
    hk.frames_skipped = 2;
    hk.frame_overruns = 5;
    hk.frame_lateness_max_us = 8680;
    hk.frame_busy_max_us = 28061;
    hk.time_scale = timeScale;
    hk.tlm_dropped = 62;
    return test::telemetryPacket(hk, 0, at(metS));
}

std::vector<std::uint8_t> pose(double metS, double x, double y) {
    cmdtlm::ROVER_STATE_Tlm s{};
    s.estimate_valid = 1;
    s.x = x;
    s.y = y;
    s.heading = 0.5;
    s.position_sigma = 0.05F;
    return test::telemetryPacket(s, 0, at(metS));
}

std::vector<std::uint8_t> health(double metS, std::uint64_t activeFaults) {
    cmdtlm::HEALTH_Tlm h{};
    h.active_faults = activeFaults;
    return test::telemetryPacket(h, 0, at(metS));
}

ground::MissionTelemetry read(const std::vector<std::vector<std::uint8_t>>& packets) {
    ground::MissionTelemetryReader reader;
    double t = 0.0;
    for (const auto& p : packets) {
        reader.add(t, p);
        t += 0.5;
    }
    return reader.mission();
}

// The demo's ending as the ground receives it: the rover started at MET 1.0
// (HK at 2.0 after 98 frames run and 2 skipped), a plan, legs, a fail-up, the
// call home with its reason, an event lost on the way.
std::vector<std::vector<std::uint8_t>> calledHomeMission() {
    namespace dev = deliberative::events;
    return {
        housekeeping(2.0, 98, 2, 4),
        plan(2.1, msg::DeliberativeState::kPlanning),
        event(10, 2.5, dev::kPlanFound, 1, "deliberative: optimal plan, gap 0.2%: 19.96 m, 6 legs"),
        event(11, 2.5, dev::kLegSent, 1, "deliberative: leg 1 (1 of 6)"),
        plan(2.5, msg::DeliberativeState::kExecuting),
        pose(3.0, 0.5, 0.0),
        health(20.0, (1ULL << 12)),
        event(12, 18.0, dev::kLegAchieved, 1, "deliberative: leg 1 reached (1 of 6)"),
        event(13, 18.0, dev::kLegSent, 1, "deliberative: leg 2 (2 of 6)"),
        // 14 lost
        event(15, 47.2, dev::kFailUpReceived, 2, "deliberative: leg 2 failed up: cannot follow"),
        // The status of the call home's frame comes down before its event (as over CAN).
        plan(47.2, msg::DeliberativeState::kCalledHome, static_cast<std::uint8_t>(msg::CallHomeReason::kMobilityLost),
             1, 1),
        event(16, 47.2, dev::kCallHome, 4, "deliberative: CALL HOME: mobility lost (the drive interlock holds every drive)"),
        pose(47.5, 9.34, -0.11),
        health(48.0, 0),
        housekeeping(49.0, 4798, 0, 4),
    };
}

}  // namespace

TEST_GROUP(SessionRecording){};

TEST(SessionRecording, RoundTripsEveryPacketWithItsTimeAndRendering) {
    const std::vector<std::vector<std::uint8_t>> packets = {
        event(1, 2.0, 905, 1, "line one\nline two"), plan(2.5, msg::DeliberativeState::kPlanning), {1, 2, 3}};
    std::ostringstream file;
    ground::SessionRecorder recorder(file, "ISO-TP vcan0 tx 0x6C0 rx 0x6C1", 1733157000.25);
    recorder.record(0.125, packets[0]);
    recorder.record(0.5, packets[1]);
    recorder.record(0.5, packets[2]);
    CHECK_EQUAL(3U, recorder.packets());
    const std::string text = file.str();
    CHECK_TRUE(text.rfind(ground::kRecordingMagic, 0) == 0);
    CHECK_TRUE(contains(text, "EVT 905 INFO line one"));
    CHECK_FALSE(contains(text, "\nline two"));  // one line a packet, whatever the text
    CHECK_TRUE(contains(text, "\n0.500000 010203 MALFORMED"));

    std::istringstream in(text);
    const ground::SessionRecording r = ground::readSessionRecording(in);
    CHECK_TRUE(r.errors.empty());
    STRCMP_EQUAL("ISO-TP vcan0 tx 0x6C0 rx 0x6C1", r.link.c_str());
    DOUBLES_EQUAL(1733157000.25, r.startUtc, 1e-6);
    LONGS_EQUAL(3, r.packets.size());
    for (std::size_t i = 0; i < packets.size(); ++i) {
        CHECK_TRUE(r.packets[i].bytes == packets[i]);
    }
    DOUBLES_EQUAL(0.125, r.packets[0].receivedS, 1e-9);
    DOUBLES_EQUAL(0.5, r.packets[2].receivedS, 1e-9);
}

TEST(SessionRecording, BadLinesAreNamedAndSkippedAndAForeignFileRefused) {
    std::istringstream in(std::string(ground::kRecordingMagic) +
                          "\n# a comment\n"
                          "1.0 0A0B the good one\n"
                          "0.5 0C0D time goes backwards\n"
                          "2.0 0A0 odd digits\n"
                          "2.0 0A0G not hex\n"
                          "x 0A0B no time\n"
                          "3.0\n"
                          "4.0 0E0F\n");
    const ground::SessionRecording r = ground::readSessionRecording(in);
    LONGS_EQUAL(2, r.packets.size());
    CHECK_TRUE((r.packets[0].bytes == std::vector<std::uint8_t>{0x0A, 0x0B}));
    CHECK_TRUE((r.packets[1].bytes == std::vector<std::uint8_t>{0x0E, 0x0F}));
    LONGS_EQUAL(5, r.errors.size());
    STRCMP_EQUAL("line 4: receive time goes backwards", r.errors[0].c_str());
    STRCMP_EQUAL("line 5: no packet (hex bytes)", r.errors[1].c_str());
    STRCMP_EQUAL("line 7: no receive time", r.errors[3].c_str());

    std::istringstream foreign("0.1 0A0B\n");
    const ground::SessionRecording f = ground::readSessionRecording(foreign);
    CHECK_TRUE(f.packets.empty());
    LONGS_EQUAL(1, f.errors.size());
    CHECK_TRUE(contains(f.errors[0], "not a session recording"));
}

TEST_GROUP(MissionTelemetry){};

TEST(MissionTelemetry, CalledHomeWithTheReasonTheCountsAndTheFinalPose) {
    const ground::MissionTelemetry m = read(calledHomeMission());
    CHECK_TRUE(m.outcome == ground::TelemetryOutcome::kCalledHome);
    LONGS_EQUAL(5, m.callHomeReason);
    STRCMP_EQUAL("deliberative layer", m.callHomeBy.c_str());
    STRCMP_EQUAL("EVT 912 CRIT deliberative: CALL HOME: mobility lost (the drive interlock holds every drive)",
                 m.callHomeEvent.c_str());
    DOUBLES_EQUAL(47.2, m.outcomeMetS, 1e-4);  // MET: 1/65536 s
    // The rover's start from the first HK: 2.0 s less 100 frames.
    CHECK_TRUE(m.flightStartKnown);
    DOUBLES_EQUAL(1.0, m.flightStartMetS, 1e-4);
    DOUBLES_EQUAL(46.2, m.flightTime(m.outcomeMetS), 1e-4);
    LONGS_EQUAL(4, m.timeScale);
    // The goal as the rover took it.
    LONGS_EQUAL(1, m.goalCount);
    DOUBLES_EQUAL(20.0, m.goalX, 1e-6);
    DOUBLES_EQUAL(-1.5, m.goalY, 1e-6);
    DOUBLES_EQUAL(1e-3, m.riskBound, 0.0);
    DOUBLES_EQUAL(19.96, m.planLengthM, 1e-5);
    // Where the last estimate put it.
    CHECK_TRUE(m.poseKnown);
    DOUBLES_EQUAL(9.34, m.finalPose.xM, 1e-9);
    DOUBLES_EQUAL(-0.11, m.finalPose.yM, 1e-9);
    LONGS_EQUAL(2, m.track.size());
    LONGS_EQUAL(0, m.finalMode);
    // Counts from the events and the last PLAN.
    LONGS_EQUAL(1, m.plansMade);
    LONGS_EQUAL(2, m.legsSent);
    LONGS_EQUAL(1, m.legsAchieved);
    LONGS_EQUAL(1, m.failUps);
    LONGS_EQUAL(1, m.replans);
    LONGS_EQUAL(1, m.callHomes);
    CHECK_TRUE((m.faultsSeen == std::set<unsigned>{12}));
    // Timing from the last HK; the link's losses.
    CHECK_TRUE(m.timingKnown);
    LONGS_EQUAL(4798, m.framesRun);
    LONGS_EQUAL(2, m.framesSkipped);
    LONGS_EQUAL(8680, m.frameLatenessMaxUs);
    LONGS_EQUAL(62, m.telemetryDropped);
    LONGS_EQUAL(6, m.eventsReceived);
    LONGS_EQUAL(1, m.eventsLost);
    LONGS_EQUAL(6, m.events.size());
    LONGS_EQUAL(deliberative::events::kCallHome, m.events.back().id);
    LONGS_EQUAL(15, m.packets);
}

TEST(MissionTelemetry, AnOutcomeCountsOnlyAfterTheRoverHadAGoal) {
    // A call home left over from before the recording: not this mission's.
    ground::MissionTelemetry m = read({plan(1.0, msg::DeliberativeState::kCalledHome, 2),
                                       plan(2.0, msg::DeliberativeState::kComplete)});
    CHECK_TRUE(m.outcome == ground::TelemetryOutcome::kNone);
    m = read({plan(1.0, msg::DeliberativeState::kWaiting), plan(2.0, msg::DeliberativeState::kExecuting),
              plan(97.3, msg::DeliberativeState::kComplete),
              plan(98.0, msg::DeliberativeState::kCalledHome, 1)});
    CHECK_TRUE(m.outcome == ground::TelemetryOutcome::kGoalReached);
    DOUBLES_EQUAL(97.3, m.outcomeMetS, 1e-4);  // MET: 1/65536 s
    LONGS_EQUAL(0, m.callHomeReason);
    CHECK_FALSE(m.flightStartKnown);  // no HK: times stay MET
    DOUBLES_EQUAL(m.outcomeMetS, m.flightTime(m.outcomeMetS), 0.0);
}

TEST(MissionTelemetry, FaultProtectionsCallHomeIsReasonSixWithItsGiveUp) {
    namespace fp = fault_protection::events;
    const ground::MissionTelemetry m =
        read({plan(1.0, msg::DeliberativeState::kExecuting),
              event(3, 30.0, fp::kGaveUp, 4, "fault protection: task stalled (fault 25): 3 tries used"),
              event(4, 30.0, fp::kCallHome, 4, "fault protection: CALL HOME"),
              plan(30.1, msg::DeliberativeState::kWaiting)});
    CHECK_TRUE(m.outcome == ground::TelemetryOutcome::kCalledHome);
    LONGS_EQUAL(static_cast<long>(msg::CallHomeReason::kFaultUnrecovered), m.callHomeReason);
    STRCMP_EQUAL("fault protection", m.callHomeBy.c_str());
    CHECK_TRUE(contains(m.callHomeEvent, "EVT 933 CRIT fault protection: task stalled (fault 25)"));
    DOUBLES_EQUAL(30.0, m.outcomeMetS, 1e-4);
}

TEST(MissionTelemetry, UndecodablePacketsAreCountedNotRead) {
    const ground::MissionTelemetry m = read({{1, 2, 3}, plan(1.0, msg::DeliberativeState::kPlanning)});
    LONGS_EQUAL(2, m.packets);
    LONGS_EQUAL(1, m.undecoded);
    DOUBLES_EQUAL(1.0, m.firstMetS, 1e-4);
}

TEST(MissionTelemetry, PrintedForPeopleAndAsFacts) {
    const ground::MissionTelemetry m = read(calledHomeMission());
    std::ostringstream people;
    ground::printMissionTelemetry(m, people);
    const std::string p = people.str();
    CHECK_TRUE(contains(p, "outcome:    called home at 46.20 s (MET 47.20), reason 5 (deliberative layer)"));
    CHECK_TRUE(contains(p, "final pose: (9.34, -0.11)"));
    CHECK_TRUE(contains(p, "time scale 4"));
    CHECK_TRUE(contains(p, "  [46.200] EVT 912 CRIT deliberative: CALL HOME: mobility lost"));
    std::ostringstream facts;
    ground::printMissionFacts(m, facts);
    const std::string f = facts.str();
    CHECK_TRUE(contains(f, "outcome=called_home\n"));
    CHECK_TRUE(contains(f, "call_home_reason=5\n"));
    CHECK_TRUE(contains(f, "outcome_time=46.200\n"));
    CHECK_TRUE(contains(f, "final_x=9.340\nfinal_y=-0.110\n"));
    CHECK_TRUE(contains(f, "legs_sent=2\n"));
    CHECK_TRUE(contains(f, "faults=12\n"));
    CHECK_TRUE(contains(f, "frames_skipped=2\n"));
    CHECK_TRUE(contains(f, "events_lost=1\n"));
    CHECK_TRUE(contains(f, "tlm_dropped=62\n"));
    // The recording has no EVENT_DATA: the four events that carry numbers came without.
    CHECK_TRUE(contains(p, "event data: 0 EVENT_DATA paired with their events, 4 events without their numbers"));
    CHECK_TRUE(contains(f, "events_without_data=4\n"));
    CHECK_TRUE(contains(f, "event_data_paired=0\n"));
}

// The summary's events carry their numbers: each EVENT_DATA paired with its
// EVENT by event_sequence; one whose event never came is stray.
TEST(MissionTelemetry, EachEventsNumbersArePairedByItsSequence) {
    namespace dev = deliberative::events;
    cmdtlm::event_data::LEG_SENT sent;
    sent.leg_id = 2;
    sent.power_bound = 308.4;
    const core::EventData values = sent.pack();
    auto numbers = [&](std::uint32_t sequence) {
        cmdtlm::EVENT_DATA_Tlm d{};
        d.event_sequence = sequence;
        d.event_id = dev::kLegSent;
        d.value_count = values.count;
        for (std::size_t i = 0; i < values.count; ++i) {
            d.value[i] = values.values[i];
        }
        return test::telemetryPacket(d, 0, at(18.0));
    };
    const ground::MissionTelemetry m = read({event(12, 18.0, dev::kLegSent, 1, "deliberative: leg 2 (2 of 6)"),
                                              numbers(12), numbers(99)});
    LONGS_EQUAL(1, m.eventDataPaired);
    LONGS_EQUAL(1, m.eventDataStray);
    LONGS_EQUAL(0, m.eventsWithoutData);
    LONGS_EQUAL(1, m.events.size());
    cmdtlm::event_data::LEG_SENT got;
    CHECK_TRUE(got.unpack(m.events[0].id, m.events[0].data));
    DOUBLES_EQUAL(308.4, got.power_bound, 0.0);
    LONGS_EQUAL(3, m.packets);
}

TEST_GROUP(GroundCliRecord){};

TEST(GroundCliRecord, RecordsUntilTheOutcomeThenTheSummaryReadsIt) {
    test::CliRig rig;
    for (const auto& p : calledHomeMission()) {
        rig.link.queue.push_back(p);
    }
    const std::string file = rig.dir.file("session.rec");
    test::CliResult r = rig.run({"record", file, "--until-outcome", "--tail", "0.2", "--seconds", "20", "--quiet"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "outcome: called home: recording 0.2 s more"));
    CHECK_TRUE(contains(r.out, "recorded 15 packets"));
    CHECK_FALSE(contains(r.out, "EVT 912"));  // --quiet
    CHECK_TRUE(rig.link.queue.empty());       // the tail took the packets after the outcome

    r = rig.run({"summary", file, "--facts"});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "outcome=called_home\n"));
    CHECK_TRUE(contains(r.out, "call_home_reason=5\n"));
    CHECK_TRUE(contains(r.out, "packets=15\n"));
    r = rig.run({"summary", file});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "recording:  15 packets (0 undecoded) over "));
    CHECK_TRUE(contains(r.out, " s on fake rover\n"));
    CHECK_TRUE(contains(r.out, "EVT 905 INFO deliberative: leg 2 (2 of 6)"));
    r = rig.run({"summary", file, "--no-events"});
    CHECK_FALSE(contains(r.out, "EVT 905"));
}

TEST(GroundCliRecord, NoOutcomeNoTelemetryAndBadUsageAreErrors) {
    test::CliRig rig;
    rig.link.queue.push_back(plan(1.0, msg::DeliberativeState::kExecuting));
    const std::string file = rig.dir.file("session.rec");
    test::CliResult r = rig.run({"record", file, "--until-outcome", "--seconds", "0.3"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "record: no outcome within 0.3 s"));
    CHECK_TRUE(contains(r.out, "PLAN "));  // not quiet: every packet shown
    r = rig.run({"record", file, "--seconds", "0.2"});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "record: no telemetry"));
    CHECK_EQUAL(2, rig.run({"record", file}).rc);  // would never stop
    CHECK_EQUAL(2, rig.run({"record"}).rc);
    CHECK_EQUAL(2, rig.run({"record", file, "--seconds", "0"}).rc);
    CHECK_EQUAL(2, rig.run({"summary"}).rc);
    r = rig.run({"summary", rig.dir.file("missing.rec")});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "cannot read"));
    {
        std::ofstream foreign(rig.dir.file("foreign.rec"));
        foreign << "not a recording\n";
    }
    r = rig.run({"summary", rig.dir.file("foreign.rec")});
    CHECK_EQUAL(1, r.rc);
    CHECK_TRUE(contains(r.err, "not a session recording"));
}

// Site mode's counts come from PLAN's fields, told only when a site map was in force.
TEST(MissionTelemetry, SiteModesHorizonEndsComeFromPlan) {
    cmdtlm::PLAN_Tlm p{};
    p.status = static_cast<std::uint8_t>(msg::DeliberativeState::kExecuting);
    p.goal_count = 1;
    p.site_mode = 1;
    p.horizons_reached = 17;
    p.horizons_driven_through = 14;
    p.horizon_stops = 3;
    const ground::MissionTelemetry m = read({test::telemetryPacket(p, 0, at(5.0))});
    CHECK_TRUE(m.siteMode);
    LONGS_EQUAL(17, m.horizonsReached);
    LONGS_EQUAL(14, m.horizonsDrivenThrough);
    LONGS_EQUAL(3, m.horizonStops);
    std::ostringstream people;
    ground::printMissionTelemetry(m, people);
    CHECK_TRUE(contains(people.str(), "site:       17 horizon ends: 14 driven through"));
    std::ostringstream facts;
    ground::printMissionFacts(m, facts);
    CHECK_TRUE(contains(facts.str(), "horizons_driven_through=14\n"));
    // The coarse map: no site line.
    const ground::MissionTelemetry coarse = read(calledHomeMission());
    CHECK_FALSE(coarse.siteMode);
    std::ostringstream plain;
    ground::printMissionTelemetry(coarse, plain);
    CHECK_FALSE(contains(plain.str(), "site:"));
}
