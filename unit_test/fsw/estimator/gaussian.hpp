// A seeded standard normal (and uniform) stream for the filter tests. Box-Muller
// on our own, so the stream is the same on every libstdc++ and architecture.
#pragma once

#include <cmath>
#include <cstdint>
#include <random>

namespace rse::test {

class Gaussian {
public:
    explicit Gaussian(std::uint64_t seed) : rng_(seed) {}
    double operator()() {
        const double u1 = (static_cast<double>(rng_() >> 11) + 0.5) * 0x1.0p-53;
        const double u2 = static_cast<double>(rng_() >> 11) * 0x1.0p-53;
        return std::sqrt(-2.0 * std::log(u1)) * std::cos(2.0 * M_PI * u2);
    }
    double uniform() { return static_cast<double>(rng_() >> 11) * 0x1.0p-53; }

private:
    std::mt19937_64 rng_;
};

}  // namespace rse::test
