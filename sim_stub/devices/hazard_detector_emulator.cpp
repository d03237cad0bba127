#include "sim_stub/devices/hazard_detector_emulator.hpp"

#include <cmath>

#include "hal/canopen/le_codec.hpp"

namespace rse::sim {

bool observeObstacle(const Pose2& pose, const Obstacle& obstacle, const HazardDetectorParams& params,
                     HazardView* view) {
    if (obstacle.shape.n < 3) {
        return false;
    }
    ClipPolygon body;
    for (std::size_t i = 0; i < obstacle.shape.n; ++i) {
        body.v[i] = toBodyFrame(pose, obstacle.shape.v[i]);
    }
    body.n = obstacle.shape.n;
    // The field of view is the wedge between the rays at -halfFov and +halfFov:
    // left of the right ray and right of the left ray (convex for halfFov <= 90 deg).
    const Vec2 origin{0.0, 0.0};
    const Vec2 rightRay{std::cos(params.halfFovRad), -std::sin(params.halfFovRad)};
    const Vec2 leftRayReversed{-std::cos(params.halfFovRad), -std::sin(params.halfFovRad)};
    ClipPolygon half;
    ClipPolygon seen;
    clipLeftOf(body, origin, rightRay, &half);
    clipLeftOf(half, origin, leftRayReversed, &seen);
    if (seen.n == 0) {
        return false;
    }
    ConvexPolygon part;
    part.n = seen.n < kMaxPolygonVertices ? seen.n : kMaxPolygonVertices;
    for (std::size_t i = 0; i < part.n; ++i) {
        part.v[i] = seen.v[i];
    }
    // The clipped part may have fewer than 3 distinct vertices (touching a ray):
    // take the nearest point over its edges directly.
    Vec2 nearest = seen.v[0];
    double best = norm(nearest);
    if (seen.n >= 3 && pointInPolygon(origin, part)) {
        nearest = origin;
        best = 0.0;
    } else {
        for (std::size_t i = 0; i < seen.n; ++i) {
            const Vec2 q = closestOnSegment(origin, seen.v[i], seen.v[(i + 1) % seen.n]);
            const double d = norm(q);
            if (d < best) {
                best = d;
                nearest = q;
            }
        }
    }
    if (best > params.rangeM) {
        return false;
    }
    const double bearing = best > 0.0 ? std::atan2(nearest.y, nearest.x) : 0.0;
    const Vec2 across{-std::sin(bearing), std::cos(bearing)};
    double lo = dot(across, seen.v[0]);
    double hi = lo;
    for (std::size_t i = 1; i < seen.n; ++i) {
        const double s = dot(across, seen.v[i]);
        lo = s < lo ? s : lo;
        hi = s > hi ? s : hi;
    }
    view->obstacleId = obstacle.id;
    view->rangeM = best;
    view->bearingRad = bearing;
    view->halfWidthM = 0.5 * (hi - lo);
    return true;
}

std::size_t observeTerrain(const Pose2& pose, const Terrain& terrain, const HazardDetectorParams& params,
                           HazardView* views, std::size_t max, std::vector<std::size_t>* scratch) {
    // Only an obstacle whose box comes within range can be seen (its nearest
    // point is farther): the index's list is every one a whole scan would see.
    std::vector<std::size_t> local;
    std::vector<std::size_t>* near = scratch != nullptr ? scratch : &local;
    terrain.near(Vec2{pose.x, pose.y}, params.rangeM, near);
    std::size_t count = 0;
    for (const std::size_t i : *near) {
        HazardView v;
        if (!terrain.obstacle(i).detectable || !observeObstacle(pose, terrain.obstacle(i), params, &v)) {
            continue;
        }
        // Insertion into the list sorted by range, keeping the nearest max.
        std::size_t at = count;
        while (at > 0 && views[at - 1].rangeM > v.rangeM) {
            --at;
        }
        if (at >= max) {
            continue;
        }
        const std::size_t last = count < max ? count : max - 1;
        for (std::size_t j = last; j > at; --j) {
            views[j] = views[j - 1];
        }
        views[at] = v;
        count = count < max ? count + 1 : max;
    }
    return count;
}

HazardDetectorEmulator::HazardDetectorEmulator(hal::CanBus& bus, const World& world,
                                               const HazardDetectorParams& params, std::uint64_t seed,
                                               bool pollsBus)
    : DeviceEmulator(bus, kHazardNodeId, pollsBus), world_(world), params_(params), rng_(seed, RngStream::kHazard) {
    near_.reserve(world.terrain().obstacleCount());   // look() allocates nothing
    for (std::size_t i = 0; i < world.terrain().obstacleCount(); ++i) {
        wideIds_ = wideIds_ || world.terrain().obstacle(i).id > 255;
    }
}

std::uint8_t HazardDetectorEmulator::trackOf(std::uint16_t obstacleId) {
    if (!wideIds_) {
        return static_cast<std::uint8_t>(obstacleId);
    }
    // Its own track, else a free one, else the one seen longest ago.
    std::size_t oldest = 0;
    for (std::size_t t = 1; t < 256; ++t) {
        if (trackObstacle_[t] == obstacleId) {
            trackSeen_[t] = looks_;
            return static_cast<std::uint8_t>(t);
        }
        const bool freeT = trackObstacle_[t] == 0;
        const bool freeOldest = oldest != 0 && trackObstacle_[oldest] == 0;
        if (oldest == 0 || (freeT && !freeOldest) || (freeT == freeOldest && trackSeen_[t] < trackSeen_[oldest])) {
            oldest = t;
        }
    }
    trackObstacle_[oldest] = obstacleId;
    trackSeen_[oldest] = looks_;
    return static_cast<std::uint8_t>(oldest);
}

void HazardDetectorEmulator::onBoot(core::TimeNs now, bool resetApplication) {
    if (resetApplication) {
        counter_ = 0;
    }
    sawSomething_ = false;
    nextClear_ = now;
    schedule_.start(now + kHazardPeriodNs, kHazardPeriodNs);
}

void HazardDetectorEmulator::produce(core::TimeNs now) {
    const std::size_t due = schedule_.take(now, 1, &mutableStats().samplesSkipped);
    if (due > 0) {
        look(now);  // a late look is one look: the world is sampled once
    }
}

void HazardDetectorEmulator::look(core::TimeNs now) {
    ++looks_;
    const std::size_t n =
        observeTerrain(world_.truth().pose, world_.terrain(), params_, views_, kMaxHazardReports, &near_);
    for (std::size_t i = 0; i < n; ++i) {
        const HazardView& v = views_[i];
        double range = v.rangeM + params_.rangeSigmaM * rng_.gaussian();
        range = range < 0.0 ? 0.0 : range;
        const double bearing = wrapAngle(v.bearingRad + params_.bearingSigmaRad * rng_.gaussian());
        report(trackOf(v.obstacleId), range, bearing, v.halfWidthM);
    }
    if (n > 0) {
        sawSomething_ = true;
        return;
    }
    if (sawSomething_ || now >= nextClear_) {
        report(0, 0.0, 0.0, 0.0);
        nextClear_ = now + kHazardClearPeriodNs;
    }
    sawSomething_ = false;
}

void HazardDetectorEmulator::report(std::uint8_t id, double rangeM, double bearingRad, double halfWidthM) {
    hal::CanFrame f;
    f.id = kHazardCobId;
    f.dlc = 8;
    hal::le::putI16(&f.data[0], saturateI16(rangeM * 100.0));
    hal::le::putI16(&f.data[2], saturateI16(bearingRad * 1000.0));
    hal::le::putI16(&f.data[4], saturateI16(halfWidthM * 100.0));
    f.data[6] = id;
    f.data[7] = counter_;
    counter_ = static_cast<std::uint8_t>(counter_ + 1);
    sendData(f);
}

}  // namespace rse::sim
