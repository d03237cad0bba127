// Deterministic pseudo-random numbers for the simulator's noise models.
//
// xoshiro256** seeded through splitmix64 from (scenario seed, stream id), so each
// noise source (wheel slip, IMU, power monitor, hazard detector, position fix,
// each drive's reported current and velocity, and each science instrument's
// work durations) has its own stream: adding samples to one never shifts another, and the same
// seed gives the same numbers on every run and every compiler (no dependence on
// the standard library's distributions). Gaussian samples by Box-Muller.
#pragma once

#include <cmath>
#include <cstddef>
#include <cstdint>

namespace rse::sim {

// Stream ids: one per noise source. Each wheel drive (0..5, wheel order) has one
// stream for the current actual and one for the velocity actual it reports.
enum class RngStream : std::uint64_t {
    kWheelSlip = 1,
    kImu = 2,
    kPower = 3,
    kHazard = 4,
    kPositionFix = 5,
    kDriveCurrent0 = 6,  // .. kDriveCurrent0 + 5
    kDriveVelocity0 = 12,  // .. kDriveVelocity0 + 5
    kGrinder = 18,         // the grinder/sampler's work durations
    kCamera = 19,          // the camera's
    kRockField = 20,       // a generated rock field (sim_stub/scenario/rock_field.hpp)
};
constexpr std::size_t kDriveNoiseStreams = 6;

// The streams of drive `channel` (0..5; larger values wrap, so every drive has one).
constexpr RngStream driveCurrentStream(std::size_t channel) {
    return static_cast<RngStream>(static_cast<std::uint64_t>(RngStream::kDriveCurrent0) +
                                  channel % kDriveNoiseStreams);
}
constexpr RngStream driveVelocityStream(std::size_t channel) {
    return static_cast<RngStream>(static_cast<std::uint64_t>(RngStream::kDriveVelocity0) +
                                  channel % kDriveNoiseStreams);
}

class SimRng {
public:
    SimRng(std::uint64_t seed, RngStream stream) {
        std::uint64_t x = seed ^ (0x9E3779B97F4A7C15ULL * static_cast<std::uint64_t>(stream));
        for (std::uint64_t& s : s_) {
            s = splitmix64(&x);
        }
    }

    std::uint64_t next() {
        const std::uint64_t result = rotl(s_[1] * 5, 7) * 9;
        const std::uint64_t t = s_[1] << 17;
        s_[2] ^= s_[0];
        s_[3] ^= s_[1];
        s_[1] ^= s_[2];
        s_[0] ^= s_[3];
        s_[2] ^= t;
        s_[3] = rotl(s_[3], 45);
        return result;
    }

    // Uniform in (0, 1): 53 random bits, never exactly 0.
    double uniform() { return (static_cast<double>(next() >> 11) + 0.5) * (1.0 / 9007199254740992.0); }

    // Standard normal (mean 0, sigma 1).
    double gaussian() {
        if (haveSpare_) {
            haveSpare_ = false;
            return spare_;
        }
        const double u1 = uniform();
        const double u2 = uniform();
        const double r = std::sqrt(-2.0 * std::log(u1));
        const double a = 2.0 * 3.14159265358979323846 * u2;
        spare_ = r * std::sin(a);
        haveSpare_ = true;
        return r * std::cos(a);
    }

private:
    static std::uint64_t rotl(std::uint64_t x, int k) { return (x << k) | (x >> (64 - k)); }
    static std::uint64_t splitmix64(std::uint64_t* x) {
        std::uint64_t z = (*x += 0x9E3779B97F4A7C15ULL);
        z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
        z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
        return z ^ (z >> 31);
    }

    std::uint64_t s_[4] = {};
    double spare_ = 0.0;
    bool haveSpare_ = false;
};

}  // namespace rse::sim
