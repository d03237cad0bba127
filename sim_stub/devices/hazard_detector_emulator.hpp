// Hazard detector (node 0x22): obstacle reports on 0x6A2 (docs/icd.md §1.2, §1.6).
//
// It sees every obstacle, known or hidden, but not one marked undetectable
// (Obstacle::detectable false, a scenario's `detectable = false`), part of which lies inside its sensing
// sector: within rangeM of the rover centre and within +-halfFov of the heading.
// For each obstacle seen, over the part of it inside the field of view:
//   range     distance from the rover centre to the nearest point of that part;
//   bearing   direction of that nearest point, 0 ahead, + left (rover frame);
//   halfWidth half the extent of that part across the line of sight (its
//             projection on the axis perpendicular to the bearing).
// So (range, bearing) are the polar coordinates of the closest point and the
// obstacle blocks at least [bearing line +- halfWidth] beyond it.
// Range and bearing carry Gaussian noise (defaults sigma 2 cm and 10 mrad);
// defaults range 3 m, field of view +-60 deg.
//
// Every 200 ms (5 Hz) the detector looks and sends one report per obstacle in
// view, nearest first (at most kMaxHazardReports). When nothing is in view it
// sends a "clear" report (all fields 0, id 0) at once if something was in view
// at the previous look, and otherwise once a second (1 Hz). The report counter
// (byte 7) counts every report, clear ones included, and wraps at 256.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "sim_stub/devices/device_emulator.hpp"
#include "sim_stub/world/random.hpp"
#include "sim_stub/world/world.hpp"

namespace rse::sim {

constexpr std::uint8_t kHazardNodeId = 0x22;
constexpr std::uint32_t kHazardCobId = 0x6A2;
constexpr core::TimeNs kHazardPeriodNs = 200 * core::kNsPerMs;
constexpr core::TimeNs kHazardClearPeriodNs = core::kNsPerSec;
constexpr std::size_t kMaxHazardReports = 16;

struct HazardDetectorParams {
    double rangeM = 3.0;
    double halfFovRad = kPi / 3.0;  // (0, pi/2]
    double rangeSigmaM = 0.02;
    double bearingSigmaRad = 0.01;
};

struct HazardView {
    std::uint16_t obstacleId = 0;   // the world's obstacle id (the report carries the track number)
    double rangeM = 0.0;
    double bearingRad = 0.0;
    double halfWidthM = 0.0;
};

// Noise-free geometry of one obstacle as the detector at pose sees it; false when
// no part of it is within range and field of view.
bool observeObstacle(const Pose2& pose, const Obstacle& obstacle, const HazardDetectorParams& params,
                     HazardView* view);
// Every obstacle in view, nearest first, at most max of them (the nearest ones).
// scratch (may be null: then a vector of its own) holds the obstacles near
// the pose; reserved to the terrain's obstacle count, nothing is allocated.
std::size_t observeTerrain(const Pose2& pose, const Terrain& terrain, const HazardDetectorParams& params,
                           HazardView* views, std::size_t max, std::vector<std::size_t>* scratch = nullptr);

class HazardDetectorEmulator final : public DeviceEmulator {
public:
    HazardDetectorEmulator(hal::CanBus& bus, const World& world, const HazardDetectorParams& params,
                           std::uint64_t seed, bool pollsBus = true);

    std::uint8_t reportCounter() const { return counter_; }  // of the next report

private:
    void onBoot(core::TimeNs now, bool resetApplication) override;
    void produce(core::TimeNs now) override;
    void look(core::TimeNs now);
    void report(std::uint8_t id, double rangeM, double bearingRad, double halfWidthM);
    // The track number (1..255) the detector reports an obstacle by: its id
    // while every id of the world fits a byte (every scenario of a few rocks:
    // reports as before), else a number given at first sight and reused
    // least recently seen first, as a real detector's tracks are (the flight
    // side tells a reused number from its old rock by the jump, map_builder.hpp).
    std::uint8_t trackOf(std::uint16_t obstacleId);

    const World& world_;
    HazardDetectorParams params_;
    SimRng rng_;
    PeriodicSchedule schedule_;
    std::uint8_t counter_ = 0;
    bool sawSomething_ = false;
    core::TimeNs nextClear_ = 0;
    HazardView views_[kMaxHazardReports];
    std::vector<std::size_t> near_;        // observeTerrain's scratch, reserved at construction
    bool wideIds_ = false;                 // some obstacle id is above 255
    std::uint16_t trackObstacle_[256] = {};  // per track number: the obstacle it follows (0: free)
    std::uint64_t trackSeen_[256] = {};      // ... the look it was last reported in
    std::uint64_t looks_ = 0;
};

}  // namespace rse::sim
