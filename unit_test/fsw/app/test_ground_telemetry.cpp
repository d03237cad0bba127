// The whole flight application's telemetry as a ground station receives it
// (ground_station_rig.hpp): each packet family from its owner's packer, on its
// schedule, carrying what the bus told it.
#include "unit_test/fsw/app/ground_station_rig.hpp"

using namespace rse;
using namespace rse::cmdtlm;
using namespace rse::test::ground;

TEST_GROUP_BASE(GroundTelemetry, GroundStation){};

TEST(GroundTelemetry, GoalsAndRiskBoundShowInThePlanPacket) {
    send("SET_MODE", {1});
    std::vector<std::uint8_t> args(24);
    core::BeWriter w(args.data(), args.size());
    w.f64(12.5);
    w.f64(-3.0);
    w.f64(1e-6);
    send("GOTO", args);
    runFrames(3);
    expectAccepted("GOTO");
    const Packet& plan = last("PLAN");
    LONGS_EQUAL(1, static_cast<long>(field(plan, "goal_count")));
    DOUBLES_EQUAL(12.5, field(plan, "goal_x"), 1e-6);
    DOUBLES_EQUAL(-3.0, field(plan, "goal_y"), 1e-6);
    DOUBLES_EQUAL(1e-6, field(plan, "risk_bound"), 1e-15);
    // STANDBY: the deliberative layer (10 Hz) takes the goal and waits for
    // AUTONOMOUS; PLAN is sent again when its state changes. No legs yet.
    runFrames(10);
    const Packet& waiting = last("PLAN");
    LONGS_EQUAL(1, static_cast<long>(field(waiting, "status")));
    LONGS_EQUAL(1, static_cast<long>(field(waiting, "goal_count")));
    LONGS_EQUAL(0, static_cast<long>(field(waiting, "waypoint_count")));
}

// PLAN_PATH: the telemetry task sends one packet per PlanPathMsg it takes off
// the bus (an on-event packet, never repeated), its fields decoded by the
// dictionary's descriptors carrying the message's values; no heap on the way.
// A message with more steps than means is malformed: counted, not sent.
TEST(GroundTelemetry, APlanPathOnTheBusGoesDownAsOnePlanPathPacket) {
    runFrames(3);
    received.clear();
    msg::PlanPathMsg m{};
    m.timeNs = 12 * core::kNsPerSec + 250 * core::kNsPerMs;
    m.planNumber = 7;
    m.status = 1;
    m.steps = 3;
    m.riskBound = 1e-3;
    m.riskUsed = 7.5e-4;
    m.lengthM = 20.25;
    m.processSigmaM = 0.0625;
    m.startCov[0] = 0.04;
    m.startCov[1] = 0.005;
    m.startCov[2] = 0.005;
    m.startCov[3] = 0.09;
    m.goalX = 20.0;
    m.goalY = -1.5;
    const double xs[4] = {0.5, 7.0, 13.5, 20.0};
    const double ys[4] = {0.0, 1.25, -0.75, -1.5};
    for (std::size_t t = 0; t < 4; ++t) {
        m.meanX[t] = xs[t];
        m.meanY[t] = ys[t];
    }
    std::size_t downlinked = 0;
    {
        test::AllocationWatch watch;
        CHECK(core::isOk(fsw.bus().publish(m)));
        fsw.run(nullptr, 1);
        LONGS_EQUAL(0, watch.count());
        std::uint8_t bytes[hal::kMemoryLinkMaxPacket];
        std::size_t length = 0;
        while (core::isOk(link.groundReceive(bytes, sizeof bytes, &length))) {
            const PrimaryHeader h = decodePrimaryHeader(bytes);
            downlinked += h.apid == findTelemetry("PLAN_PATH")->apid ? 1U : 0U;
            if (h.apid == findTelemetry("PLAN_PATH")->apid) {
                LONGS_EQUAL(findTelemetry("PLAN_PATH")->payloadSize, length - kTelemetryHeaderSize);
                Packet p;
                p.apid = h.apid;
                received.push_back(p);  // after the watch's count: the test's own heap
                received.back().payload.assign(bytes + kTelemetryHeaderSize, bytes + length);
            }
        }
    }
    LONGS_EQUAL(1, downlinked);
    LONGS_EQUAL(0x017, findTelemetry("PLAN_PATH")->apid);
    const Packet& path = last("PLAN_PATH");
    LONGS_EQUAL(7, static_cast<long>(field(path, "plan_number")));
    DOUBLES_EQUAL(12.25, field(path, "plan_time"), 1e-12);
    LONGS_EQUAL(1, static_cast<long>(field(path, "status")));
    LONGS_EQUAL(3, static_cast<long>(field(path, "steps")));
    DOUBLES_EQUAL(1e-3, field(path, "risk_bound"), 0.0);
    DOUBLES_EQUAL(7.5e-4, field(path, "risk_used"), 0.0);
    DOUBLES_EQUAL(20.25, field(path, "length"), 0.0);
    DOUBLES_EQUAL(0.0625, field(path, "process_sigma"), 0.0);
    DOUBLES_EQUAL(0.04, field(path, "start_cov", 0), 1e-8);
    DOUBLES_EQUAL(0.005, field(path, "start_cov", 1), 1e-9);
    DOUBLES_EQUAL(0.005, field(path, "start_cov", 2), 1e-9);
    DOUBLES_EQUAL(0.09, field(path, "start_cov", 3), 1e-8);
    DOUBLES_EQUAL(20.0, field(path, "goal_x"), 0.0);
    DOUBLES_EQUAL(-1.5, field(path, "goal_y"), 0.0);
    for (std::size_t t = 0; t < 4; ++t) {
        DOUBLES_EQUAL(xs[t], field(path, "mean_x", t), 0.0);
        DOUBLES_EQUAL(ys[t], field(path, "mean_y", t), 0.0);
    }
    for (std::size_t t = 4; t < msg::kPlanPathMeans; ++t) {
        DOUBLES_EQUAL(0.0, field(path, "mean_x", t), 0.0);
        DOUBLES_EQUAL(0.0, field(path, "mean_y", t), 0.0);
    }
    LONGS_EQUAL(1, fsw.planTelemetry().planPathsSent());

    // Not repeated: nothing new on the bus, no packet.
    runFrames(120);
    LONGS_EQUAL(1, countOf("PLAN_PATH"));

    // More steps than the message has means: malformed, counted, not sent.
    const std::uint32_t malformed = fsw.telemetry().malformed();
    m.steps = static_cast<std::uint8_t>(msg::kPlanPathMeans);
    CHECK(core::isOk(fsw.bus().publish(m)));
    runFrames(1);
    LONGS_EQUAL(malformed + 1, fsw.telemetry().malformed());
    LONGS_EQUAL(1, countOf("PLAN_PATH"));
    LONGS_EQUAL(1, fsw.planTelemetry().planPathsSent());
}

// PLAN_EXTEND: refused by mode in SAFE; in STANDBY passed to the plan
// executive as a PlanCommandMsg (the extra time in ms, the name's bytes),
// which refuses it with no plan running: event 976, PLAN_EXEC's counters.
TEST(GroundTelemetry, RoverStateAndHealthReportTheEstimatorAndFaults) {
    const std::uint64_t staleBits = std::uint64_t{0xF} << msg::fault::kSensorStale;
    runFrames(250);
    const Packet& early = last("HEALTH");
    const auto earlyMask = static_cast<std::uint64_t>(field(early, "active_faults"));
    CHECK((earlyMask & ~staleBits) == 0);
    LONGS_EQUAL(0, static_cast<long>(field(last("ROVER_STATE"), "estimate_valid")));
    const std::size_t before = countOf("HEALTH");
    runFrames(100);  // past 3 s
    CHECK(countOf("HEALTH") >= before + 1);
    const Packet& health = last("HEALTH");
    std::uint64_t expected = (std::uint64_t{1} << msg::fault::kPoseUncertain) | staleBits;
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        expected |= std::uint64_t{1} << (msg::fault::kDriveHeartbeatLost + w);
    }
    DOUBLES_EQUAL(static_cast<double>(expected), field(health, "active_faults"), 0.0);
    LONGS_EQUAL(msg::fault::kPoseUncertain, static_cast<long>(field(health, "last_fault_id")));
    LONGS_EQUAL(1, static_cast<long>(field(health, "last_fault_raised")));
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, static_cast<long>(field(health, "drive_mode", w)));  // nominal
        DOUBLES_EQUAL(1.0, field(health, "power_factor", w), 1e-6);
    }
    DOUBLES_EQUAL(1000.0, field(last("ROVER_STATE"), "position_sigma"), 1e-3);
}

// EXEC_SET_TASK: ground disables a rate-group row; it stops running, the health
// monitor sees it stall and fault protection runs it again (FAULT_PROTECTION
// class 7, restart the task), as documented in docs/fault_protection.md.
TEST(GroundTelemetry, AnEventBurstBeyondTheLinksRoomWaitsInTheEventLogAndArrivesWhole) {
    runFrames(2);
    received.clear();
    constexpr int kBurst = 3 * static_cast<int>(hal::kMemoryLinkDownlinkDepth);
    static_assert(kBurst < static_cast<int>(core::kEventRingDepth), "the burst fits the event log");
    for (int i = 0; i < kBurst; ++i) {
        fsw.events().report(999, core::Severity::kInfo, "burst %d", i);
    }
    fsw.run(nullptr, 10);  // the ground reads nothing for 10 frames: the downlink fills
    CHECK(link.downlinkQueued() > 0);
    runFrames(60);
    std::vector<long> sequences;
    int next = 0;
    for (const Packet& p : received) {
        if (p.apid != findTelemetry("EVENT")->apid) {
            continue;
        }
        sequences.push_back(static_cast<long>(field(p, "event_sequence")));
        if (static_cast<long>(field(p, "event_id")) == 999) {
            ++next;
        }
    }
    LONGS_EQUAL(kBurst, next);
    for (std::size_t i = 1; i < sequences.size(); ++i) {
        LONGS_EQUAL(sequences[i - 1] + 1, sequences[i]);  // no gap: nothing lost on the way
    }
    LONGS_EQUAL(0, fsw.events().lost());
    LONGS_EQUAL(0, fsw.telemetryOutput().dropped(hal::TxPriority::kEvent));
}

// POWER (1 Hz, minor frame 30): the power monitor's sample and every drive's
// motor temperature, from the frames the devices put on the CAN bus through
// CAN I/O's bus messages, each field equal to what PowerMsg and
// DriveStatusMsg carried. A drive that has not reported a temperature reads
// invalid (0). No heap on the way.
TEST(GroundTelemetry, PowerCarriesTheBatteryAndEveryMotorTemperatureFromTheBus) {
    hal::MemoryCanEndpoint* devices = can.attach("devices");
    CHECK(devices != nullptr);
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kPower)));
    runFrames(100);
    LONGS_EQUAL(1, countOf("POWER"));  // nothing heard yet: all zero, no temperature valid
    LONGS_EQUAL(0x018, findTelemetry("POWER")->apid);
    DOUBLES_EQUAL(0.0, field(last("POWER"), "battery_voltage"), 0.0);
    DOUBLES_EQUAL(0.0, field(last("POWER"), "power_sample_time"), 0.0);
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        LONGS_EQUAL(0, static_cast<long>(field(last("POWER"), "temperature_valid", w)));
    }

    // The power monitor (0x6A1: mV, mA + discharge, 0.01 %, mA) and TPDO2 of
    // drive nodes 1..5 (0.1 degC); node 6 (RR) stays silent.
    hal::CanFrame power{};
    power.id = hal::device_ids::kPower;
    power.dlc = 8;
    const std::uint16_t millivolts = 27123;
    const auto charging = static_cast<std::uint16_t>(-1500);
    const std::uint16_t soc = 8765;
    const std::uint16_t solar = 2500;
    const std::uint16_t words[4] = {millivolts, charging, soc, solar};
    for (std::size_t i = 0; i < 4; ++i) {
        power.data[2 * i] = static_cast<std::uint8_t>(words[i]);
        power.data[2 * i + 1] = static_cast<std::uint8_t>(words[i] >> 8);
    }
    CHECK(core::isOk(devices->send(power)));
    const std::int16_t deciC[5] = {215, 350, -105, 812, 650};
    for (std::size_t node = 1; node <= 5; ++node) {
        hal::CanFrame tpdo2{};
        tpdo2.id = 0x280 + static_cast<std::uint32_t>(node);
        tpdo2.dlc = 2;
        tpdo2.data[0] = static_cast<std::uint8_t>(deciC[node - 1]);
        tpdo2.data[1] = static_cast<std::uint8_t>(static_cast<std::uint16_t>(deciC[node - 1]) >> 8);
        CHECK(core::isOk(devices->send(tpdo2)));
    }
    // What CAN I/O published, as the telemetry task read it: the power sample,
    // and the drive status of the frame POWER went down in (one a frame).
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kDriveStatus)));
    msg::PowerMsg published{};
    int powerMessages = 0;
    msg::DriveStatusMsg drives{};
    msg::DriveStatusMsg drivesWhenSent{};
    std::uint64_t allocations = 0;
    for (int i = 0; i < 100; ++i) {
        {
            test::AllocationWatch watch;
            fsw.run(nullptr, 1);
            allocations += watch.count();
        }
        core::Message m;
        while (core::isOk(fsw.bus().receive(probe, &m))) {
            if (m.header.id == msg::ids::kPower) {
                CHECK(core::isOk(m.decode(&published)));
                ++powerMessages;
            } else if (m.header.id == msg::ids::kDriveStatus) {
                CHECK(core::isOk(m.decode(&drives)));
            }
        }
        const std::size_t before = countOf("POWER");
        collectDownlink(link, &received);
        if (countOf("POWER") > before) {
            drivesWhenSent = drives;
        }
    }
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(2, countOf("POWER"));
    LONGS_EQUAL(1, powerMessages);
    const Packet& p = last("POWER");
    DOUBLES_EQUAL(27.123, published.busVoltageV, 1e-12);
    DOUBLES_EQUAL(static_cast<float>(published.busVoltageV), field(p, "battery_voltage"), 0.0);
    DOUBLES_EQUAL(static_cast<float>(published.busCurrentA), field(p, "battery_current"), 0.0);
    DOUBLES_EQUAL(-1.5, field(p, "battery_current"), 0.0);
    DOUBLES_EQUAL(static_cast<float>(published.stateOfCharge), field(p, "state_of_charge"), 0.0);
    DOUBLES_EQUAL(0.8765, field(p, "state_of_charge"), 1e-7);
    DOUBLES_EQUAL(2.5, field(p, "solar_current"), 0.0);
    CHECK(published.timeNs > 0);
    DOUBLES_EQUAL(static_cast<float>(static_cast<double>(published.timeNs) / 1e9), field(p, "power_sample_time"), 0.0);
    for (std::size_t w = 0; w < 5; ++w) {
        LONGS_EQUAL(1, drivesWhenSent.wheels[w].temperatureValid);
        LONGS_EQUAL(1, static_cast<long>(field(p, "temperature_valid", w)));
        DOUBLES_EQUAL(drivesWhenSent.wheels[w].temperatureC, field(p, "motor_temperature", w), 0.0);
        DOUBLES_EQUAL(static_cast<float>(deciC[w]) * 0.1F, field(p, "motor_temperature", w), 0.0);
    }
    LONGS_EQUAL(0, drivesWhenSent.wheels[5].temperatureValid);
    LONGS_EQUAL(0, static_cast<long>(field(p, "temperature_valid", 5)));
    DOUBLES_EQUAL(0.0, field(p, "motor_temperature", 5), 0.0);
}

// HAZARDS (APID 0x019): the habitual layer's remembered hazards. With the
// hazard map unchanged it goes down every 5 s (minor frame 45 of every fifth
// second); a new revision goes down in the next minor frame 45, carrying the
// message's hazards, with no heap. A message listing more hazards than it
// holds is malformed: counted, not sent.
TEST(GroundTelemetry, HazardsGoDownEveryFiveSecondsAndWithinASecondOfANewRevision) {
    CHECK(core::isOk(fsw.bus().subscribe(probe, msg::ids::kKnownHazards)));
    std::vector<std::uint64_t> hazardFrames;
    msg::KnownHazardsMsg habitual{};  // the habitual layer's latest
    std::uint64_t allocations = 0;
    // One frame: run (heap counted), the packets taken, the probe drained;
    // true when the habitual layer published its hazards in it.
    auto step = [&]() {
        {
            test::AllocationWatch watch;
            fsw.run(nullptr, 1);
            allocations += watch.count();
        }
        const std::size_t before = received.size();
        collectDownlink(link, &received);
        for (std::size_t i = before; i < received.size(); ++i) {
            if (received[i].apid == findTelemetry("HAZARDS")->apid) {
                hazardFrames.push_back(fsw.executive().stats().framesRun - 1);
            }
        }
        bool published = false;
        core::Message m;
        while (core::isOk(fsw.bus().receive(probe, &m))) {
            if (m.header.id == msg::ids::kKnownHazards) {
                CHECK(core::isOk(m.decode(&habitual)));
                published = true;
            }
        }
        return published;
    };
    for (int i = 0; i < 1000; ++i) {
        (void)step();
    }
    // Ten seconds, the map unchanged (nothing seen): two packets, at frames 45 and 545.
    LONGS_EQUAL(2, hazardFrames.size());
    LONGS_EQUAL(45, static_cast<long>(hazardFrames[0]));
    LONGS_EQUAL(545, static_cast<long>(hazardFrames[1]));
    LONGS_EQUAL(habitual.revision, static_cast<long>(field(last("HAZARDS"), "revision")));
    LONGS_EQUAL(0, static_cast<long>(field(last("HAZARDS"), "count")));
    LONGS_EQUAL(2, fsw.hazardsTelemetry().hazardsSent());

    // Just after the habitual layer's 1 Hz publication (so none of its own
    // comes before the next frame 45), and not in a second whose frame 45 is
    // the 5 s one: a new revision.
    std::uint64_t frame = 0;
    std::uint64_t next45 = 0;
    for (int i = 0; i < 1000; ++i) {
        const bool published = step();
        frame = fsw.executive().stats().framesRun - 1;
        next45 = frame + (145 - frame % 100) % 100;
        next45 += next45 == frame ? 100 : 0;
        if (published && next45 % 500 != 45) {
            break;
        }
    }
    CHECK(next45 % 500 != 45);
    msg::KnownHazardsMsg seen{};
    seen.timeNs = 1;
    seen.revision = habitual.revision + 7;
    seen.count = 2;
    seen.hazards[0] = msg::KnownHazard{12.5F, -1.25F, 0.5F, 7, {}};
    seen.hazards[1] = msg::KnownHazard{3.0F, 4.0F, 0.25F, 9, {}};
    CHECK(core::isOk(fsw.bus().publish(seen)));
    const std::size_t sentBefore = hazardFrames.size();
    while (fsw.executive().stats().framesRun - 1 < next45) {
        (void)step();
    }
    LONGS_EQUAL(sentBefore + 1, hazardFrames.size());
    LONGS_EQUAL(static_cast<long>(next45), static_cast<long>(hazardFrames.back()));
    const Packet& h = last("HAZARDS");
    LONGS_EQUAL(seen.revision, static_cast<long>(field(h, "revision")));
    LONGS_EQUAL(2, static_cast<long>(field(h, "count")));
    DOUBLES_EQUAL(12.5, field(h, "x", 0), 0.0);
    DOUBLES_EQUAL(-1.25, field(h, "y", 0), 0.0);
    DOUBLES_EQUAL(0.5, field(h, "radius", 0), 0.0);
    LONGS_EQUAL(7, static_cast<long>(field(h, "obstacle_id", 0)));
    DOUBLES_EQUAL(3.0, field(h, "x", 1), 0.0);
    DOUBLES_EQUAL(4.0, field(h, "y", 1), 0.0);
    DOUBLES_EQUAL(0.25, field(h, "radius", 1), 0.0);
    LONGS_EQUAL(9, static_cast<long>(field(h, "obstacle_id", 1)));
    for (std::size_t i = 2; i < msg::kMaxKnownHazards; ++i) {
        DOUBLES_EQUAL(0.0, field(h, "radius", i), 0.0);
        LONGS_EQUAL(0, static_cast<long>(field(h, "obstacle_id", i)));
    }
    LONGS_EQUAL(0, allocations);

    // More hazards than the message holds: malformed, counted, not taken.
    const std::uint32_t malformed = fsw.telemetry().malformed();
    msg::KnownHazardsMsg bad = seen;
    bad.revision = seen.revision + 1;
    bad.count = static_cast<std::uint8_t>(msg::kMaxKnownHazards + 1);
    CHECK(core::isOk(fsw.bus().publish(bad)));
    (void)step();
    LONGS_EQUAL(malformed + 1, fsw.telemetry().malformed());
}
