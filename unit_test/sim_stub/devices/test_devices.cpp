#include <cmath>
#include <cstdint>
#include <vector>

#include "hal/canopen/le_codec.hpp"
#include "hal/devices/imu.hpp"
#include "hal/devices/position_fix.hpp"
#include "hal/devices/power_monitor.hpp"
#include "sim_stub/devices/imu_emulator.hpp"
#include "sim_stub/devices/position_fix_emulator.hpp"
#include "sim_stub/devices/power_monitor_emulator.hpp"
#include "unit_test/sim_stub/sim_test_support.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::sim;
using hal::CanFrame;
using rse::test::countId;
using rse::test::nmt;

namespace {
constexpr core::TimeNs kMs = core::kNsPerMs;
}

struct SimDevicesBench : public Utest, public test::DeviceBench {};

TEST_GROUP_BASE(SimDevices, SimDevicesBench) {
    void setup() override { open(Pose2{1.5, -2.0, 0.7}); }
    void teardown() override { close(); }
    void send(const CanFrame& f) { CHECK(core::Status::kOk == flight->send(f)); }
};

TEST(SimDevices, ImuBootsSendsHeartbeatsAndHundredSamplesASecond) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, core::kNsPerSec);
    // Boot-up first, at power-on.
    CHECK(!frames.empty());
    LONGS_EQUAL(0x720, frames[0].id);
    LONGS_EQUAL(1, frames[0].dlc);
    LONGS_EQUAL(0x00, frames[0].data[0]);
    LONGS_EQUAL(0, frames[0].timestamp);
    const std::vector<CanFrame> hb = withId(0x720);
    LONGS_EQUAL(11, hb.size());  // boot-up + 10 heartbeats
    for (std::size_t i = 1; i < hb.size(); ++i) {
        LONGS_EQUAL(1, hb[i].dlc);
        LONGS_EQUAL(0x7F, hb[i].data[0]);  // pre-operational
        CHECK_EQUAL(static_cast<core::TimeNs>(i) * 100 * kMs, hb[i].timestamp);
    }
    const std::vector<CanFrame> samples = withId(0x6A0);
    LONGS_EQUAL(100, samples.size());
    for (std::size_t i = 0; i < samples.size(); ++i) {
        LONGS_EQUAL(8, samples[i].dlc);
        LONGS_EQUAL(i, hal::le::getU16(&samples[i].data[4]));
        LONGS_EQUAL(0x01, samples[i].data[6] & 0x01);
        LONGS_EQUAL(0, samples[i].data[7]);
        CHECK_EQUAL(static_cast<core::TimeNs>(i + 1) * 10 * kMs, samples[i].timestamp);
    }
    LONGS_EQUAL(frames.size(), 111);
    LONGS_EQUAL(100, imu.stats().dataFrames);
    LONGS_EQUAL(10, imu.stats().heartbeats);
    LONGS_EQUAL(1, imu.stats().bootUps);
}

TEST(SimDevices, ImuMeanYawRateMatchesTruthPlusBiasWithinTheNoise) {
    speeds = test::sides(-2.0, 2.0);  // turning on the spot at 0.444 rad/s
    ImuParams params;
    params.noiseSigmaRadS = 0.002;
    params.biasRadS = 0.01;
    ImuEmulator imu(*simPort, *world, params, 42);
    runUntil(imu, core::kNsPerSec);
    const double truth = world->truth().yawRateRadS;
    DOUBLES_EQUAL(0.4444444, truth, 1e-6);
    const std::vector<CanFrame> samples = withId(0x6A0);
    LONGS_EQUAL(100, samples.size());
    double sum = 0.0;
    double sumSq = 0.0;
    for (const CanFrame& f : samples) {
        const double rate = hal::le::getI32(&f.data[0]) * 1e-6;
        sum += rate;
        sumSq += rate * rate;
    }
    const double n = static_cast<double>(samples.size());
    const double mean = sum / n;
    const double sd = std::sqrt(sumSq / n - mean * mean);
    DOUBLES_EQUAL(truth + params.biasRadS, mean, 3.0 * params.noiseSigmaRadS / std::sqrt(n));
    CHECK(sd > 0.5 * params.noiseSigmaRadS && sd < 1.5 * params.noiseSigmaRadS);
}

TEST(SimDevices, ImuBiasStepShowsInTheSamples) {
    ImuParams params;
    params.noiseSigmaRadS = 0.001;
    ImuEmulator imu(*simPort, *world, params, 3);
    runUntil(imu, core::kNsPerSec);
    clear();
    imu.stepBias(0.05);
    DOUBLES_EQUAL(0.05, imu.biasRadS(), 0.0);
    runUntil(imu, 2 * core::kNsPerSec);
    double sum = 0.0;
    const std::vector<CanFrame> samples = withId(0x6A0);
    for (const CanFrame& f : samples) {
        sum += hal::le::getI32(&f.data[0]) * 1e-6;
    }
    DOUBLES_EQUAL(0.05, sum / static_cast<double>(samples.size()), 3.0 * 0.001 / 10.0);
}

TEST(SimDevices, PowerMonitorSendsTenSamplesASecondMatchingTheBattery) {
    speeds = test::sides(5.0, 5.0);
    PowerMonitorParams params;
    PowerMonitorEmulator power(*simPort, *world, params, 9);
    runUntil(power, core::kNsPerSec);
    LONGS_EQUAL(11, countId(frames, 0x721));
    std::size_t samples = 0;
    for (std::size_t i = 0; i < frames.size(); ++i) {
        const CanFrame& f = frames[i];
        if (f.id != 0x6A1) {
            continue;
        }
        ++samples;
        LONGS_EQUAL(8, f.dlc);
        const TruthRecord& truth = truthAtFrame[i];
        DOUBLES_EQUAL(truth.busVoltageV, hal::le::getU16(&f.data[0]) * 1e-3, 4.0 * params.voltageSigmaV + 1e-3);
        DOUBLES_EQUAL(truth.busCurrentA, hal::le::getI16(&f.data[2]) * 1e-3, 4.0 * params.currentSigmaA + 1e-3);
        DOUBLES_EQUAL(truth.stateOfCharge, hal::le::getU16(&f.data[4]) * 1e-4, 0.6e-4);
        DOUBLES_EQUAL(truth.solarCurrentA, hal::le::getU16(&f.data[6]) * 1e-3, 0.6e-3);
    }
    LONGS_EQUAL(10, samples);
}

TEST(SimDevices, PositionFixSendsXThenYWithTheSameCounterOnceASecond) {
    PositionFixParams params;
    params.sigmaM = 0.05;
    params.headingSigmaRad = 0.005;
    PositionFixEmulator fix(*simPort, *world, params, 5);
    runUntil(fix, 100 * core::kNsPerSec);
    LONGS_EQUAL(100, countId(frames, 0x6A3));
    LONGS_EQUAL(100, countId(frames, 0x6A4));
    double sumX = 0.0, sumY = 0.0, sumH = 0.0;
    std::uint16_t expected = 0;
    for (std::size_t i = 0; i + 1 < frames.size(); ++i) {
        const CanFrame& fx = frames[i];
        if (fx.id != 0x6A3) {
            continue;
        }
        const CanFrame& fy = frames[i + 1];
        LONGS_EQUAL(0x6A4, fy.id);  // right after
        LONGS_EQUAL(8, fx.dlc);
        LONGS_EQUAL(8, fy.dlc);
        LONGS_EQUAL(expected, hal::le::getU16(&fx.data[6]));
        LONGS_EQUAL(expected, hal::le::getU16(&fy.data[6]));
        LONGS_EQUAL(50, hal::le::getU16(&fx.data[4]));  // sigma in mm
        const double x = hal::le::getI32(&fx.data[0]) * 1e-3;
        const double y = hal::le::getI32(&fy.data[0]) * 1e-3;
        const double h = hal::le::getI16(&fy.data[4]) * 1e-4;
        DOUBLES_EQUAL(1.5, x, 5.0 * params.sigmaM);
        DOUBLES_EQUAL(-2.0, y, 5.0 * params.sigmaM);
        sumX += x;
        sumY += y;
        sumH += h;
        ++expected;
    }
    DOUBLES_EQUAL(1.5, sumX / 100.0, 3.0 * params.sigmaM / 10.0);
    DOUBLES_EQUAL(-2.0, sumY / 100.0, 3.0 * params.sigmaM / 10.0);
    DOUBLES_EQUAL(0.7, sumH / 100.0, 3.0 * params.headingSigmaRad / 10.0 + 1e-4);
}

TEST(SimDevices, NmtStopLeavesOnlyHeartbeatsAndStartResumesData) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, 200 * kMs);
    send(nmt(0x01, 0x20));  // start
    runUntil(imu, 400 * kMs);
    CHECK(hal::canopen::NmtState::kOperational == imu.nmtState());
    LONGS_EQUAL(0x05, withId(0x720).back().data[0]);
    send(nmt(0x02, 0));  // stop all
    clear();
    runUntil(imu, 1400 * kMs);
    LONGS_EQUAL(0, countId(frames, 0x6A0));
    LONGS_EQUAL(10, countId(frames, 0x720));
    LONGS_EQUAL(0x04, withId(0x720).back().data[0]);
    send(nmt(0x01, 0x20));
    clear();
    runUntil(imu, 1500 * kMs);
    LONGS_EQUAL(10, countId(frames, 0x6A0));
    LONGS_EQUAL(3, imu.stats().nmtCommands);
}

TEST(SimDevices, NmtResetNodeRebootsAndRestartsTheCounters) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, 500 * kMs);
    send(nmt(0x81, 0x21));  // another node: ignored
    clear();
    runUntil(imu, 600 * kMs);
    LONGS_EQUAL(1, countId(frames, 0x720));  // just the heartbeat at 600 ms
    LONGS_EQUAL(0x7F, withId(0x720)[0].data[0]);
    send(nmt(0x81, 0x20));  // reset node
    clear();
    runUntil(imu, 800 * kMs);
    const std::vector<CanFrame> hb = withId(0x720);
    LONGS_EQUAL(2, hb.size());  // boot-up at 601 ms (first step after the command), heartbeat at 701 ms
    LONGS_EQUAL(0x00, hb[0].data[0]);
    CHECK_EQUAL(601 * kMs, hb[0].timestamp);
    CHECK_EQUAL(701 * kMs, hb[1].timestamp);
    LONGS_EQUAL(0x7F, hb[1].data[0]);
    const std::vector<CanFrame> samples = withId(0x6A0);
    CHECK(!samples.empty());
    LONGS_EQUAL(0, hal::le::getU16(&samples[0].data[4]));  // counter restarted
    CHECK_EQUAL(611 * kMs, samples[0].timestamp);
    LONGS_EQUAL(2, imu.stats().bootUps);
}

TEST(SimDevices, NmtResetToAllNodesAndResetCommunication) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, 300 * kMs);
    send(nmt(0x82, 0));  // reset communication, all nodes
    clear();
    runUntil(imu, 500 * kMs);
    const std::vector<CanFrame> hb = withId(0x720);
    LONGS_EQUAL(0x00, hb[0].data[0]);
    const std::vector<CanFrame> samples = withId(0x6A0);
    LONGS_EQUAL(30, hal::le::getU16(&samples[0].data[4]));  // counter kept across a communication reset
    send(nmt(0x81, 0));  // reset node, all nodes
    clear();
    runUntil(imu, 700 * kMs);
    LONGS_EQUAL(0x00, withId(0x720)[0].data[0]);
    LONGS_EQUAL(0, hal::le::getU16(&withId(0x6A0)[0].data[4]));
    LONGS_EQUAL(3, imu.stats().bootUps);
}

TEST(SimDevices, MalformedNmtIsIgnored) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, 100 * kMs);
    CanFrame shortNmt = nmt(0x02, 0x20);
    shortNmt.dlc = 1;
    send(shortNmt);
    send(nmt(0x55, 0x20));  // unknown command
    runUntil(imu, 300 * kMs);
    CHECK(hal::canopen::NmtState::kPreOperational == imu.nmtState());
    LONGS_EQUAL(1, imu.stats().nmtCommands);  // the unknown command was addressed to it
}

TEST(SimDevices, DropoutSilencesDataButNotTheHeartbeatAndTheCounterShowsTheGap) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    runUntil(imu, 1000 * kMs);
    imu.setDropout(true);
    clear();
    runUntil(imu, 2000 * kMs);
    LONGS_EQUAL(0, countId(frames, 0x6A0));
    LONGS_EQUAL(10, countId(frames, 0x720));
    LONGS_EQUAL(100, imu.stats().suppressed);
    imu.setDropout(false);
    clear();
    runUntil(imu, 2100 * kMs);
    const std::vector<CanFrame> samples = withId(0x6A0);
    LONGS_EQUAL(10, samples.size());
    LONGS_EQUAL(200, hal::le::getU16(&samples[0].data[4]));
}

TEST(SimDevices, CrashSilencesEverythingAndRestartBootsAgain) {
    PowerMonitorEmulator power(*simPort, *world, PowerMonitorParams{}, 1);
    runUntil(power, 500 * kMs);
    power.crash();
    CHECK_TRUE(power.crashed());
    clear();
    send(nmt(0x81, 0));  // a crashed node does not hear NMT
    runUntil(power, 1500 * kMs);
    CHECK(frames.empty());
    power.restart();
    clear();
    runUntil(power, 2501 * kMs);
    LONGS_EQUAL(0x721, frames[0].id);
    LONGS_EQUAL(0x00, frames[0].data[0]);
    CHECK_EQUAL(1501 * kMs, frames[0].timestamp);
    LONGS_EQUAL(10, countId(frames, 0x6A1));
    LONGS_EQUAL(11, countId(frames, 0x721));
    CHECK_FALSE(power.crashed());
}

TEST(SimDevices, LongStepsCatchUpBoundedAndCountSkippedSamples) {
    ImuEmulator imu(*simPort, *world, ImuParams{}, 1);
    imu.step(0);
    clock.sleepUntil(50 * kMs);
    imu.step(50 * kMs);  // 5 samples due
    LONGS_EQUAL(5, imu.stats().dataFrames);
    clock.sleepUntil(1050 * kMs);
    imu.step(1050 * kMs);  // 100 due: 16 sent, the rest skipped
    LONGS_EQUAL(5 + kDeviceMaxCatchUp, imu.stats().dataFrames);
    LONGS_EQUAL(100 - kDeviceMaxCatchUp, imu.stats().samplesSkipped);
}

TEST(SimDevices, FlightClientsAcceptEveryEmulatorFrame) {
    core::EventLog events{clock};
    hal::Imu imuClient(events);
    hal::PowerMonitor powerClient(events);
    hal::PositionFixSource fixClient(events);
    speeds = test::sides(3.0, 4.0);
    ImuEmulator imu(*simPort, *world, ImuParams{}, 11);
    PowerMonitorEmulator power(*simPort, *world, PowerMonitorParams{}, 11);
    PositionFixEmulator fix(*simPort, *world, PositionFixParams{}, 11);
    for (; t <= 5 * core::kNsPerSec; t += kMs) {
        clock.sleepUntil(t);
        world->advance(t, speeds, WheelArray{});
        imu.step(t);
        power.step(t);
        fix.step(t);
        CanFrame f;
        while (core::isOk(flight->receive(&f))) {
            if (f.id == 0x6A0) {
                imuClient.onFrame(f, t);
            } else if (f.id == 0x6A1) {
                powerClient.onFrame(f, t);
            } else if (f.id == 0x6A3 || f.id == 0x6A4) {
                fixClient.onFrame(f, t);
            }
        }
    }
    LONGS_EQUAL(500, imuClient.frameStats().accepted);
    LONGS_EQUAL(50, powerClient.frameStats().accepted);
    LONGS_EQUAL(10, fixClient.frameStats().accepted);
    LONGS_EQUAL(5, fixClient.latest().count);
    LONGS_EQUAL(0, fixClient.unpaired());
    for (const hal::DeviceFrameStats* s : {&imuClient.frameStats(), &powerClient.frameStats(), &fixClient.frameStats()}) {
        LONGS_EQUAL(0, s->badLength);
        LONGS_EQUAL(0, s->badValue);
        LONGS_EQUAL(0, s->gaps);
    }
    DOUBLES_EQUAL(world->truth().yawRateRadS, imuClient.latest().yawRateRadS, 0.01);
    DOUBLES_EQUAL(world->truth().pose.x, fixClient.latest().xM, 0.3);
    DOUBLES_EQUAL(world->truth().stateOfCharge, powerClient.latest().stateOfCharge, 1e-3);
}
