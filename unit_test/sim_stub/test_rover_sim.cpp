#include <cmath>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "hal/canopen/le_codec.hpp"
#include "sim_stub/rover_sim.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"
#include "unit_test/sim_stub/recording_fault_target.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;
using hal::CanFrame;

namespace {

constexpr core::TimeNs kMs = core::kNsPerMs;
constexpr core::TimeNs kTick = 10 * kMs;  // the flight software's minor frame

// The drive emulators' stand-in: applies motor faults to the fake wheels and
// records every drive hook.
class FakeDriveFaults final : public FaultTarget {
public:
    explicit FakeDriveFaults(test::FakeWheels& wheels) : wheels_(wheels) {}
    test::RecordingFaultTarget record;
    bool recording = true;  // off where the test counts allocations (the log allocates)
    unsigned hooks = 0;
    bool failed[kWheelCount] = {};

    void degradeMotor(std::size_t wheel, double k) override {
        wheels_.w[wheel].setFactor(k);
        if (note()) {
            record.degradeMotor(wheel, k);
        }
    }
    void failMotor(std::size_t wheel) override {
        failed[wheel] = true;
        if (note()) {
            record.failMotor(wheel);
        }
    }
    void suppressHeartbeat(std::size_t wheel, bool on) override {
        if (note()) {
            record.suppressHeartbeat(wheel, on);
        }
    }
    void crashDrive(std::size_t wheel) override {
        if (note()) {
            record.crashDrive(wheel);
        }
    }
    void restartDrive(std::size_t wheel) override {
        if (note()) {
            record.restartDrive(wheel);
        }
    }
    void setDeviceDropout(SimDevice d, bool on) override { record.setDeviceDropout(d, on); }
    void crashDevice(SimDevice d) override { record.crashDevice(d); }
    void restartDevice(SimDevice d) override { record.restartDevice(d); }
    void failInstrument(SimDevice d, std::uint8_t code, bool silent, bool on) override {
        record.failInstrument(d, code, silent, on);
    }
    void stepImuBias(double delta) override { record.stepImuBias(delta); }
    void addBusFault(const hal::CanFaultRule& r) override { record.addBusFault(r); }
    void babble(std::uint32_t id, double rate, bool on) override { record.babble(id, rate, on); }
    void positionFixOutlier(double offsetM, double bearingRad, std::uint32_t count) override {
        record.positionFixOutlier(offsetM, bearingRad, count);
    }
    void slideRover(double offsetM, double bearingRad, double durationS) override {
        record.slideRover(offsetM, bearingRad, durationS);
    }
    void stallFlightTask(std::size_t row, const std::string& name, bool on) override {
        record.stallFlightTask(row, name, on);
    }

private:
    bool note() {
        ++hooks;
        return recording;
    }
    test::FakeWheels& wheels_;
};

class CountingListener final : public SimFrameListener {
public:
    std::size_t frames = 0;
    std::uint32_t lastId = 0xFFFF;
    void onFrame(const CanFrame& frame, core::TimeNs) override {
        ++frames;
        lastId = frame.id;
    }
};

// One complete lockstep rig: a virtual clock, an in-memory bus with a "flight"
// endpoint (the test plays the flight software) and the simulator's endpoint.
struct Rig {
    core::VirtualClock clock;
    hal::MemoryCanBus wire{clock};
    hal::MemoryCanEndpoint* flight;
    hal::MemoryCanEndpoint* simPort;
    test::FakeWheels wheels;
    FakeDriveFaults drives{wheels};
    CountingListener listener;
    RoverSim sim;
    std::vector<CanFrame> frames;
    bool capture = true;
    std::size_t received = 0;

    explicit Rig(const Scenario& s, bool wired = true)
        : flight(wire.attach("flight")),
          simPort(wire.attach("sim")),
          sim(s, *simPort, wheels.models(),
              wired ? RoverSimWiring{&wire, &drives, &listener} : RoverSimWiring{}) {}

    void drive(double left, double right) {
        wheels.drive(left, right);
        for (std::size_t i = 0; i < kWheelCount; ++i) {
            if (drives.failed[i]) {
                wheels.w[i].command(0.0);
            }
        }
    }
    void tick(core::TimeNs t) {
        clock.sleepUntil(t);
        sim.step(t);
        CanFrame f;
        while (core::isOk(flight->receive(&f))) {
            ++received;
            if (capture) {
                frames.push_back(f);
            }
        }
    }
    void runUntil(core::TimeNs until, core::TimeNs step = kTick) {
        for (core::TimeNs t = clock.now() + (received == 0 && sim.stats().steps == 0 ? 0 : step); t <= until;
             t += step) {
            tick(t);
        }
    }
    std::vector<CanFrame> withId(std::uint32_t id) const {
        std::vector<CanFrame> out;
        for (const CanFrame& f : frames) {
            if (f.id == id) {
                out.push_back(f);
            }
        }
        return out;
    }
};

Scenario demo() { return loadScenarioFile("sim_stub/scenarios/demo_mission.toml"); }

Scenario openGround(std::uint64_t seed = 1) {
    Scenario s;
    s.seed = seed;
    s.map = MapBounds{-50, 50, -50, 50};
    return s;
}

// The position fixes a rig received, in metres (x from 0x6A3, y from 0x6A4).
struct Fix {
    double x = 0.0;
    double y = 0.0;
    std::uint16_t counter = 0;
};
std::vector<Fix> fixes(const Rig& rig) {
    const std::vector<CanFrame> xs = rig.withId(0x6A3);
    const std::vector<CanFrame> ys = rig.withId(0x6A4);
    std::vector<Fix> out;
    for (std::size_t i = 0; i < xs.size() && i < ys.size(); ++i) {
        Fix f;
        f.x = hal::le::getI32(&xs[i].data[0]) * 1e-3;
        f.y = hal::le::getI32(&ys[i].data[0]) * 1e-3;
        f.counter = hal::le::getU16(&xs[i].data[6]);
        out.push_back(f);
    }
    return out;
}

bool sameFrame(const CanFrame& a, const CanFrame& b) {
    return a.id == b.id && a.dlc == b.dlc && a.flags == b.flags && a.timestamp == b.timestamp &&
           std::memcmp(a.data, b.data, sizeof a.data) == 0;
}

}  // namespace

TEST_GROUP(SimRover){};

TEST(SimRover, TwoSimulatorsWithTheSameSeedGiveIdenticalTruthAndFrames) {
    const Scenario s = demo();
    Rig* a = new Rig(s);
    Rig* b = new Rig(s);
    for (core::TimeNs t = 0; t <= 80 * core::kNsPerSec; t += kTick) {
        const bool turning = t > 20 * core::kNsPerSec && t < 22 * core::kNsPerSec;
        for (Rig* r : {a, b}) {
            r->drive(turning ? -3.0 : 4.0, 4.0);
            r->tick(t);
        }
        const TruthRecord& ta = a->sim.truth();
        const TruthRecord& tb = b->sim.truth();
        if (ta.pose.x != tb.pose.x || ta.pose.y != tb.pose.y || ta.pose.theta != tb.pose.theta ||
            ta.stateOfCharge != tb.stateOfCharge || ta.collisions != tb.collisions) {
            FAIL("truth diverged");
        }
    }
    LONGS_EQUAL(a->frames.size(), b->frames.size());
    CHECK(a->frames.size() > 4000);
    for (std::size_t i = 0; i < a->frames.size(); ++i) {
        if (!sameFrame(a->frames[i], b->frames[i])) {
            FAIL("frame sequences differ");
        }
    }
    CHECK(a->sim.truth().pose.x > 5.0);  // it really drove (with slip noise on)
    delete a;
    delete b;
}

TEST(SimRover, ADifferentSeedGivesDifferentNoise) {
    Scenario s = demo();
    Rig* a = new Rig(s);
    s.seed += 1;
    Rig* b = new Rig(s);
    a->runUntil(core::kNsPerSec);
    b->runUntil(core::kNsPerSec);
    const std::vector<CanFrame> ia = a->withId(0x6A0);
    const std::vector<CanFrame> ib = b->withId(0x6A0);
    LONGS_EQUAL(100, ia.size());
    LONGS_EQUAL(100, ib.size());
    std::size_t differ = 0;
    for (std::size_t i = 0; i < ia.size(); ++i) {
        differ += std::memcmp(ia[i].data, ib[i].data, 4) != 0 ? 1U : 0U;
    }
    CHECK(differ > 90);
    delete a;
    delete b;
}

TEST(SimRover, StepAllocatesNothingWhileDrivingWithFaultsFiring) {
    Scenario s = demo();
    // Put faults of every kind inside the watched window.
    auto add = [&s](FaultType type, double atS, double untilS) {
        FaultSpec f;
        f.type = type;
        f.at = static_cast<core::TimeNs>(atS * 1e9);
        f.until = untilS > 0.0 ? static_cast<core::TimeNs>(untilS * 1e9) : kNever;
        f.wheel = 2;
        f.device = SimDevice::kImu;
        f.value = type == FaultType::kBabblingNode ? 2000.0 : 1.5;
        f.cobId = 0x7E0;
        f.busRule.id = 0x723;
        f.busRule.count = 2;
        s.faults.push_back(f);
    };
    s.faults.clear();
    add(FaultType::kSensorDropout, 2.0, 3.0);
    add(FaultType::kDeviceCrash, 3.0, 3.5);
    add(FaultType::kImuBiasStep, 4.0, 0.0);
    add(FaultType::kBusFault, 4.5, 0.0);
    add(FaultType::kBabblingNode, 5.0, 5.05);
    add(FaultType::kMotorDegradation, 6.0, 0.0);
    add(FaultType::kMotorFailure, 7.0, 0.0);
    add(FaultType::kDriveCrash, 8.0, 8.5);
    add(FaultType::kPositionFixOutlier, 9.0, 0.0);  // 1.5 m, one fix
    Rig* rig = new Rig(s);
    rig->capture = false;
    rig->drives.recording = false;
    rig->drive(5.0, 5.0);
    rig->tick(0);
    std::uint64_t allocations = 0;
    {
        test::AllocationWatch watch;
        for (core::TimeNs t = kMs; t <= 20 * core::kNsPerSec; t += kMs) {  // to x ~ 10 m: hazard reports flowing
            rig->tick(t);
        }
        allocations = watch.count();
    }
    LONGS_EQUAL(0, allocations);
    LONGS_EQUAL(s.faults.size() + 4, rig->sim.faultSchedule().fired());
    LONGS_EQUAL(4, rig->drives.hooks);  // degrade, fail, crash, restart
    LONGS_EQUAL(1, rig->sim.positionFix().outliersProduced());
    CHECK(rig->sim.stats().babbleFrames > 50);
    CHECK(rig->received > 3000);  // 20 s: 2000 IMU, 200 power, 40 fix, 800 heartbeats, hazard, babble
    delete rig;
}

TEST(SimRover, DrivingDrawsTheBatteryDownAndTheMonitorReportsIt) {
    Scenario s = openGround();
    s.solar.peakCurrentA = 0.0;
    Rig* idle = new Rig(s);
    Rig* driving = new Rig(s);
    driving->drive(5.0, 5.0);
    idle->runUntil(60 * core::kNsPerSec);
    driving->runUntil(60 * core::kNsPerSec);
    const double start = s.battery.initialSoc;
    CHECK(driving->sim.truth().stateOfCharge < idle->sim.truth().stateOfCharge);
    CHECK(idle->sim.truth().stateOfCharge < start);
    const CanFrame last = driving->withId(0x6A1).back();
    const double reportedA = hal::le::getI16(&last.data[2]) * 1e-3;
    DOUBLES_EQUAL(driving->sim.truth().busCurrentA, reportedA, 0.05);
    const double idleA = hal::le::getI16(&idle->withId(0x6A1).back().data[2]) * 1e-3;
    CHECK(reportedA > idleA + 5.0);
    DOUBLES_EQUAL(30.0, driving->sim.truth().pose.x, 1e-6);
    delete idle;
    delete driving;
}

TEST(SimRover, ATurnDrawsMoreCurrentThanStraightDrivingAtTheSameWheelSpeed) {
    Rig* straight = new Rig(openGround());
    Rig* turn = new Rig(openGround());
    straight->drive(5.0, 5.0);
    turn->drive(-5.0, 5.0);
    straight->runUntil(5 * core::kNsPerSec);
    turn->runUntil(5 * core::kNsPerSec);
    const TruthRecord& a = straight->sim.truth();
    const TruthRecord& b = turn->sim.truth();
    for (std::size_t i = 0; i < kWheelCount; ++i) {
        DOUBLES_EQUAL(std::fabs(a.wheels[i].speedRadS), std::fabs(b.wheels[i].speedRadS), 0.0);
        CHECK(std::fabs(b.wheels[i].loadTorqueNm) > std::fabs(a.wheels[i].loadTorqueNm));
    }
    CHECK(b.motorCurrentA > 1.2 * a.motorCurrentA);
    CHECK(b.busCurrentA > a.busCurrentA);
    CHECK(b.stateOfCharge < a.stateOfCharge);
    delete straight;
    delete turn;
}

TEST(SimRover, DevicesBootOnTheFirstStepAndAnswerNmtThroughTheSharedEndpoint) {
    Rig* rig = new Rig(openGround());
    rig->tick(0);
    for (std::uint32_t id = 0x720; id <= 0x723; ++id) {
        LONGS_EQUAL(1, rig->withId(id).size());
        LONGS_EQUAL(0x00, rig->withId(id)[0].data[0]);
    }
    rig->runUntil(500 * kMs);
    CHECK(core::Status::kOk == rig->flight->send(test::nmt(0x82, 0)));  // what the master sends first
    rig->frames.clear();
    rig->tick(510 * kMs);
    for (std::uint32_t id = 0x720; id <= 0x723; ++id) {
        const std::vector<CanFrame> boot = rig->withId(id);
        LONGS_EQUAL(1, boot.size());
        LONGS_EQUAL(0x00, boot[0].data[0]);
    }
    CHECK(core::Status::kOk == rig->flight->send(test::nmt(0x02, 0x22)));  // stop the hazard detector only
    rig->frames.clear();
    rig->runUntil(2510 * kMs);
    LONGS_EQUAL(0, rig->withId(0x6A2).size());
    LONGS_EQUAL(20, rig->withId(0x722).size());
    LONGS_EQUAL(200, rig->withId(0x6A0).size());
    LONGS_EQUAL(2, rig->listener.frames);  // every frame read is offered to the listener
    LONGS_EQUAL(0x000, rig->listener.lastId);
    LONGS_EQUAL(2, rig->sim.stats().framesReceived);
    delete rig;
}

TEST(SimRover, TheFaultScheduleActsOnDevicesBusAndDrives) {
    Scenario s = parseScenario(R"(
seed = 9
[map]
x_min_m = -20.0
x_max_m = 20.0
y_min_m = -20.0
y_max_m = 20.0
[start]
x_m = 0.0
y_m = 0.0
[[faults]]
type = "sensor_dropout"
at_s = 1.0
device = "imu"
until_s = 2.0
[[faults]]
type = "device_crash"
at_s = 1.0
device = "position_fix"
restart_at_s = 3.0
[[faults]]
type = "motor_degradation"
at_s = 1.5
wheel = 2
current_factor = 2.0
[[faults]]
type = "bus_fault"
at_s = 2.5
action = "drop"
cob_id = 0x721
frames = 3
[[faults]]
type = "babbling_node"
at_s = 4.0
cob_id = 0x7E5
rate_hz = 1000
duration_s = 0.1
[[faults]]
type = "motor_failure"
at_s = 4.5
wheel = 6
)",
                               "faults.toml");
    Rig* rig = new Rig(s);
    rig->drive(2.0, 2.0);
    rig->runUntil(6 * core::kNsPerSec);
    // IMU silent in (1 s, 2 s]: the dropout starts after the 1.00 s step.
    std::size_t imuInDropout = 0;
    for (const CanFrame& f : rig->withId(0x6A0)) {
        imuInDropout += (f.timestamp > 1000 * kMs && f.timestamp <= 2000 * kMs) ? 1U : 0U;
    }
    LONGS_EQUAL(0, imuInDropout);
    LONGS_EQUAL(600 - 100, rig->withId(0x6A0).size());
    // Position fix crashed from 1 s to 3 s: no heartbeat, then a boot-up at 3.01 s.
    std::size_t fixHeartbeatsInCrash = 0;
    core::TimeNs reboot = 0;
    for (const CanFrame& f : rig->withId(0x723)) {
        fixHeartbeatsInCrash += (f.timestamp > 1000 * kMs && f.timestamp <= 3000 * kMs) ? 1U : 0U;
        if (f.data[0] == 0x00 && f.timestamp > 0) {
            reboot = f.timestamp;
        }
    }
    LONGS_EQUAL(0, fixHeartbeatsInCrash);
    CHECK_EQUAL(3010 * kMs, reboot);
    // Bus fault: three power-monitor heartbeats lost on the wire.
    LONGS_EQUAL(3, rig->wire.stats().faultDropped);
    LONGS_EQUAL(1 + 60 - 3, rig->withId(0x721).size());
    // Babbling node: 100 frames of 0x7E5.
    LONGS_EQUAL(100, rig->withId(0x7E5).size());
    LONGS_EQUAL(100, rig->sim.stats().babbleFrames);
    // Drive faults reach the drive owner with 0-based wheel indices.
    LONGS_EQUAL(2, rig->drives.record.log.size());
    STRCMP_EQUAL("0.000 degrade 1 2.00", rig->drives.record.log[0].c_str());
    STRCMP_EQUAL("0.000 fail 5", rig->drives.record.log[1].c_str());
    DOUBLES_EQUAL(2.0 * rig->wheels.w[0].currentA(), rig->wheels.w[1].currentA(), 1e-9);
    LONGS_EQUAL(0, rig->sim.stats().faultsUnhandled);
    delete rig;
}

TEST(SimRover, FaultsWithNothingToActOnAreCounted) {
    Scenario s = openGround();
    FaultSpec f;
    f.type = FaultType::kMotorFailure;
    f.at = core::kNsPerSec;
    s.faults.push_back(f);
    f.type = FaultType::kBusFault;
    s.faults.push_back(f);
    Rig* rig = new Rig(s, false);  // no drive owner, no in-memory bus hub
    rig->runUntil(2 * core::kNsPerSec);
    LONGS_EQUAL(2, rig->sim.stats().faultsUnhandled);
    LONGS_EQUAL(0, rig->sim.stats().faultsApplied);
    delete rig;
}

namespace {

// The ground link's owner as the simulator sees it: records each EXEC_SET_TASK
// it was asked to send, and may refuse (a task it does not know).
class FakeFlightTasks final : public FlightTaskCommander {
public:
    bool accept = true;
    std::vector<std::string> log;
    bool setFlightTaskEnabled(std::size_t row, const std::string& name, bool enabled) override {
        log.push_back((name.empty() ? "row " + std::to_string(row) : name) + (enabled ? " enabled" : " disabled"));
        return accept;
    }
};

Scenario withTaskStall(core::TimeNs until) {
    Scenario s = openGround();
    FaultSpec f;
    f.type = FaultType::kTaskStall;
    f.taskName = "habitual";
    f.at = core::kNsPerSec;
    f.until = until;
    s.faults.push_back(f);
    return s;
}

}  // namespace

// The simulator cannot stall a flight task: it asks the ground link's owner to
// disable the row at `at` and enable it at `until`; the drive owner never sees it.
TEST(SimRover, ATaskStallIsHandedToTheGroundLinkOwnerAsDisableThenEnable) {
    Rig* rig = new Rig(withTaskStall(2 * core::kNsPerSec));
    FakeFlightTasks ground;
    rig->sim.attachFlightTasks(&ground);
    rig->runUntil(1500 * core::kNsPerMs);
    LONGS_EQUAL(1, ground.log.size());
    STRCMP_EQUAL("habitual disabled", ground.log[0].c_str());
    rig->runUntil(3 * core::kNsPerSec);
    LONGS_EQUAL(2, ground.log.size());
    STRCMP_EQUAL("habitual enabled", ground.log[1].c_str());
    LONGS_EQUAL(2, rig->sim.stats().faultsApplied);
    LONGS_EQUAL(0, rig->sim.stats().faultsUnhandled);
    CHECK(rig->drives.record.log.empty());
    delete rig;
}

// With no ground link (rse-sim over CAN, a rig without a ground), or one that
// could not send the command, the stall is not applied: counted as unhandled
// (and written to stderr), never silently dropped.
TEST(SimRover, ATaskStallNobodyCanCommandIsCountedAsNotApplied) {
    Rig* rig = new Rig(withTaskStall(2 * core::kNsPerSec));
    rig->runUntil(3 * core::kNsPerSec);
    LONGS_EQUAL(2, rig->sim.stats().faultsUnhandled);
    LONGS_EQUAL(2, rig->sim.stats().taskStallsUnhandled);
    LONGS_EQUAL(0, rig->sim.stats().faultsApplied);
    delete rig;

    rig = new Rig(withTaskStall(kNever));
    FakeFlightTasks ground;
    ground.accept = false;
    rig->sim.attachFlightTasks(&ground);
    rig->runUntil(3 * core::kNsPerSec);
    LONGS_EQUAL(1, ground.log.size());
    LONGS_EQUAL(1, rig->sim.stats().taskStallsUnhandled);
    LONGS_EQUAL(0, rig->sim.stats().faultsApplied);
    delete rig;
}

TEST(SimRover, DemoMissionTheHazardDetectorSeesTheHiddenRockBeforeTheRoverHitsIt) {
    Rig* rig = new Rig(demo());
    rig->drive(5.0, 5.0);  // straight down the direct line, blind to the hidden rock
    double xAtFirstSighting = -1.0;
    double firstRange = -1.0;
    for (core::TimeNs t = 0; t <= 80 * core::kNsPerSec; t += kTick) {
        rig->frames.clear();
        rig->drive(5.0, 5.0);
        rig->tick(t);
        for (const CanFrame& f : rig->frames) {
            if (f.id == 0x6A2 && f.data[6] == 3 && firstRange < 0.0) {
                firstRange = hal::le::getI16(&f.data[0]) * 0.01;
                xAtFirstSighting = rig->sim.truth().pose.x;
            }
        }
    }
    const TruthRecord& truth = rig->sim.truth();
    CHECK(firstRange > 2.5 && firstRange <= 3.1);
    CHECK(xAtFirstSighting > 8.0 && xAtFirstSighting < 10.0);
    LONGS_EQUAL(1, truth.collisions);
    LONGS_EQUAL(3, truth.lastCollisionObstacle);
    CHECK_TRUE(truth.inContact);
    CHECK(truth.pose.x > 11.0 && truth.pose.x < 12.0);
    // The scheduled degradation (79 s, wheel 2) reached the drive owner; the failure (87 s) is later.
    LONGS_EQUAL(1, rig->drives.record.log.size());
    STRCMP_EQUAL("0.000 degrade 1 1.40", rig->drives.record.log[0].c_str());
    delete rig;
}

TEST(SimRover, StepsBackwardsInTimeAreIgnored) {
    Rig* rig = new Rig(openGround());
    rig->drive(5.0, 5.0);
    rig->runUntil(core::kNsPerSec);
    const double x = rig->sim.truth().pose.x;
    rig->sim.step(500 * kMs);
    DOUBLES_EQUAL(x, rig->sim.truth().pose.x, 0.0);
    CHECK_EQUAL(core::kNsPerSec, rig->sim.time());
    delete rig;
}

TEST(SimRover, APositionFixOutlierDisplacesExactlyCountFixesByTheOffset) {
    // Noise-free fixes of a rover standing at (0, 0): every fix is (0, 0) but the outliers.
    Scenario s = parseScenario(R"(
seed = 3
[map]
x_min_m = -20.0
x_max_m = 20.0
y_min_m = -20.0
y_max_m = 20.0
[start]
x_m = 0.0
y_m = 0.0
[devices.position_fix]
sigma_m = 0.0
heading_sigma_rad = 0.0
[[faults]]
type = "position_fix_outlier"
at_s = 2.5
offset_m = 10.0
count = 3
bearing_deg = 90
)",
                               "outlier.toml");
    Rig* rig = new Rig(s);
    rig->runUntil(10 * core::kNsPerSec);
    const std::vector<Fix> got = fixes(*rig);
    LONGS_EQUAL(10, got.size());  // 1 Hz from 1 s
    for (std::size_t i = 0; i < got.size(); ++i) {
        const bool outlier = got[i].counter >= 2 && got[i].counter <= 4;  // the fixes of 3, 4 and 5 s
        DOUBLES_EQUAL(0.0, got[i].x, 1e-9);
        DOUBLES_EQUAL(outlier ? 10.0 : 0.0, got[i].y, 1e-9);
    }
    LONGS_EQUAL(3, rig->sim.positionFix().outliersProduced());
    LONGS_EQUAL(0, rig->sim.positionFix().outliersPending());
    LONGS_EQUAL(1, rig->sim.stats().faultsApplied);
    LONGS_EQUAL(0, rig->sim.stats().faultsUnhandled);
    delete rig;
}

TEST(SimRover, AnOutlierComesOnTopOfTheNormalNoiseAndShiftsNoOtherFix) {
    // Two simulators with the same seed, one with an outlier injected directly:
    // the noise draws are the same, so the fixes differ by the offset exactly
    // where the outliers are and nowhere else.
    Scenario s = openGround(21);
    s.devices.positionFix.sigmaM = 0.5;
    Rig* a = new Rig(s);
    Rig* b = new Rig(s);
    a->runUntil(3200 * kMs);
    b->runUntil(3200 * kMs);
    const double bearing = 2.0;  // rad, map frame
    b->sim.positionFixOutlier(25.0, bearing, 2);  // the fixes of 4 s and 5 s
    LONGS_EQUAL(2, b->sim.positionFix().outliersPending());
    a->runUntil(8 * core::kNsPerSec);
    b->runUntil(8 * core::kNsPerSec);
    const std::vector<Fix> fa = fixes(*a);
    const std::vector<Fix> fb = fixes(*b);
    LONGS_EQUAL(8, fa.size());
    LONGS_EQUAL(8, fb.size());
    std::size_t displaced = 0;
    for (std::size_t i = 0; i < fa.size(); ++i) {
        const double dx = fb[i].x - fa[i].x;
        const double dy = fb[i].y - fa[i].y;
        CHECK(std::fabs(fa[i].x) > 1e-3 || std::fabs(fa[i].y) > 1e-3);  // the noise is on
        if (fb[i].counter == 3 || fb[i].counter == 4) {
            ++displaced;
            DOUBLES_EQUAL(25.0 * std::cos(bearing), dx, 0.0011);  // both sides rounded to 1 mm
            DOUBLES_EQUAL(25.0 * std::sin(bearing), dy, 0.0011);
        } else {
            DOUBLES_EQUAL(0.0, dx, 0.0);
            DOUBLES_EQUAL(0.0, dy, 0.0);
        }
    }
    LONGS_EQUAL(2, displaced);
    // The heading field is untouched (the same noise draw on both).
    const std::vector<CanFrame> ya = a->withId(0x6A4);
    const std::vector<CanFrame> yb = b->withId(0x6A4);
    for (std::size_t i = 0; i < ya.size(); ++i) {
        LONGS_EQUAL(hal::le::getI16(&ya[i].data[4]), hal::le::getI16(&yb[i].data[4]));
    }
    delete a;
    delete b;
}

TEST(SimRover, AnInvalidOutlierIsCountedAsUnhandled) {
    Rig* rig = new Rig(openGround());
    rig->tick(0);
    rig->sim.positionFixOutlier(0.0, 0.0, 1);
    rig->sim.positionFixOutlier(5.0, 0.0, 0);
    rig->sim.positionFixOutlier(NAN, 0.0, 1);
    rig->sim.positionFixOutlier(5.0, INFINITY, 1);
    LONGS_EQUAL(4, rig->sim.stats().faultsUnhandled);
    LONGS_EQUAL(0, rig->sim.stats().faultsApplied);
    LONGS_EQUAL(0, rig->sim.positionFix().outliersPending());
    rig->sim.positionFixOutlier(5.0, 0.0, 4);
    rig->sim.positionFixOutlier(5.0, 0.0, 2);  // replaces the pending one
    LONGS_EQUAL(2, rig->sim.positionFix().outliersPending());
    LONGS_EQUAL(2, rig->sim.stats().faultsApplied);
    delete rig;
}
