// Measurement noise on what the drive reports (TPDO1, SDO 0x606C / 0x6078):
// statistics, independence from the physics, determinism, and the DriveBank /
// scenario wiring.
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>

#include "hal/can/memory_can_bus.hpp"
#include "sim_stub/drives/drive_bank.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "unit_test/sim_stub/drives/drive_test_rig.hpp"
#include "unit_test/support/alloc_guard.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using rse::test::DriveRig;
using rse::test::Tpdo;

namespace {

constexpr std::int32_t kTargetMradS = 1000;
constexpr double kSteadyCurrentMa = 750.0;  // no-load 150 + 2000 mA/N m x 0.3 N m
constexpr std::size_t kSamples = 4000;

sim::DriveEmulatorConfig noisy(double currentSigmaMa, double velocitySigmaMradS, std::uint64_t seed = 1,
                               std::size_t channel = 0) {
    sim::DriveEmulatorConfig c;
    c.currentSigmaMa = currentSigmaMa;
    c.velocitySigmaMradS = velocitySigmaMradS;
    c.noiseSeed = seed;
    c.noiseChannel = channel;
    return c;
}

// Enabled, driving at kTargetMradS and settled (the acceleration term is gone).
void settle(DriveRig& rig) {
    rig.enable();
    for (int i = 0; i < 300; ++i) {
        (void)rig.cycle(0x000F, kTargetMradS);
    }
}

struct Moments {
    double mean = 0.0;
    double sigma = 0.0;
};

template <typename T>
Moments moments(const T* v, std::size_t n) {
    double sum = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        sum += static_cast<double>(v[i]);
    }
    Moments m;
    m.mean = sum / static_cast<double>(n);
    double sq = 0.0;
    for (std::size_t i = 0; i < n; ++i) {
        const double d = static_cast<double>(v[i]) - m.mean;
        sq += d * d;
    }
    m.sigma = std::sqrt(sq / static_cast<double>(n - 1));
    return m;
}

// kSamples TPDO1s at steady speed.
struct Reports {
    std::int16_t current[kSamples] = {};
    std::int32_t velocity[kSamples] = {};
    bool allPresent = true;
    bool physicsNoiseFree = true;  // currentMa() and the wheel speed never moved
};

void collect(DriveRig& rig, Reports* r) {
    for (std::size_t i = 0; i < kSamples; ++i) {
        const Tpdo t = rig.cycle(0x000F, kTargetMradS);
        r->allPresent = r->allPresent && t.present;
        r->current[i] = t.current;
        r->velocity[i] = t.velocity;
        r->physicsNoiseFree = r->physicsNoiseFree && std::fabs(rig.drive.currentMa() - kSteadyCurrentMa) < 1e-6 &&
                              std::fabs(rig.drive.wheelSpeedRadS() - 1.0) < 1e-6;
    }
}

bool sameCurrents(const Reports& a, const Reports& b) {
    for (std::size_t i = 0; i < kSamples; ++i) {
        if (a.current[i] != b.current[i]) {
            return false;
        }
    }
    return true;
}

}  // namespace

TEST_GROUP(DriveNoise) {
    DriveRig* a = nullptr;
    DriveRig* b = nullptr;
    Reports* ra = nullptr;
    Reports* rb = nullptr;
    void setup() override {
        ra = new Reports;
        rb = new Reports;
    }
    void teardown() override {
        delete a;
        delete b;
        delete ra;
        delete rb;
    }
};

TEST(DriveNoise, ByDefaultTheReportsAreTheExactModelValues) {
    a = new DriveRig();
    DOUBLES_EQUAL(0.0, a->drive.config().currentSigmaMa, 0.0);
    DOUBLES_EQUAL(0.0, a->drive.config().velocitySigmaMradS, 0.0);
    settle(*a);
    collect(*a, ra);
    CHECK_TRUE(ra->allPresent);
    CHECK_TRUE(ra->physicsNoiseFree);
    for (std::size_t i = 0; i < kSamples; ++i) {
        if (ra->current[i] != 750 || ra->velocity[i] != kTargetMradS) {
            FAIL("a noise-free drive reported a value off the model");
        }
    }
    LONGS_EQUAL(750, a->drive.lastReportedCurrentMa());
    LONGS_EQUAL(750, static_cast<std::int16_t>(a->uploadValue(0x6078, 0)));
    LONGS_EQUAL(kTargetMradS, static_cast<std::int32_t>(a->uploadValue(0x606C, 0)));
}

TEST(DriveNoise, TheReportedCurrentHasTheConfiguredSigmaAndThePhysicsStaysClean) {
    const double sigma = 20.0;  // mA (0.02 A)
    a = new DriveRig(noisy(sigma, 0.0));
    settle(*a);
    collect(*a, ra);
    CHECK_TRUE(ra->allPresent);
    CHECK_TRUE(ra->physicsNoiseFree);
    const Moments m = moments(ra->current, kSamples);
    // Standard error of the mean 20/sqrt(4000) = 0.32 mA; of sigma about 0.22 mA.
    DOUBLES_EQUAL(kSteadyCurrentMa, m.mean, 1.5);
    DOUBLES_EQUAL(sigma, m.sigma, 1.0);
    std::size_t beyond2Sigma = 0;
    for (std::int16_t c : ra->current) {
        beyond2Sigma += std::fabs(c - kSteadyCurrentMa) > 2.0 * sigma ? 1U : 0U;
    }
    CHECK(beyond2Sigma > 120 && beyond2Sigma < 250);  // Gaussian: 4.6 % of 4000 = 182
    for (std::int32_t v : ra->velocity) {
        if (v != kTargetMradS) {
            FAIL("current noise leaked into the velocity");
        }
    }
    // Statusword bits come from the clean model: target reached all along.
    CHECK((a->drive.statusword() & 0x0400) != 0);
}

TEST(DriveNoise, EverySdoUploadIsANewDraw) {
    a = new DriveRig(noisy(20.0, 5.0));
    settle(*a);
    a->drain();
    constexpr std::size_t kUploads = 1000;
    std::int16_t currents[kUploads] = {};
    std::int32_t velocities[kUploads] = {};
    for (std::size_t i = 0; i < kUploads; ++i) {
        currents[i] = static_cast<std::int16_t>(a->uploadValue(0x6078, 0));
        LONGS_EQUAL(currents[i], a->drive.lastReportedCurrentMa());
        velocities[i] = static_cast<std::int32_t>(a->uploadValue(0x606C, 0));
        LONGS_EQUAL(velocities[i], a->drive.lastReportedVelocityMradS());
    }
    const Moments c = moments(currents, kUploads);
    const Moments v = moments(velocities, kUploads);
    DOUBLES_EQUAL(kSteadyCurrentMa, c.mean, 3.0);
    DOUBLES_EQUAL(20.0, c.sigma, 2.0);
    DOUBLES_EQUAL(kTargetMradS, v.mean, 1.0);
    DOUBLES_EQUAL(5.0, v.sigma, 0.6);
    LONGS_EQUAL(750, a->drive.currentActualMa());  // the noise-free accessor
    LONGS_EQUAL(kTargetMradS, a->drive.velocityActualMradS());
}

TEST(DriveNoise, TheReportedVelocityHasTheConfiguredSigma) {
    a = new DriveRig(noisy(0.0, 8.0));
    settle(*a);
    collect(*a, ra);
    CHECK_TRUE(ra->physicsNoiseFree);
    const Moments v = moments(ra->velocity, kSamples);
    DOUBLES_EQUAL(kTargetMradS, v.mean, 0.6);
    DOUBLES_EQUAL(8.0, v.sigma, 0.4);
    for (std::int16_t c : ra->current) {
        if (c != 750) {
            FAIL("velocity noise leaked into the current");
        }
    }
}

TEST(DriveNoise, TheSameSeedAndChannelGiveTheSameReports) {
    a = new DriveRig(noisy(20.0, 5.0, 42, 3));
    b = new DriveRig(noisy(20.0, 5.0, 42, 3));
    settle(*a);
    settle(*b);
    collect(*a, ra);
    collect(*b, rb);
    CHECK_TRUE(sameCurrents(*ra, *rb));
    for (std::size_t i = 0; i < kSamples; ++i) {
        LONGS_EQUAL(ra->velocity[i], rb->velocity[i]);
    }
}

TEST(DriveNoise, AnotherSeedOrAnotherDriveGivesOtherNoise) {
    a = new DriveRig(noisy(20.0, 0.0, 42, 3));
    b = new DriveRig(noisy(20.0, 0.0, 43, 3));
    settle(*a);
    settle(*b);
    collect(*a, ra);
    collect(*b, rb);
    CHECK_FALSE(sameCurrents(*ra, *rb));
    delete b;
    b = new DriveRig(noisy(20.0, 0.0, 42, 4));
    settle(*b);
    collect(*b, rb);
    CHECK_FALSE(sameCurrents(*ra, *rb));
}

TEST(DriveNoise, VelocityNoiseDoesNotShiftTheCurrentStream) {
    a = new DriveRig(noisy(20.0, 0.0, 7, 1));
    b = new DriveRig(noisy(20.0, 5.0, 7, 1));
    settle(*a);
    settle(*b);
    collect(*a, ra);
    collect(*b, rb);
    CHECK_TRUE(sameCurrents(*ra, *rb));
}

TEST(DriveNoise, SetMeasurementNoiseIsLikeConstructingWithIt) {
    a = new DriveRig(noisy(20.0, 0.0, 9, 2));
    b = new DriveRig();
    b->drive.setMeasurementNoise(20.0, 0.0, 9, 2);
    DOUBLES_EQUAL(20.0, b->drive.config().currentSigmaMa, 0.0);
    LONGS_EQUAL(9, b->drive.config().noiseSeed);
    LONGS_EQUAL(2, b->drive.config().noiseChannel);
    settle(*a);
    settle(*b);
    collect(*a, ra);
    collect(*b, rb);
    CHECK_TRUE(sameCurrents(*ra, *rb));
    b->drive.setMeasurementNoise(-1.0, NAN, 9, 2);  // invalid sigmas: off
    DOUBLES_EQUAL(0.0, b->drive.config().currentSigmaMa, 0.0);
    DOUBLES_EQUAL(0.0, b->drive.config().velocitySigmaMradS, 0.0);
    const Tpdo t = b->cycle(0x000F, kTargetMradS);
    LONGS_EQUAL(750, t.current);
}

TEST(DriveNoise, NoisyReportsAllocateNothing) {
    a = new DriveRig(noisy(20.0, 5.0));
    settle(*a);
    std::uint64_t allocations = 0;
    {
        test::AllocationWatch watch;
        collect(*a, ra);
        (void)a->uploadValue(0x6078, 0);
        (void)a->uploadValue(0x606C, 0);
        allocations = watch.count();
    }
    LONGS_EQUAL(0, allocations);
    CHECK_TRUE(ra->allPresent);
}

TEST_GROUP(DriveBankNoise) {
    core::VirtualClock clock;
    hal::MemoryCanBus* wire = nullptr;
    std::array<hal::CanBus*, sim::kWheelCount> buses{};
    void setup() override {
        wire = new hal::MemoryCanBus(clock);
        for (hal::CanBus*& b : buses) {
            b = wire->attach("drive");
        }
    }
    void teardown() override { delete wire; }
};

TEST(DriveBankNoise, BuiltFromAScenarioEveryDriveGetsTheNoiseTheSeedAndItsOwnChannel) {
    sim::Scenario s;
    s.seed = 77;
    s.drives.currentSigmaA = 0.02;
    s.drives.velocitySigmaRadS = 0.004;
    s.rover.driveNodes = {{11, 12, 13, 14, 15, 16}};
    sim::DriveBank* bank = new sim::DriveBank(buses, s);
    for (std::size_t w = 0; w < sim::kWheelCount; ++w) {
        const sim::DriveEmulatorConfig& c = bank->drive(w).config();
        DOUBLES_EQUAL(20.0, c.currentSigmaMa, 1e-12);
        DOUBLES_EQUAL(4.0, c.velocitySigmaMradS, 1e-12);
        LONGS_EQUAL(77, c.noiseSeed);
        LONGS_EQUAL(w, c.noiseChannel);
        LONGS_EQUAL(11 + w, bank->drive(w).nodeId());
    }
    delete bank;
}

TEST(DriveBankNoise, TheDefaultScenarioAndTheNodeIdConstructorAreNoiseFree) {
    const sim::Scenario s;
    DOUBLES_EQUAL(0.0, s.drives.currentSigmaA, 0.0);
    DOUBLES_EQUAL(0.0, s.drives.velocitySigmaRadS, 0.0);
    const sim::DriveEmulatorConfig c = sim::DriveBank::configFor(s);
    DOUBLES_EQUAL(0.0, c.currentSigmaMa, 0.0);
    DOUBLES_EQUAL(0.0, c.velocitySigmaMradS, 0.0);
    sim::DriveBank* bank = new sim::DriveBank(buses, s.rover.driveNodes);
    for (std::size_t w = 0; w < sim::kWheelCount; ++w) {
        DOUBLES_EQUAL(0.0, bank->drive(w).config().currentSigmaMa, 0.0);
        LONGS_EQUAL(w, bank->drive(w).config().noiseChannel);
    }
    bank->setMeasurementNoise(sim::DriveNoiseParams{0.03, 0.0}, 5);
    for (std::size_t w = 0; w < sim::kWheelCount; ++w) {
        DOUBLES_EQUAL(30.0, bank->drive(w).config().currentSigmaMa, 1e-12);
        LONGS_EQUAL(5, bank->drive(w).config().noiseSeed);
        LONGS_EQUAL(w, bank->drive(w).config().noiseChannel);
    }
    delete bank;
}
