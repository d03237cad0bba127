// Test-only: the deliberative task on a real software bus with the default
// tables, one 10 Hz run at a time. The rig stands in for what surrounds it: the
// estimator (a PoseEstimateMsg per run from a synthetic pose and covariance),
// the plan executive (PlanGoalMsg) and the mode owner (ModeMsg), the drive-mode estimator
// (DriveModesMsg) and the habitual layer (LegReportMsg, written by each test).
// It records what the task publishes (legs, plan status, plan paths, safe requests) and
// the events it raises, without allocating.
#pragma once

#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/deliberative/deliberative_task.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/fault_protection_msgs.hpp"
#include "fsw/msg/goal_msgs.hpp"
#include "fsw/msg/habitual_msgs.hpp"
#include "fsw/msg/health_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/table_loader.hpp"

namespace rse::test {

class DeliberativeRig {
public:
    static constexpr core::TimeNs kRun = 100 * core::kNsPerMs;
    static constexpr std::uint8_t kAutonomous = 2;
    static constexpr std::uint8_t kStandby = 1;

    // siteMap: the site map the task plans on (site mode), or none.
    explicit DeliberativeRig(const site_map::SiteMap* siteMap = nullptr)
        : events(clock), bus(clock, events), tables(events), task(bus, events, tables, siteMap) {}

    bool init() {
        if (!core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount))) {
            return false;
        }
        if (!core::isOk(bus.createPipe("probe", 32, &probe)) || !core::isOk(bus.subscribe(probe, msg::ids::kLegCommand)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kPlanStatus)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kSafeRequest)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kPlanPath)) ||
            !core::isOk(bus.subscribe(probe, msg::ids::kRouteChunk))) {
            return false;
        }
        if (!core::isOk(task.init())) {
            return false;
        }
        clearSeen();
        return true;
    }

    // ---- what the rest of the flight software would publish -------------------
    void setMode(std::uint8_t mode) {
        msg::ModeMsg m{};
        m.timeNs = clock.now();
        m.mode = mode;
        (void)bus.publish(m);
    }
    // The plan executive's goals: one (a drive activity); lists with more as
    // well (the task takes them, the executive sends one at a time).
    void sendGoals(const double (*xy)[2], std::size_t count, double risk, std::uint8_t listIndex = 0,
                   float radiusM = 0.0F) {
        msg::PlanGoalMsg p{};
        p.listIndex = listIndex;
        msg::GoalListMsg& g = p.goals;
        g.timeNs = clock.now();
        g.riskBound = risk;
        g.revision = ++goalRevision;
        g.count = static_cast<std::uint8_t>(count);
        for (std::size_t i = 0; i < count; ++i) {
            g.goals[i].xM = xy[i][0];
            g.goals[i].yM = xy[i][1];
            g.goals[i].radiusM = radiusM;
        }
        (void)bus.publish(p);
    }
    // radiusM: a drive `within` it (0: the point).
    void sendGoal(double gx, double gy, double risk, float radiusM = 0.0F) {
        const double xy[1][2] = {{gx, gy}};
        sendGoals(xy, 1, risk, 0, radiusM);
    }
    // The interlock latched (or not), with wheel `failed` failed and the others operational.
    void sendDriveStatus(bool interlockTripped, std::size_t failed = msg::kWheelCount) {
        msg::DriveStatusMsg status{};
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            status.wheels[w].health = w == failed ? msg::DriveHealth::kFailed : msg::DriveHealth::kOperational;
        }
        status.interlockTripped = interlockTripped ? 1 : 0;
        (void)bus.publish(status);
    }
    void sendDriveModes(msg::DriveMode declared = msg::DriveMode::kNominal, std::size_t wheel = msg::kWheelCount,
                        double factor = 1.0) {
        msg::DriveModesMsg m{};
        m.timeNs = clock.now();
        for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
            m.drives[w].powerFactor = static_cast<float>(w == wheel ? factor : 1.0);
            m.drives[w].declared = w == wheel ? declared : msg::DriveMode::kNominal;
            m.drives[w].probability[static_cast<std::size_t>(m.drives[w].declared)] = 1.0F;
        }
        (void)bus.publish(m);
    }
    // The habitual layer's remembered hazards: {x, y, radius} each, ids 1, 2, ...
    void sendHazards(const double (*xyr)[3], std::size_t count) {
        msg::KnownHazardsMsg m{};
        m.timeNs = clock.now();
        m.revision = ++hazardRevision;
        m.count = static_cast<std::uint8_t>(count);
        for (std::size_t i = 0; i < count; ++i) {
            m.hazards[i].xM = static_cast<float>(xyr[i][0]);
            m.hazards[i].yM = static_cast<float>(xyr[i][1]);
            m.hazards[i].radiusM = static_cast<float>(xyr[i][2]);
            m.hazards[i].obstacleId = static_cast<std::uint8_t>(i + 1);
        }
        (void)bus.publish(m);
    }
    // Fault protection's mission hold (reasons 0: released).
    void sendHold(std::uint32_t reasons, std::uint32_t resumeCount) {
        msg::MissionHoldMsg h{};
        h.timeNs = clock.now();
        h.reasons = reasons;
        h.resumeCount = resumeCount;
        (void)bus.publish(h);
    }
    void sendFaults(std::uint64_t activeMask) {
        msg::FaultStatusMsg f{};
        f.timeNs = clock.now();
        f.activeMask = activeMask;
        (void)bus.publish(f);
    }
    void report(msg::HabitualState state, msg::LegConstraint violated = msg::LegConstraint::kNone,
                double predicted = 0.0, double allowed = 0.0) {
        msg::LegReportMsg r{};
        r.timeNs = clock.now();
        r.legId = lastLeg.legId;
        r.state = state;
        r.violated = violated;
        if (violated == msg::LegConstraint::kEnergy) {
            r.predictedEnergyJ = predicted;
            r.allowedEnergyJ = allowed;
        } else if (violated == msg::LegConstraint::kPower) {
            r.predictedPowerW = predicted;
            r.allowedPowerW = allowed;
        } else {
            r.predictedLengthM = predicted;
            r.allowedLengthM = allowed;
        }
        r.excess = predicted - allowed;
        (void)bus.publish(r);
    }
    // The habitual layer reached the leg: the rover is at its end.
    void achieveLeg() {
        x = lastLeg.goalXM;
        y = lastLeg.goalYM;
        report(msg::HabitualState::kAchieved);
    }

    // ---- one 10 Hz run ------------------------------------------------------------
    void run() {
        clock.advance(kRun);
        if (publishPose) {
            msg::PoseEstimateMsg p{};
            p.timeNs = clock.now();
            p.xM = x;
            p.yM = y;
            p.headingRad = heading;
            p.covariance[0] = positionVariance;
            p.covariance[4] = positionVariance;
            p.covariance[8] = 1e-4;
            p.initialised = 1;
            p.positionSigmaM = positionSigma;
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
    template <typename Pred>
    bool runUntil(Pred pred, int maxRuns) {
        for (int i = 0; i < maxRuns && !pred(); ++i) {
            run();
        }
        return pred();
    }
    bool runUntilState(msg::DeliberativeState state, int maxRuns = 200) {
        return runUntil([&] { return task.state() == state; }, maxRuns);
    }

    template <typename Table>
    bool loadTable(tables::TableId id, const Table& table, std::uint32_t version) {
        const bool ok = activateTable(tables, id, table, version);
        clearSeen();
        return ok;
    }

    unsigned seenCount(core::EventId id) {
        pumpEvents();
        return seen[id % 1000];
    }
    const char* seenText(core::EventId id) {
        pumpEvents();
        return texts[id % 1000];
    }
    // The latest event's numbers by name (false: none of that layout).
    template <typename Layout>
    bool seenData(core::EventId id, Layout* out) {
        pumpEvents();
        return out->unpack(id, data[id % 1000]);
    }
    void clearSeen() {
        pumpEvents();
        std::memset(seen, 0, sizeof seen);
    }

    core::VirtualClock clock{0};
    core::EventLog events;
    core::SoftwareBus bus;
    tables::TableService tables;
    deliberative::DeliberativeTask task;
    core::PipeId probe = 0;
    std::uint64_t frames = 0;
    std::uint32_t goalRevision = 0;
    std::uint32_t hazardRevision = 0;

    // The synthetic estimate.
    double x = 0.0;
    double y = 0.0;
    double heading = 0.0;
    double positionVariance = 0.01;  // m^2 on each axis (0.1 m 1-sigma)
    double positionSigma = 0.1;      // PoseEstimateMsg::positionSigmaM
    bool publishPose = true;

    // What the task published.
    msg::LegCommandMsg lastLeg{};     // latest nonzero leg
    unsigned legs = 0;                // nonzero legs
    unsigned cancels = 0;             // legId 0
    msg::PlanStatusMsg lastStatus{};
    unsigned statuses = 0;
    msg::SafeRequestMsg lastSafe{};
    unsigned safeRequests = 0;
    msg::PlanPathMsg lastPath{};
    unsigned planPaths = 0;
    msg::RouteChunkMsg lastRouteChunk{};
    unsigned routeChunks = 0;
    unsigned seen[1000] = {};
    char texts[1000][core::kEventTextSize] = {};
    core::EventData data[1000] = {};

private:
    void pumpEvents() {
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            seen[e.id % 1000] += 1;
            std::memcpy(texts[e.id % 1000], e.text, sizeof e.text);
            data[e.id % 1000] = e.data;
        }
    }
    void drainProbe() {
        for (int i = 0; i < 64 && core::isOk(bus.receive(probe, &inbox)); ++i) {
            msg::LegCommandMsg leg{};
            msg::PlanStatusMsg status{};
            msg::SafeRequestMsg safe{};
            msg::PlanPathMsg path{};
            msg::RouteChunkMsg chunk{};
            if (inbox.header.id == msg::ids::kRouteChunk && core::isOk(inbox.decode(&chunk))) {
                lastRouteChunk = chunk;
                ++routeChunks;
            } else if (inbox.header.id == msg::ids::kLegCommand && core::isOk(inbox.decode(&leg))) {
                if (leg.legId == 0) {
                    ++cancels;
                } else {
                    lastLeg = leg;
                    ++legs;
                }
            } else if (inbox.header.id == msg::ids::kPlanStatus && core::isOk(inbox.decode(&status))) {
                lastStatus = status;
                ++statuses;
            } else if (inbox.header.id == msg::ids::kSafeRequest && core::isOk(inbox.decode(&safe))) {
                lastSafe = safe;
                ++safeRequests;
            } else if (inbox.header.id == msg::ids::kPlanPath && core::isOk(inbox.decode(&path))) {
                lastPath = path;
                ++planPaths;
            }
        }
    }
    core::Message inbox{};
};

}  // namespace rse::test
