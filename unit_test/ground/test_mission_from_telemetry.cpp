// The mission read from a recording (ground/mission_from_telemetry.hpp,
// `rse-ground report`): the demo's events as EVENT packets, each followed by
// its EVENT_DATA (the event's numbers), in the order a CAN downlink delivers
// them (events ahead of routine telemetry: PLAN's call-home reason after the
// call home's and the safing's events), poses, and a PLAN_PATH for the plan;
// the ten points come out all in order at the events' flight times, the plan
// with its means and covariance, and the report and map files say so. The
// pairing of EVENT_DATA with its EVENT by event_sequence: in order, data lost
// (the event read without numbers, counted), stray data (its event lost:
// counted, dropped), a late pair after other events.
#include <cstdint>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/event_data.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/tables/table_image.hpp"
#include "ground/mission_from_telemetry.hpp"
#include "ground/mission_report.hpp"
#include "ground/session_recording.hpp"
#include "ground/table_compiler.hpp"
#include "unit_test/ground/ground_test_support.hpp"
#include "unit_test/ground/mission_stream_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;

namespace {

constexpr double kStartMetS = 1.0;  // the rover's executive started at MET 1.0

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

core::TimeNs at(double metS) { return static_cast<core::TimeNs>(metS * 1e9 + 0.5); }

std::vector<std::uint8_t> event(std::uint32_t sequence, double metS, std::uint16_t id, const char* text) {
    cmdtlm::EVENT_Tlm e{};
    e.event_sequence = sequence;
    e.event_time = metS;
    e.event_id = id;
    e.severity = 1;
    std::strncpy(e.text, text, sizeof e.text - 1);
    return test::telemetryPacket(e, static_cast<std::uint16_t>(sequence), at(metS));
}

std::vector<std::uint8_t> eventData(std::uint32_t sequence, double metS, std::uint16_t id, const core::EventData& data) {
    cmdtlm::EVENT_DATA_Tlm d{};
    d.event_sequence = sequence;
    d.event_id = id;
    d.value_count = data.count;
    for (std::size_t i = 0; i < data.count; ++i) {
        d.value[i] = data.values[i];
    }
    return test::telemetryPacket(d, static_cast<std::uint16_t>(sequence), at(metS));
}

std::vector<std::uint8_t> plan(double metS, std::uint8_t callHome) {
    cmdtlm::PLAN_Tlm p{};
    p.status = static_cast<std::uint8_t>(callHome != 0 ? msg::DeliberativeState::kCalledHome
                                                       : msg::DeliberativeState::kExecuting);
    p.call_home = callHome;
    p.goal_count = 1;
    p.goal_x[0] = 20.0F;
    p.risk_bound = 1e-3;
    p.call_homes = callHome != 0 ? 1 : 0;
    return test::telemetryPacket(p, 0, at(metS));
}

std::vector<std::uint8_t> pose(double metS, double x, double y) {
    cmdtlm::ROVER_STATE_Tlm s{};
    s.estimate_valid = 1;
    s.x = x;
    s.y = y;
    return test::telemetryPacket(s, 0, at(metS));
}

std::vector<std::uint8_t> housekeeping(double metS) {
    cmdtlm::HK_Tlm hk{};
    hk.mode = 2;
    hk.frames_run = static_cast<std::uint64_t>((metS - kStartMetS) / 0.01 + 0.5);
    hk.time_scale = 1;
    return test::telemetryPacket(hk, 0, at(metS));
}

// The demo's first plan: four means from the start to the goal.
std::vector<std::uint8_t> planPath(double metS) {
    cmdtlm::PLAN_PATH_Tlm p{};
    p.plan_number = 1;
    p.plan_time = metS;
    p.status = 0;
    p.steps = 3;
    p.risk_bound = 1e-3;
    p.risk_used = 9.17e-6;
    p.length = 19.96F;
    p.process_sigma = 0.05F;
    p.start_cov[0] = 0.01F;
    p.start_cov[3] = 0.01F;
    p.goal_x = 20.0F;
    const float xs[4] = {0.0F, 3.86F, 14.33F, 20.0F};
    const float ys[4] = {0.0F, -0.28F, -0.38F, 0.0F};
    for (int i = 0; i < 4; ++i) {
        p.mean_x[i] = xs[i];
        p.mean_y[i] = ys[i];
    }
    return test::telemetryPacket(p, 0, at(metS));
}

// What to do to the EVENT_DATA of the demo's events (by their place in kDemo).
struct DataFate {
    std::size_t lose = SIZE_MAX;       // this event's EVENT_DATA is lost
    std::size_t loseEvent = SIZE_MAX;  // this event's EVENT is lost (its EVENT_DATA comes: stray)
    std::size_t delay = SIZE_MAX;      // this event's EVENT_DATA comes after the next event's pair
};

// The recording as a CAN ground receives it: every event first (each with its
// numbers right after it), the routine packets of a frame after them, and
// PLAN's call-home reason last of all.
std::string demoRecording(const DataFate& fate = {}) {
    std::ostringstream file;
    ground::SessionRecorder recorder(file, "ISO-TP vcan0 tx 0x6C0 rx 0x6C1", 1733157000.0);
    double received = 0.0;
    auto record = [&](const std::vector<std::uint8_t>& packet) { recorder.record(received += 0.01, packet); };
    record(housekeeping(kStartMetS + 0.2));
    record(plan(kStartMetS + 0.3, 0));
    std::uint32_t sequence = 1;
    std::vector<std::uint8_t> delayed;
    for (std::size_t i = 0; i < test::kDemo.size(); ++i) {
        const test::Step& s = test::kDemo[i];
        const double met = kStartMetS + s.t;
        if (i != fate.loseEvent) {
            record(event(sequence, met, s.id, s.text));
        }
        if (s.data.count > 0 && i == fate.delay) {
            delayed = eventData(sequence, met, s.id, s.data);
        } else if (s.data.count > 0 && i != fate.lose) {
            record(eventData(sequence, met, s.id, s.data));
        }
        if (!delayed.empty() && i == fate.delay + 1) {
            record(delayed);
            delayed.clear();
        }
        ++sequence;
        if (s.id == 902) {
            record(planPath(met));
        }
        record(pose(met + 0.01, s.t / 5.0, 0.0));
    }
    record(plan(kStartMetS + 104.69, static_cast<std::uint8_t>(msg::CallHomeReason::kNoPlanWithinRisk)));
    return file.str();
}

}  // namespace

TEST_GROUP(MissionFromTelemetry){};

TEST(MissionFromTelemetry, TheTenPointsThePlanAndTheTrackComeFromTheRecording) {
    std::istringstream in(demoRecording());
    const ground::SessionRecording recording = ground::readSessionRecording(in);
    CHECK_TRUE(recording.errors.empty());
    const ground::MissionTelemetry mission = ground::readMissionTelemetry(recording);
    const ground::TelemetryMissionRecord result =
        ground::missionRecordFromTelemetry(recording, mission, test::oneRock(), 0.6, "demo over vcan0");
    const ground::MissionRecord& r = result.record;
    CHECK_TRUE(r.allInOrder);
    LONGS_EQUAL(10, result.pointsInOrder.size());
    for (std::size_t i = 0; i < result.pointsInOrder.size(); ++i) {
        LONGS_EQUAL(static_cast<long>(i + 1), result.pointsInOrder[i].number);
    }
    // At the events' flight times (MET less the start HK gave).
    DOUBLES_EQUAL(0.39, r.points[0].timeS, 1e-5);
    DOUBLES_EQUAL(104.68, r.points[9].timeS, 1e-5);
    CHECK_TRUE(contains(r.points[9].what, "CALL HOME, operator called: no plan within the risk limit"));
    // The plan from PLAN_PATH, ready for its ellipses.
    LONGS_EQUAL(1, result.plansDrawn);
    LONGS_EQUAL(1, r.plans.size());
    LONGS_EQUAL(3, r.plans[0].plan.steps);
    DOUBLES_EQUAL(14.33, r.plans[0].plan.meanX[2], 1e-5);
    DOUBLES_EQUAL(0.01, r.plans[0].problem.startCov[3], 1e-7);
    DOUBLES_EQUAL(0.05, r.plans[0].problem.processSigmaM, 1e-7);
    DOUBLES_EQUAL(1e-3, r.plans[0].problem.riskBound, 0.0);
    DOUBLES_EQUAL(1.47, r.plans[0].timeS, 1e-5);
    CHECK_EQUAL(test::kDemo.size(), r.estimatedTrack.size());
    CHECK_TRUE(r.truthTrack.empty());  // no truth in telemetry
    CHECK_TRUE(contains(r.outcome, "called home at 104.7 s, reason 1"));
}

// Every EVENT_DATA paired with its EVENT; one arriving after the next event's
// pair is still paired (by event_sequence, not by position).
TEST(MissionFromTelemetry, EachEventDataIsPairedWithItsEventBySequence) {
    std::size_t withData = 0;
    for (const test::Step& s : test::kDemo) {
        withData += s.data.count > 0 ? 1U : 0U;
    }
    DataFate late;
    late.delay = 4;  // leg 1 achieved (808): its numbers after 906's EVENT and EVENT_DATA
    for (const DataFate& fate : {DataFate{}, late}) {
        std::istringstream in(demoRecording(fate));
        const ground::SessionRecording recording = ground::readSessionRecording(in);
        const ground::MissionTelemetry mission = ground::readMissionTelemetry(recording);
        const ground::TelemetryMissionRecord result =
            ground::missionRecordFromTelemetry(recording, mission, test::oneRock(), 0.6, "demo");
        LONGS_EQUAL(withData, result.eventDataPaired);
        LONGS_EQUAL(0, result.eventsWithoutData);
        LONGS_EQUAL(0, result.eventDataStray);
        CHECK_TRUE(result.record.allInOrder);
        LONGS_EQUAL(withData, mission.eventDataPaired);
        LONGS_EQUAL(0, mission.eventsWithoutData);
        // The summary's events carry their numbers too.
        cmdtlm::event_data::LEG_SENT sent;
        bool legOne = false;
        for (const ground::TelemetryEvent& e : mission.events) {
            legOne = legOne || (sent.unpack(e.id, e.data) && sent.leg_id == 1.0 && sent.power_bound == 308.0);
        }
        CHECK_TRUE(legOne);
    }
}

// The first leg's EVENT_DATA lost: its event is read without numbers (counted),
// so the points that needed them (2: the plan's first leg) are missing, not
// guessed from the words; the rest are read as before.
TEST(MissionFromTelemetry, AnEventWhoseDataWasLostIsCountedAndShowsNoPoint) {
    DataFate fate;
    fate.lose = 2;  // 905, leg 1
    std::istringstream in(demoRecording(fate));
    const ground::SessionRecording recording = ground::readSessionRecording(in);
    const ground::MissionTelemetry mission = ground::readMissionTelemetry(recording);
    const ground::TelemetryMissionRecord result =
        ground::missionRecordFromTelemetry(recording, mission, test::oneRock(), 0.6, "demo");
    LONGS_EQUAL(1, result.eventsWithoutData);
    LONGS_EQUAL(0, result.eventDataStray);
    LONGS_EQUAL(1, mission.eventsWithoutData);
    CHECK_FALSE(result.record.points[1].seen);
    CHECK_TRUE(result.record.points[0].seen);
    CHECK_TRUE(result.record.points[9].seen);
    CHECK_TRUE(contains(result.record.verdict, "missing 2"));
}

// An EVENT lost on the way with its EVENT_DATA received: the numbers are stray
// (counted, dropped); nothing else is paired wrongly.
TEST(MissionFromTelemetry, EventDataWhoseEventNeverCameIsCountedStray) {
    std::size_t withData = 0;
    for (const test::Step& s : test::kDemo) {
        withData += s.data.count > 0 ? 1U : 0U;
    }
    DataFate fate;
    fate.loseEvent = 7;  // 816, hazard 3 remembered
    std::istringstream in(demoRecording(fate));
    const ground::SessionRecording recording = ground::readSessionRecording(in);
    const ground::MissionTelemetry mission = ground::readMissionTelemetry(recording);
    const ground::TelemetryMissionRecord result =
        ground::missionRecordFromTelemetry(recording, mission, test::oneRock(), 0.6, "demo");
    LONGS_EQUAL(1, result.eventDataStray);
    LONGS_EQUAL(withData - 1, result.eventDataPaired);
    LONGS_EQUAL(0, result.eventsWithoutData);
    LONGS_EQUAL(1, mission.eventDataStray);
    CHECK_TRUE(result.record.hazards.empty());  // only 816 tells a hazard
    CHECK_TRUE(result.record.allInOrder);        // 804 names the disc: point 5 still seen
}

TEST(MissionFromTelemetry, ReportWritesTheFilesAndExitsByTheVerdict) {
    test::CliRig rig;
    const std::string file = rig.dir.file("session.rec");
    {
        std::ofstream out(file);
        out << demoRecording();
    }
    std::uint8_t image[tables::kMaxTableImageSize];
    const std::size_t n = tables::encodeTable(test::oneRock(), 1, image, sizeof image);
    CHECK(n > 0);
    const std::string map = rig.dir.file("map.tbl");
    ground::writeTableImageFile(map, std::vector<std::uint8_t>(image, image + n));
    const std::string outDir = rig.dir.file("report");
    test::CliResult r = rig.run({"report", file, "--map", map, "--out", outDir});
    CHECK_EQUAL(0, r.rc);
    CHECK_TRUE(contains(r.out, "] POINT 1 operator: "));
    CHECK_TRUE(contains(r.out, "] POINT 10 deliberative + mode owner: "));
    CHECK_TRUE(contains(r.out, "points:     ten points: all in order\n"));
    CHECK_TRUE(contains(r.out, "plans:      1 drawn from PLAN_PATH (1 made, events 902)\n"));
    CHECK_TRUE(contains(r.out, "event data: 22 EVENT_DATA paired, 0 events without their numbers, 0 stray\n"));
    std::ifstream report(outDir + "/report.md");
    const std::string md((std::istreambuf_iterator<char>(report)), std::istreambuf_iterator<char>());
    CHECK_TRUE(contains(md, "**ten points: all in order**"));
    CHECK_TRUE(contains(md, "demo") || contains(md, "session.rec"));
    std::ifstream svg(outDir + "/map.svg");
    const std::string picture((std::istreambuf_iterator<char>(svg)), std::istreambuf_iterator<char>());
    CHECK_TRUE(contains(picture, "<svg"));

    // Without the call home's reason the ten points are not all there: exit 3.
    std::string partial = demoRecording();
    partial.erase(partial.rfind('\n', partial.size() - 2) + 1);  // the last packet: PLAN with the reason
    {
        std::ofstream out(file);
        out << partial;
    }
    r = rig.run({"report", file, "--map", map, "--out", outDir});
    CHECK_EQUAL(3, r.rc);
    CHECK_TRUE(contains(r.out, "missing 10"));

    // Bad input: a map that is no COARSE_MAP, a missing recording, no recording at all.
    r = rig.run({"report", file, "--map", file, "--out", outDir});
    CHECK_EQUAL(2, r.rc);
    CHECK_TRUE(contains(r.err, "is not a good COARSE_MAP image"));
    CHECK_EQUAL(1, rig.run({"report", rig.dir.file("missing.rec"), "--map", map}).rc);
    CHECK_EQUAL(2, rig.run({"report"}).rc);
}

// Site mode: a route's ROUTE chunks become the record's route, in order, and
// the mission map draws it (and the site map's rocks the record holds).
TEST(MissionFromTelemetry, ARoutesChunksBecomeItsRouteAndTheMapDrawsIt) {
    std::ostringstream file;
    ground::SessionRecorder recorder(file, "UDP", 1733157000.0);
    double received = 0.0;
    recorder.record(received += 0.01, housekeeping(kStartMetS + 0.2));
    for (std::uint8_t c = 0; c < 2; ++c) {
        cmdtlm::ROUTE_Tlm t{};
        t.route_number = 1;
        t.point_count = 40;
        t.chunk_index = c;
        t.chunk_count = 2;
        t.count = c == 0 ? 32 : 8;
        for (std::uint8_t k = 0; k < t.count; ++k) {
            t.x[k] = static_cast<float>(32 * c + k);   // x runs 0 .. 39 over the route
            t.y[k] = 1.0F;
        }
        recorder.record(received += 0.01, test::telemetryPacket(t, 0, at(kStartMetS + 1.0)));
    }
    std::istringstream in(file.str());
    const ground::SessionRecording recording = ground::readSessionRecording(in);
    CHECK_TRUE(recording.errors.empty());
    const ground::MissionTelemetry mission = ground::readMissionTelemetry(recording);
    ground::TelemetryMissionRecord result =
        ground::missionRecordFromTelemetry(recording, mission, test::oneRock(), 0.6, "site mode");
    ground::MissionRecord& r = result.record;
    LONGS_EQUAL(1, r.routes.size());
    LONGS_EQUAL(40, r.routes[0].size());
    DOUBLES_EQUAL(0.0, r.routes[0].front().x, 0.0);
    DOUBLES_EQUAL(39.0, r.routes[0].back().x, 0.0);
    r.siteRocks.push_back({{5.0, 2.0}, {6.0, 2.0}, {6.0, 3.0}});
    const std::string svg = ground::renderMissionMap(r);
    CHECK_TRUE(contains(svg, "class=\"route\""));
    CHECK_TRUE(contains(svg, "class=\"site-rock\""));
    CHECK_TRUE(contains(svg, "global route (site map)"));
}
