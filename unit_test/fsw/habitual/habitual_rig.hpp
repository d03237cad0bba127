// Test-only: the habitual task on a real software bus with the default tables,
// driven one 10 Hz run at a time. The rig stands in for everything around it:
// the estimator (ten PoseEstimateMsg per run from a synthetic pose), a perfect
// follower (the pose moves along the latest trajectory at its speed, stops at
// once on a stop trajectory, reports kReached at its end), the hazard detector
// (disc obstacles turned into sightings relative to the pose), the drive mode
// estimator, the mode manager and the deliberative layer. It records what the
// task publishes without allocating.
#pragma once

#include <cmath>
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/habitual/habitual_task.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/sensor_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/table_loader.hpp"

namespace rse::test {

class HabitualRig {
public:
    static constexpr core::TimeNs kRun = 100 * core::kNsPerMs;
    static constexpr std::size_t kMaxReports = 64;
    static constexpr std::size_t kMaxDiscs = 8;

    HabitualRig() : events(clock), bus(clock, events), tables(events), task(bus, events, tables) {}

    bool init() {
        if (!core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount))) {
            return false;
        }
        if (!core::isOk(bus.createPipe("probe", 32, &probe)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kTrajectory)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kLegReport)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kKnownHazards))) {
            return false;
        }
        if (!core::isOk(task.init())) {
            return false;
        }
        drainAllEvents();
        return true;
    }

    // ---- what the rest of the flight software would publish --------------------
    void setMode(std::uint8_t mode) {
        msg::ModeMsg m{};
        m.timeNs = clock.now();
        m.mode = mode;
        (void)bus.publish(m);
    }
    // Fault protection's mission hold (reasons 0: released).
    void sendHold(std::uint32_t reasons, std::uint32_t resumeCount, std::uint8_t estop = 0) {
        msg::MissionHoldMsg h{};
        h.timeNs = clock.now();
        h.reasons = reasons;
        h.resumeCount = resumeCount;
        h.estop = estop;
        (void)bus.publish(h);
    }
    // arriveWithinM: a goal region's radius (0: the point, reached to the table's tolerance).
    void sendLeg(std::uint32_t legId, double gx, double gy, double maxLengthM, double maxEnergyJ,
                 double maxPowerW = 0.0, double arriveWithinM = 0.0) {
        msg::LegCommandMsg leg{};
        leg.timeNs = clock.now();
        leg.legId = legId;
        leg.goalXM = gx;
        leg.goalYM = gy;
        leg.maxPathLengthM = maxLengthM;
        leg.maxEnergyJ = maxEnergyJ;
        leg.maxPowerW = maxPowerW;
        leg.arriveWithinM = arriveWithinM;
        (void)bus.publish(leg);
    }
    void sendPowerFactors(const double (&factors)[msg::kWheelCount], msg::DriveMode declared = msg::DriveMode::kNominal,
                          std::size_t declaredWheel = msg::kWheelCount) {
        msg::DriveModesMsg m{};
        m.timeNs = clock.now();
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            m.drives[w].powerFactor = static_cast<float>(factors[w]);
            m.drives[w].declared = w == declaredWheel ? declared : msg::DriveMode::kNominal;
            m.drives[w].probability[static_cast<std::size_t>(m.drives[w].declared)] = 1.0F;
        }
        m.updates = ++modeUpdates;
        (void)bus.publish(m);
    }
    void sendFollower(msg::FollowerState state, msg::FollowReason reason = msg::FollowReason::kNone) {
        msg::FollowerStatusMsg s{};
        s.timeNs = clock.now();
        s.trajectoryId = trajectory.trajectoryId;
        s.state = state;
        s.reason = reason;
        (void)bus.publish(s);
    }
    // A disc obstacle the synthetic hazard detector reports while it is within
    // `rangeM` of the rover (any bearing: the task must not care).
    void addHiddenDisc(std::uint8_t id, double cx, double cy, double radius) {
        if (discCount < kMaxDiscs) {
            discs[discCount++] = Disc{id, cx, cy, radius};
        }
    }

    // ---- one 10 Hz run --------------------------------------------------------
    void run() {
        clock.advance(kRun);
        advanceRover(kRun);
        publishHazards();
        for (int i = 0; i < 10; ++i) {
            msg::PoseEstimateMsg p{};
            p.timeNs = clock.now() - (9 - i) * 10 * core::kNsPerMs;
            p.xM = x;
            p.yM = y;
            p.headingRad = heading;
            p.speedMS = speed;
            p.initialised = poseInitialised ? 1 : 0;
            (void)bus.publish(p);
        }
        core::FrameContext frame{};
        frame.frame = ++frames;
        frame.scheduledStart = clock.now();
        frame.actualStart = clock.now();
        tables.run(frame);
        task.run(frame);
        drainProbe();
        pumpEvents();
    }
    void runFor(int runs) {
        for (int i = 0; i < runs; ++i) {
            run();
        }
    }
    // Runs until pred() or the run limit; returns whether pred() held.
    template <typename Pred>
    bool runUntil(Pred pred, int maxRuns) {
        for (int i = 0; i < maxRuns && !pred(); ++i) {
            run();
        }
        return pred();
    }

    // ---- tables -----------------------------------------------------------------
    template <typename Table>
    bool loadTable(tables::TableId id, const Table& table, std::uint32_t version) {
        const bool ok = activateTable(tables, id, table, version);
        drainAllEvents();
        return ok;
    }

    // ---- observations -------------------------------------------------------------
    // Events raised since the last clearSeen(), by id, and the latest text of each.
    unsigned seenCount(core::EventId id) {
        pumpEvents();
        return seen[id % 1000];
    }
    const char* seenText(core::EventId id) {
        pumpEvents();
        return texts[id % 1000];
    }
    void clearSeen() {
        pumpEvents();
        std::memset(seen, 0, sizeof seen);
    }
    void drainAllEvents() {
        pumpEvents();
        std::memset(seen, 0, sizeof seen);
    }

    core::VirtualClock clock{0};
    core::EventLog events;
    core::SoftwareBus bus;
    tables::TableService tables;
    habitual::HabitualTask task;
    core::PipeId probe = 0;
    std::uint64_t frames = 0;
    std::uint32_t modeUpdates = 0;

    // The synthetic rover.
    double x = 0.0;
    double y = 0.0;
    double heading = 0.0;
    double speed = 0.0;
    bool poseInitialised = true;
    bool follow = true;        // move along the trajectory
    bool reportReached = true;  // report kReached at its end
    double hazardRangeM = 3.0;

    // What the task published.
    msg::TrajectoryMsg trajectory{};  // latest
    unsigned trajectories = 0;
    unsigned stops = 0;
    unsigned plans = 0;
    msg::LegReportMsg reports[kMaxReports] = {};
    std::size_t reportCount = 0;  // all received; reports[] keeps the latest kMaxReports
    msg::LegReportMsg lastReport{};
    msg::KnownHazardsMsg lastHazards{};
    unsigned hazardMaps = 0;
    unsigned seen[1000] = {};
    char texts[1000][core::kEventTextSize] = {};

private:
    struct Disc {
        std::uint8_t id;
        double cx;
        double cy;
        double radius;
    };

    void pumpEvents() {
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            seen[e.id % 1000] += 1;
            std::memcpy(texts[e.id % 1000], e.text, sizeof e.text);
        }
    }

    void drainProbe() {
        for (int i = 0; i < 64 && core::isOk(bus.receive(probe, &inbox)); ++i) {
            msg::TrajectoryMsg t{};
            msg::LegReportMsg r{};
            msg::KnownHazardsMsg k{};
            if (core::isOk(inbox.decode(&k))) {
                lastHazards = k;
                ++hazardMaps;
            } else if (core::isOk(inbox.decode(&t))) {
                trajectory = t;
                ++trajectories;
                if (t.count == 0) {
                    ++stops;
                } else {
                    ++plans;
                }
                progress = 0.0;
                reachedSent = false;
            } else if (core::isOk(inbox.decode(&r))) {
                reports[reportCount % kMaxReports] = r;
                ++reportCount;
                lastReport = r;
            }
        }
    }

    void advanceRover(core::TimeNs dt) {
        if (!follow || trajectory.count < 2) {
            speed = 0.0;
            return;
        }
        double total = 0.0;
        for (std::size_t i = 1; i < trajectory.count; ++i) {
            total += std::hypot(trajectory.points[i].xM - trajectory.points[i - 1].xM,
                                trajectory.points[i].yM - trajectory.points[i - 1].yM);
        }
        if (progress >= total) {
            speed = 0.0;
            if (reportReached && !reachedSent) {
                sendFollower(msg::FollowerState::kReached);
                reachedSent = true;
            }
            return;
        }
        speed = trajectory.speedMS;
        progress += speed * static_cast<double>(dt) / static_cast<double>(core::kNsPerSec);
        if (progress > total) {
            progress = total;
        }
        double s = progress;
        for (std::size_t i = 1; i < trajectory.count; ++i) {
            const double ax = trajectory.points[i - 1].xM;
            const double ay = trajectory.points[i - 1].yM;
            const double len = std::hypot(trajectory.points[i].xM - ax, trajectory.points[i].yM - ay);
            if (len <= 0.0) {
                continue;
            }
            heading = std::atan2(trajectory.points[i].yM - ay, trajectory.points[i].xM - ax);
            if (s <= len || i + 1 == trajectory.count) {
                const double t = s < len ? s / len : 1.0;
                x = ax + t * (trajectory.points[i].xM - ax);
                y = ay + t * (trajectory.points[i].yM - ay);
                break;
            }
            s -= len;
        }
    }

    void publishHazards() {
        msg::HazardMsg h{};
        h.timeNs = clock.now();
        for (std::size_t i = 0; i < discCount; ++i) {
            const Disc& d = discs[i];
            const double dist = std::hypot(d.cx - x, d.cy - y);
            if (dist - d.radius > hazardRangeM || h.count >= msg::kMaxHazardsInMsg) {
                continue;
            }
            msg::HazardSightingTlm& s = h.sightings[h.count++];
            s.rangeM = dist - d.radius;
            s.bearingRad = std::atan2(d.cy - y, d.cx - x) - heading;
            s.halfWidthM = d.radius;
            s.obstacleId = d.id;
        }
        (void)bus.publish(h);
    }

    core::Message inbox{};
    double progress = 0.0;
    bool reachedSent = false;
    Disc discs[kMaxDiscs] = {};
    std::size_t discCount = 0;
};

}  // namespace rse::test
