// The trajectory follower task on an in-memory software bus, closing the loop
// through a kinematic unicycle: each 10 ms frame the test publishes the rover's
// pose (as the estimator would) and the drive status (as CAN I/O would), runs
// the task, takes the wheel command it published (CAN I/O keeps the last one),
// turns it back into body (v, w) with the inverse of the skid-steer law and
// integrates the rover over the frame. Every frame the command is checked
// against the rover geometry table's speed, acceleration and wheel limits.
#include <cmath>
#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/drive_msgs.hpp"
#include "fsw/msg/estimator_msgs.hpp"
#include "fsw/msg/mode_msgs.hpp"
#include "fsw/msg/trajectory_msgs.hpp"
#include "fsw/reflexive/reflexive_events.hpp"
#include "fsw/reflexive/trajectory_task.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_image.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/support/alloc_guard.hpp"
#include "unit_test/support/event_probe.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using core::Status;
using core::TimeNs;
using msg::FollowerState;
using msg::FollowReason;
namespace ev = rse::reflexive::events;

namespace {

constexpr TimeNs kFrame = 10 * core::kNsPerMs;
constexpr double kDt = 0.01;
constexpr double kEps = 1e-9;
constexpr double kPi = 3.14159265358979323846;
constexpr std::uint8_t kSafe = 0;
constexpr std::uint8_t kStandby = 1;
constexpr std::uint8_t kAutonomous = 2;
constexpr std::uint8_t kManual = 3;

struct Pt {
    double x;
    double y;
};

// Distance from (x, y) to the polyline pts[0..n-1].
double distanceToPath(const Pt* pts, std::size_t n, double x, double y) {
    double best = std::hypot(x - pts[0].x, y - pts[0].y);
    for (std::size_t k = 0; k + 1 < n; ++k) {
        const double ex = pts[k + 1].x - pts[k].x;
        const double ey = pts[k + 1].y - pts[k].y;
        const double len2 = ex * ex + ey * ey;
        double t = len2 > 0.0 ? ((x - pts[k].x) * ex + (y - pts[k].y) * ey) / len2 : 0.0;
        t = t < 0.0 ? 0.0 : (t > 1.0 ? 1.0 : t);
        best = std::fmin(best, std::hypot(x - (pts[k].x + t * ex), y - (pts[k].y + t * ey)));
    }
    return best;
}

}  // namespace

TEST_GROUP(TrajectoryTask) {
    core::VirtualClock clock{1 * core::kNsPerSec};
    core::EventLog events{clock};
    // CppUTest creates each test object on the heap, so the bus's storage stays off the stack.
    core::SoftwareBus bus{clock, events};
    tables::TableService tables{events};
    reflexive::TrajectoryTask task{clock, bus, events, tables};
    core::PipeId probe = 0;
    core::Message inbox{};
    std::uint64_t frameCount = 0;

    // The rover: a unicycle driven by the wheel command CAN I/O holds.
    double x = 0.0, y = 0.0, heading = 0.0;
    double wheels[msg::kWheelCount] = {};
    double v = 0.0, w = 0.0;  // body speed and rate of the held command
    // The world around the task.
    bool posePublishing = true;
    std::uint8_t poseInitialised = 1;
    std::uint8_t interlock = 0;
    bool canIoEstop = false;        // CAN I/O holds every drive at zero and ignores commands
    double wheelCurrentA = 1.4;     // what a turning wheel draws (a rolling one: about 1.4 A)
    bool blocked = false;           // a rock ahead: the rover does not move forwards
    bool skipAccelCheckOnce = false;
    std::uint32_t haltsSeen = 0;
    // What the task published in the last frame, and over the test.
    unsigned commandsThisFrame = 0;
    unsigned commandsTotal = 0;
    msg::WheelCommandMsg lastCommand{};
    unsigned statusesThisFrame = 0;
    unsigned statusesTotal = 0;
    msg::FollowerStatusMsg lastStatus{};
    // Largest seen over the test.
    double maxSpeed = 0.0;
    // Geometry, as the f32 table fields hold it.
    double radius = 0.0, track = 0.0, accelLimit = 0.0, speedLimit = 0.0, rateLimit = 0.0, wheelLimit = 0.0;

    void setup() override {
        CHECK_TRUE(Status::kOk == tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount));
        const tables::RoverGeometryTable& g = tables.roverGeometry();
        radius = static_cast<double>(g.wheel_radius_m);
        track = static_cast<double>(g.track_width_m);
        accelLimit = static_cast<double>(g.max_accel_m_s2);
        speedLimit = static_cast<double>(g.max_body_speed_m_s);
        rateLimit = static_cast<double>(g.max_body_rate_rad_s);
        wheelLimit = static_cast<double>(g.max_wheel_speed_rad_s);
        DOUBLES_EQUAL(0.30, speedLimit, 1e-6);  // the figures below assume the default tables
        DOUBLES_EQUAL(0.20, accelLimit, 1e-6);
        DOUBLES_EQUAL(0.15, static_cast<double>(tables.follower().arrival_tolerance_m), 1e-6);
        CHECK_TRUE(Status::kOk == task.init());
        CHECK_TRUE(Status::kOk == bus.createPipe("probe", 8, &probe));
        CHECK_TRUE(Status::kOk == bus.subscribe(probe, msg::ids::kWheelCommand));
        CHECK_TRUE(Status::kOk == bus.subscribe(probe, msg::ids::kFollowerStatus));
        publishMode(kAutonomous);
        runFrame();
        (void)test::drainEventsWithId(events, 0);
    }

    void publishMode(std::uint8_t mode, std::uint8_t estop = 0) {
        msg::ModeMsg m{};
        m.timeNs = clock.now();
        m.mode = mode;
        m.estop = estop;
        CHECK_TRUE(Status::kOk == bus.publish(m));
    }

    msg::TrajectoryMsg trajectory(std::uint32_t id, double speed, const Pt* pts, std::size_t n) {
        msg::TrajectoryMsg t{};
        t.timeNs = clock.now();
        t.trajectoryId = id;
        t.legId = 7;
        t.speedMS = speed;
        t.count = static_cast<std::uint8_t>(n);
        for (std::size_t i = 0; i < n && i < msg::kMaxTrajectoryPoints; ++i) {
            t.points[i] = msg::TrajectoryPoint{pts[i].x, pts[i].y};
        }
        return t;
    }
    void send(std::uint32_t id, double speed, const Pt* pts, std::size_t n) {
        CHECK_TRUE(Status::kOk == bus.publish(trajectory(id, speed, pts, n)));
    }
    void sendStop(std::uint32_t id) { send(id, 0.0, nullptr, 0); }

    // One minor frame: inputs, the task, its outputs, the rover moves, time moves on.
    void runFrame() {
        const TimeNs now = clock.now();
        if (posePublishing) {
            msg::PoseEstimateMsg p{};
            p.timeNs = now;
            p.xM = x;
            p.yM = y;
            p.headingRad = heading;
            p.speedMS = v;
            p.yawRateRadS = w;
            p.initialised = poseInitialised;
            CHECK_TRUE(Status::kOk == bus.publish(p));
        }
        msg::DriveStatusMsg d{};
        d.timeNs = now;
        d.interlockTripped = interlock;
        // The drives: each wheel turning as commanded (stopped against a
        // rock when blocked), drawing wheelCurrentA.
        for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
            msg::WheelStatus& ws = d.wheels[i];
            ws.targetRadS = wheels[i];
            ws.velocityRadS = wheels[i];
            ws.currentA = wheels[i] != 0.0 ? wheelCurrentA : 0.15;
            ws.feedbackTimeNs = now;
            ws.feedbackCount = static_cast<std::uint32_t>(frameCount + 1);
            ws.health = msg::DriveHealth::kOperational;
        }
        CHECK_TRUE(Status::kOk == bus.publish(d));
        task.run(core::FrameContext{frameCount, static_cast<std::uint32_t>(frameCount % 100), now, now});
        ++frameCount;
        commandsThisFrame = 0;
        statusesThisFrame = 0;
        while (core::isOk(bus.receive(probe, &inbox))) {
            if (inbox.header.id == msg::ids::kWheelCommand) {
                CHECK_TRUE(Status::kOk == inbox.decode(&lastCommand));
                ++commandsThisFrame;
                ++commandsTotal;
                for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
                    wheels[i] = lastCommand.velocityRadS[i];
                }
            } else {
                CHECK_TRUE(Status::kOk == inbox.decode(&lastStatus));
                ++statusesThisFrame;
                ++statusesTotal;
            }
        }
        LONGS_EQUAL_TEXT(0, bus.pipeStats(probe)->dropped, "the probe missed a message");
        checkAndIntegrate();
        clock.advance(kFrame);
    }

    // Inverse skid-steer, the limits, then the unicycle over one frame. A
    // give-up or a halt zeroes the wheels at once by design: exempt from the
    // acceleration check, as is CAN I/O's e-stop.
    void checkAndIntegrate() {
        if (canIoEstop) {
            for (double& c : wheels) {
                c = 0.0;
            }
        }
        for (std::size_t i = 0; i < msg::kWheelCount; ++i) {
            CHECK_TRUE(wheels[i] == wheels[i < 3 ? 0 : 3]);  // one speed per side
        }
        const double left = wheels[0];
        const double right = wheels[3];
        const double vNew = radius * (left + right) / 2.0;
        const double wNew = radius * (right - left) / track;
        const bool zeroedAtOnce = task.state() == FollowerState::kCannotFollow || task.counters().halts != haltsSeen;
        const bool hardStop = (vNew == 0.0 && wNew == 0.0 && zeroedAtOnce) || canIoEstop || skipAccelCheckOnce;
        skipAccelCheckOnce = false;
        haltsSeen = task.counters().halts;
        maxSpeed = std::fmax(maxSpeed, std::fabs(vNew));
        CHECK_TRUE(std::fabs(vNew) <= speedLimit + kEps);
        CHECK_TRUE(std::fabs(wNew) <= rateLimit + kEps);
        if (!hardStop) {
            CHECK_TRUE(std::fabs(vNew - v) / kDt <= accelLimit + kEps);
            CHECK_TRUE(std::fabs(wNew - w) / kDt <= accelLimit / (track / 2.0) + kEps);
        }
        CHECK_TRUE(std::fabs(left) <= wheelLimit + kEps && std::fabs(right) <= wheelLimit + kEps);
        v = vNew;
        w = wNew;
        for (int i = 0; i < 10; ++i) {  // 1 ms sub-steps
            if (blocked && v > 0.0) {
                continue;
            }
            x += v * std::cos(heading) * kDt / 10.0;
            y += v * std::sin(heading) * kDt / 10.0;
            heading += w * kDt / 10.0;
        }
        heading = std::remainder(heading, 2.0 * kPi);
    }
    void runFrames(int n) {
        for (int i = 0; i < n; ++i) {
            runFrame();
        }
    }
    // Runs until the task's state is `state` (at most maxFrames); returns the frames run.
    int runUntil(FollowerState state, int maxFrames) {
        int n = 0;
        while (task.state() != state && n < maxFrames) {
            runFrame();
            ++n;
        }
        CHECK_TRUE_TEXT(task.state() == state, "state not reached in time");
        return n;
    }
    // Follows a long straight path east until at cruise speed.
    void cruiseEast() {
        const Pt pts[2] = {{x, y}, {x + 100.0, y}};
        send(1, 0.3, pts, 2);
        runFrames(200);
        DOUBLES_EQUAL(0.3, v, 1e-6);
        (void)test::drainEventsWithId(events, 0);
    }
    bool commandIsZero() const {
        for (double c : lastCommand.velocityRadS) {
            if (c != 0.0) {
                return false;
            }
        }
        return true;
    }
    unsigned eventsWithId(core::EventId id) { return test::drainEventsWithId(events, id); }
};

TEST(TrajectoryTask, AStraightLineIsFollowedAndReachedWithinTheTolerance) {
    x = 0.0;
    y = 0.05;  // a little off the line
    heading = 0.05;
    const Pt pts[2] = {{0.0, 0.0}, {5.0, 0.0}};
    send(11, 0.3, pts, 2);
    runFrame();
    CHECK_TRUE(FollowerState::kFollowing == task.state());
    LONGS_EQUAL(1, task.counters().trajectoriesAccepted);
    LONGS_EQUAL(1, eventsWithId(ev::kTrajectoryAccepted));
    double worst = 0.0;
    double converged = 0.0;
    int frames = 0;
    while (task.state() == FollowerState::kFollowing && frames < 3000) {
        runFrame();
        ++frames;
        CHECK_TRUE(commandsThisFrame == 1);  // every run while following
        worst = std::fmax(worst, std::fabs(y));
        if (x > 2.0) {
            converged = std::fmax(converged, std::fabs(y));
        }
    }
    CHECK_TRUE(FollowerState::kReached == task.state());
    CHECK_TRUE(worst < 0.06);       // never farther than it started
    CHECK_TRUE(converged < 0.005);  // and on the line after 2 m
    DOUBLES_EQUAL(0.3, maxSpeed, 1e-6);  // cruised at the limit
    LONGS_EQUAL(1, task.counters().reached);
    LONGS_EQUAL(1, eventsWithId(ev::kTrajectoryReached));
    CHECK_TRUE(FollowerState::kReached == lastStatus.state);
    LONGS_EQUAL(11, lastStatus.trajectoryId);
    // It comes to rest within the tolerance of the last point, then publishes nothing more.
    runFrames(200);
    DOUBLES_EQUAL(0.0, v, 0.0);
    DOUBLES_EQUAL(0.0, w, 0.0);
    CHECK_TRUE(std::hypot(x - 5.0, y) <= 0.15);
    const unsigned published = commandsTotal;
    runFrames(300);
    LONGS_EQUAL(published, commandsTotal);
    LONGS_EQUAL(0, eventsWithId(ev::kTrajectoryReached));  // once
    CHECK_TRUE(FollowerState::kReached == task.state());
}

TEST(TrajectoryTask, AnLShapedPathIsFollowedWithABoundedCrossTrackError) {
    const Pt pts[3] = {{0.0, 0.0}, {4.0, 0.0}, {4.0, 4.0}};
    send(12, 0.3, pts, 3);
    double worst = 0.0;
    int frames = 0;
    while (task.state() != FollowerState::kReached && frames < 5000) {
        runFrame();
        ++frames;
        worst = std::fmax(worst, distanceToPath(pts, 3, x, y));
    }
    CHECK_TRUE(FollowerState::kReached == task.state());
    CHECK_TRUE(worst < 0.2);  // pure pursuit cuts the corner (0.17 m with the default tables)
    runFrames(300);
    CHECK_TRUE(std::hypot(x - 4.0, y - 4.0) <= 0.15);
    DOUBLES_EQUAL(0.0, v, 0.0);
    LONGS_EQUAL(2, task.latestStatus().targetIndex);  // the last segment ends at points[2]
    CHECK_TRUE(task.latestStatus().remainingM < 0.15);
}

TEST(TrajectoryTask, ThePathStartingBehindIsTurnedInPlaceFirst) {
    const Pt pts[2] = {{0.0, 0.0}, {-4.0, 0.2}};
    send(13, 0.3, pts, 2);
    int turning = 0;
    runFrame();
    while (task.follower().latest().turningInPlace && turning < 2000) {
        DOUBLES_EQUAL(0.0, v, 0.0);  // turning in place: no forward speed
        runFrame();
        ++turning;
    }
    CHECK_TRUE(turning > 100);  // about 2.3 rad at up to 0.5 rad/s
    CHECK_TRUE(std::hypot(x, y) < 1e-4);  // the frame it drove on moved it 0.02 mm
    CHECK_TRUE(heading > 0.0);  // turned left, towards the look-ahead point at +y
    LONGS_EQUAL(1, task.follower().turnsInPlace());
    runUntil(FollowerState::kReached, 5000);
    LONGS_EQUAL(1, task.follower().turnsInPlace());
}

TEST(TrajectoryTask, AStopTrajectoryDeceleratesToZeroWithinVOverAPlusOneFrame) {
    cruiseEast();
    const double v0 = v;
    sendStop(2);
    posePublishing = false;  // a stop waits for nothing, not even a pose
    int frames = 0;
    while (v > 0.0 && frames < 1000) {
        runFrame();
        ++frames;
        if (v > 0.0) {
            CHECK_TRUE(FollowerState::kStopping == task.state());
        }
    }
    // Time to zero body speed: v / max_accel, plus at most one frame.
    CHECK_TRUE(frames * kDt <= v0 / accelLimit + kDt + 1e-9);
    CHECK_TRUE(frames * kDt >= v0 / accelLimit - kDt);  // and no faster than the limit allows
    CHECK_TRUE(FollowerState::kIdle == task.state());
    LONGS_EQUAL(1, task.counters().stopsAccepted);
    LONGS_EQUAL(1, task.counters().stopsCompleted);
    CHECK_TRUE(commandIsZero());
    core::Event e;
    unsigned accepted = 0, stopped = 0;
    while (core::isOk(events.pop(&e))) {
        accepted += e.id == ev::kStopAccepted ? 1U : 0U;
        stopped += e.id == ev::kFollowerStopped ? 1U : 0U;
    }
    LONGS_EQUAL(1, accepted);
    LONGS_EQUAL(1, stopped);
    LONGS_EQUAL(2, task.latestStatus().trajectoryId);
    const unsigned published = commandsTotal;
    runFrames(200);
    LONGS_EQUAL(published, commandsTotal);  // idle: the zero was the last command
}

TEST(TrajectoryTask, TheInterlockCutsAStopShortAtOnce) {
    cruiseEast();
    sendStop(2);
    runFrames(20);
    CHECK_TRUE(FollowerState::kStopping == task.state());
    CHECK_TRUE(v > 0.0);
    interlock = 1;
    runFrame();
    CHECK_TRUE(FollowerState::kIdle == task.state());
    LONGS_EQUAL(1, commandsThisFrame);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().halts);
    LONGS_EQUAL(0, task.counters().stopsCompleted);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerHalted));
}

TEST(TrajectoryTask, LeavingAutonomousWhileDeceleratingAfterArrivalZeroesAtOnce) {
    const Pt pts[2] = {{0.0, 0.0}, {2.0, 0.0}};
    send(8, 0.3, pts, 2);
    runUntil(FollowerState::kReached, 2000);
    CHECK_TRUE(v > 0.0);  // still decelerating
    const unsigned before = commandsTotal;
    publishMode(kStandby);
    runFrame();
    CHECK_TRUE(FollowerState::kReached == task.state());  // it did reach
    LONGS_EQUAL(1, commandsThisFrame);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().halts);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerHalted));
    runFrames(100);
    LONGS_EQUAL(before + 1, commandsTotal);
}

TEST(TrajectoryTask, CrossTrackErrorGivesUpWithTheWheelsAtZeroInTheSameFrame) {
    cruiseEast();
    y += 1.2;  // shoved off the path (max_cross_track_m 1.0)
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kCrossTrackError == task.latestStatus().reason);
    LONGS_EQUAL(1, commandsThisFrame);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, statusesThisFrame);
    CHECK_TRUE(FollowerState::kCannotFollow == lastStatus.state);
    DOUBLES_EQUAL(0.0, lastStatus.commandedSpeedMS, 0.0);
    DOUBLES_EQUAL(1.2, lastStatus.crossTrackErrorM, 0.01);
    LONGS_EQUAL(1, task.counters().gaveUpCrossTrack);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerGaveUp));
    const unsigned published = commandsTotal;
    runFrames(100);
    LONGS_EQUAL(published, commandsTotal);
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
}

TEST(TrajectoryTask, APoseOlderThanTheTimeoutGivesUpWithTheWheelsAtZeroInTheSameFrame) {
    cruiseEast();
    posePublishing = false;  // the last pose was published at the start of the previous frame
    const TimeNs timeout = static_cast<TimeNs>(tables.follower().pose_timeout_ms) * core::kNsPerMs;
    const TimeNs lastPose = clock.now() - kFrame;
    int frames = 0;
    while (task.state() == FollowerState::kFollowing && frames < 100) {
        runFrame();
        ++frames;
    }
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kPoseStale == task.latestStatus().reason);
    const TimeNs gaveUpAt = clock.now() - kFrame;
    CHECK_TRUE(gaveUpAt - lastPose > timeout);
    CHECK_TRUE(gaveUpAt - kFrame - lastPose <= timeout);  // the first frame it was too old
    LONGS_EQUAL(1, commandsThisFrame);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().gaveUpPoseStale);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerGaveUp));
}

TEST(TrajectoryTask, AnUninitialisedPoseGivesUpAtOnce) {
    poseInitialised = 0;
    runFrame();
    const Pt pts[2] = {{0.0, 0.0}, {3.0, 0.0}};
    send(3, 0.3, pts, 2);
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kPoseStale == task.latestStatus().reason);
    LONGS_EQUAL(1, task.counters().gaveUpPoseStale);
    LONGS_EQUAL(0, commandsTotal);  // never moved: nothing to zero
    DOUBLES_EQUAL(0.0, v, 0.0);
}

TEST(TrajectoryTask, TheDriveInterlockGivesUpWithTheWheelsAtZeroInTheSameFrame) {
    cruiseEast();
    interlock = 1;
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kDrivesHeld == task.latestStatus().reason);
    LONGS_EQUAL(1, commandsThisFrame);
    CHECK_TRUE(commandIsZero());  // so the drives do not resume the old speed when it resets
    LONGS_EQUAL(1, task.counters().gaveUpDrivesHeld);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerGaveUp));
    // A trajectory while the drives are held is taken and given up at once.
    const Pt pts[2] = {{x, y}, {x + 3.0, y}};
    send(4, 0.3, pts, 2);
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    LONGS_EQUAL(4, task.latestStatus().trajectoryId);
    LONGS_EQUAL(2, task.counters().gaveUpDrivesHeld);
    LONGS_EQUAL(0, commandsThisFrame);
}

TEST(TrajectoryTask, TheSoftwareEstopGivesUpInTheSameFrameAndPublishesNothing) {
    cruiseEast();
    publishMode(kAutonomous, 1);
    canIoEstop = true;
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kDrivesHeld == task.latestStatus().reason);
    DOUBLES_EQUAL(0.0, task.latestStatus().commandedSpeedMS, 0.0);
    DOUBLES_EQUAL(0.0, task.latestStatus().commandedTurnRateRadS, 0.0);
    // CAN I/O zeroes every drive on the same ModeMsg and refuses commands while
    // the e-stop is set, so the follower sends none.
    LONGS_EQUAL(0, commandsThisFrame);
    LONGS_EQUAL(1, task.counters().gaveUpDrivesHeld);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerGaveUp));
    canIoEstop = false;
    publishMode(kAutonomous, 0);  // cleared: the rover stays at rest until the next trajectory
    runFrames(50);
    LONGS_EQUAL(0, commandsThisFrame);
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
}

TEST(TrajectoryTask, LeavingAutonomousGivesUpWithOneZeroCommandAndThenSilence) {
    cruiseEast();
    const unsigned before = commandsTotal;
    publishMode(kManual);
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    CHECK_TRUE(FollowReason::kNotAutonomous == task.latestStatus().reason);
    LONGS_EQUAL(1, commandsThisFrame);  // the rover was moving: stopped in this frame
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().gaveUpNotAutonomous);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerGaveUp));
    runFrames(200);
    LONGS_EQUAL(before + 1, commandsTotal);  // never again outside AUTONOMOUS
}

TEST(TrajectoryTask, NoWheelCommandIsEverPublishedOutsideAutonomous) {
    const std::uint8_t modes[3] = {kSafe, kStandby, kManual};
    std::uint32_t id = 20;
    for (std::uint8_t mode : modes) {
        publishMode(mode);
        runFrame();
        const Pt pts[2] = {{x, y}, {x + 3.0, y}};
        send(++id, 0.3, pts, 2);
        runFrame();
        CHECK_TRUE(FollowerState::kCannotFollow == task.state());
        CHECK_TRUE(FollowReason::kNotAutonomous == task.latestStatus().reason);
        LONGS_EQUAL(id, task.latestStatus().trajectoryId);
        runFrames(100);
        sendStop(++id);
        runFrame();
        CHECK_TRUE(FollowerState::kIdle == task.state());
        runFrames(50);
    }
    LONGS_EQUAL(0, commandsTotal);
    LONGS_EQUAL(3, task.counters().gaveUpNotAutonomous);
    DOUBLES_EQUAL(0.0, std::hypot(x, y), 0.0);
}

TEST(TrajectoryTask, BeforeAnyModeMessageItIsNotAutonomous) {
    reflexive::TrajectoryTask fresh{clock, bus, events, tables};
    CHECK_TRUE(Status::kOk == fresh.init());
    CHECK_FALSE(fresh.autonomous());
    const Pt pts[2] = {{0.0, 0.0}, {3.0, 0.0}};
    send(5, 0.3, pts, 2);
    fresh.run(core::FrameContext{});
    CHECK_TRUE(FollowerState::kCannotFollow == fresh.state());
    CHECK_TRUE(FollowReason::kNotAutonomous == fresh.latestStatus().reason);
    LONGS_EQUAL(0, fresh.counters().wheelCommandsPublished);
}

TEST(TrajectoryTask, ANewTrajectoryRestartsFollowingAfterAGiveUp) {
    cruiseEast();
    y += 1.5;
    runFrame();
    CHECK_TRUE(FollowerState::kCannotFollow == task.state());
    const Pt pts[2] = {{x, y}, {x + 2.0, y}};
    send(6, 0.3, pts, 2);
    runFrame();
    CHECK_TRUE(FollowerState::kFollowing == task.state());
    CHECK_TRUE(FollowReason::kNone == task.latestStatus().reason);
    LONGS_EQUAL(6, lastStatus.trajectoryId);  // published at once: the id changed
    runUntil(FollowerState::kReached, 3000);
}

TEST(TrajectoryTask, BadTrajectoriesAreRefusedWholeAndTheOldOneStaysInForce) {
    cruiseEast();
    const Pt pts[2] = {{0.0, 0.0}, {1.0, 0.0}};
    msg::TrajectoryMsg bad[5] = {trajectory(30, 0.3, pts, 2), trajectory(0, 0.3, pts, 2),
                                 trajectory(32, std::nan(""), pts, 2), trajectory(33, -0.1, pts, 2),
                                 trajectory(34, 0.3, pts, 2)};
    bad[0].count = msg::kMaxTrajectoryPoints + 1;
    bad[4].points[1].yM = INFINITY;
    for (const msg::TrajectoryMsg& t : bad) {
        CHECK_TRUE(Status::kOk == bus.publish(t));
        runFrame();
        CHECK_TRUE(FollowerState::kFollowing == task.state());
        LONGS_EQUAL(1, task.latestStatus().trajectoryId);
        CHECK_TRUE(FollowReason::kBadTrajectory == task.latestStatus().reason);
    }
    // One that does not decode (short).
    const std::uint8_t junk[8] = {};
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kTrajectory, junk, sizeof junk));
    runFrame();
    LONGS_EQUAL(6, task.counters().trajectoriesRefused);
    LONGS_EQUAL(1, task.counters().trajectoriesAccepted);
    LONGS_EQUAL(3, eventsWithId(ev::kTrajectoryRefused));  // 1st, 2nd, 4th
    CHECK_TRUE(FollowReason::kBadTrajectory == lastStatus.reason);
    DOUBLES_EQUAL(0.3, v, 1e-9);  // still cruising on trajectory 1
    // A non-finite point beyond count is not part of the trajectory.
    const Pt here[2] = {{x, y}, {x + 1.0, y}};
    msg::TrajectoryMsg fine = trajectory(35, 0.3, here, 2);
    fine.points[5].xM = std::nan("");
    CHECK_TRUE(Status::kOk == bus.publish(fine));
    runFrame();
    LONGS_EQUAL(35, task.latestStatus().trajectoryId);
    CHECK_TRUE(FollowReason::kNone == task.latestStatus().reason);
    runUntil(FollowerState::kReached, 2000);
}

TEST(TrajectoryTask, MalformedPoseModeAndDriveStatusAreCountedEventedAndIgnored) {
    cruiseEast();
    const std::uint8_t junk[8] = {};
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kPoseEstimate, junk, sizeof junk));
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kMode, junk, sizeof junk));
    CHECK_TRUE(Status::kOk == bus.publish(msg::ids::kDriveStatus, junk, sizeof junk));
    runFrame();
    LONGS_EQUAL(3, task.counters().malformedInputs);
    LONGS_EQUAL(2, eventsWithId(ev::kFollowerInputMalformed));  // 1st and 2nd; the 3rd throttled
    CHECK_TRUE(FollowerState::kFollowing == task.state());
    // A pose with NaN and a mode beyond MANUAL are not used either.
    posePublishing = false;
    msg::PoseEstimateMsg p{};
    p.timeNs = clock.now();
    p.xM = std::nan("");
    p.initialised = 1;
    CHECK_TRUE(Status::kOk == bus.publish(p));
    publishMode(9);
    runFrame();
    posePublishing = true;
    LONGS_EQUAL(5, task.counters().malformedInputs);
    LONGS_EQUAL(1, eventsWithId(ev::kFollowerInputMalformed));  // the 4th
    CHECK_TRUE(task.autonomous());
    CHECK_TRUE(FollowerState::kFollowing == task.state());
    runFrames(10);
    CHECK_TRUE(FollowerState::kFollowing == task.state());
}

TEST(TrajectoryTask, StatusIsPublishedOnEveryChangeAndAtTenHertz) {
    const unsigned start = statusesTotal;
    runFrames(100);
    LONGS_EQUAL(start + 10, statusesTotal);  // idle: every 10th run
    const Pt pts[2] = {{0.0, 0.0}, {1.0, 0.0}};
    send(40, 0.3, pts, 2);
    runFrame();
    LONGS_EQUAL(1, statusesThisFrame);  // id and state changed
    CHECK_TRUE(FollowerState::kFollowing == lastStatus.state);
    LONGS_EQUAL(40, lastStatus.trajectoryId);
    DOUBLES_EQUAL(task.latestStatus().commandedSpeedMS, lastStatus.commandedSpeedMS, 0.0);
    CHECK_TRUE(lastStatus.commandedSpeedMS > 0.0);
    DOUBLES_EQUAL(1.0, lastStatus.remainingM, 1e-6);
    LONGS_EQUAL(1, lastStatus.targetIndex);
    const unsigned beforeReach = statusesTotal;
    const int frames = runUntil(FollowerState::kReached, 2000);
    LONGS_EQUAL(1, statusesThisFrame);
    CHECK_TRUE(FollowerState::kReached == lastStatus.state);
    // The change, plus one per 10 runs on the way.
    CHECK_TRUE(statusesTotal - beforeReach >= static_cast<unsigned>(frames / 10));
    CHECK_TRUE(statusesTotal - beforeReach <= static_cast<unsigned>(frames / 10 + 1));
}

TEST(TrajectoryTask, TablesAreReadEveryRun) {
    cruiseEast();
    tables::RoverGeometryTable g = tables.roverGeometry();
    g.max_body_speed_m_s = 0.15F;
    std::uint8_t image[tables::kMaxTableImageSize] = {};
    const std::size_t length = tables::encodeTable(g, 2, image, sizeof image);
    CHECK_TRUE(length > 0);
    CHECK_TRUE(tables::TableReject::kNone ==
               tables.loadChunk(tables::TableId::kRoverGeometry, 0, image, length).reason);
    CHECK_TRUE(tables::TableReject::kNone == tables.validate(tables::TableId::kRoverGeometry).reason);
    CHECK_TRUE(tables::TableReject::kNone == tables.activate(tables::TableId::kRoverGeometry).reason);
    tables.run(core::FrameContext{});
    // A lowered limit wins at once over the slew (skidSteerWheelSpeeds would cut it anyway).
    speedLimit = 0.15 + 1e-7;
    skipAccelCheckOnce = true;
    runFrame();
    DOUBLES_EQUAL(0.15, v, 1e-6);
    runFrames(100);
    DOUBLES_EQUAL(0.15, v, 1e-6);
}

TEST(TrajectoryTask, AContactStopsTheWheelsInTheFrameItIsFeltAndBacksOffBeforeGivingUp) {
    cruiseEast();
    const double feltAt = x;
    blocked = true;         // the rover meets a rock: it stops, the wheels slip, the current jumps
    wheelCurrentA = 7.5;
    skipAccelCheckOnce = true;  // the contact zeroes at once, as every give-up
    runFrame();
    LONGS_EQUAL(1, task.counters().contacts);
    CHECK_TRUE(task.state() == FollowerState::kCannotFollow);   // the follower's own state
    CHECK_TRUE(lastStatus.state == FollowerState::kBackingOff);  // what it reports while backing off
    CHECK_TRUE(lastStatus.reason == FollowReason::kContact);
    DOUBLES_EQUAL(0.0, v, 0.0);  // not pushing any more: zero in the frame it is felt
    LONGS_EQUAL(1, eventsWithId(reflexive::events::kContactSeen));
    blocked = false;
    wheelCurrentA = 1.4;
    int frames = 0;
    while (lastStatus.state == FollowerState::kBackingOff && frames < 1000) {
        runFrame();
        ++frames;
        CHECK(v <= 0.0);
    }
    CHECK_TRUE(lastStatus.state == FollowerState::kCannotFollow);
    CHECK_TRUE(lastStatus.reason == FollowReason::kContact);
    const double backoff = static_cast<double>(tables.follower().contact_backoff_m);
    CHECK(feltAt - x >= backoff - 0.005);
    CHECK(feltAt - x <= backoff + 0.01);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().backoffs);
    LONGS_EQUAL(0, task.counters().backoffsCut);
    LONGS_EQUAL(1, eventsWithId(reflexive::events::kBackedOff));
    // The status (DRIVES telemetry) says so, published the run it ended.
    LONGS_EQUAL(1, lastStatus.backoffs);
    LONGS_EQUAL(0, lastStatus.backoffsCut);
    LONGS_EQUAL(static_cast<int>(reflexive::BackoffEnd::kDistance), lastStatus.lastBackoffEnd);
    LONGS_EQUAL(0, lastStatus.contactsUnplaced);
    runFrames(100);
    CHECK_TRUE(commandIsZero());
    LONGS_EQUAL(1, task.counters().contacts);  // standing still is no contact
}

TEST(TrajectoryTask, ANewTrajectoryDuringTheBackoffEndsItAndIsFollowed) {
    cruiseEast();
    wheelCurrentA = 7.5;
    skipAccelCheckOnce = true;
    runFrame();
    wheelCurrentA = 1.4;
    runFrames(20);
    CHECK_TRUE(lastStatus.state == FollowerState::kBackingOff);
    const Pt pts[2] = {{x, y}, {x, y + 10.0}};
    skipAccelCheckOnce = true;
    send(2, 0.3, pts, 2);
    runFrame();
    LONGS_EQUAL(1, task.counters().backoffs);
    LONGS_EQUAL(1, task.counters().backoffsCut);  // superseded
    CHECK_TRUE(lastStatus.state != FollowerState::kBackingOff);
    LONGS_EQUAL(1, lastStatus.backoffsCut);
    LONGS_EQUAL(static_cast<int>(reflexive::BackoffEnd::kSuperseded), lastStatus.lastBackoffEnd);
}

TEST(TrajectoryTask, NoHeapAllocationOverThousandsOfRuns) {
    const std::uint8_t junk[8] = {};
    test::AllocationWatch watch;
    for (std::uint32_t round = 0; round < 3; ++round) {
        const Pt l[3] = {{x, y}, {x + 2.0, y}, {x + 2.0, y + 2.0}};
        send(100 + round, 0.3, l, 3);
        runFrames(2000);  // reached
        CHECK_TRUE(bus.publish(msg::ids::kTrajectory, junk, sizeof junk) == Status::kOk);
        const Pt back[2] = {{x, y}, {x - 2.0, y + 1.0}};
        send(200 + round, 0.3, back, 2);  // turn in place, then drive
        runFrames(500);
        sendStop(300 + round);
        runFrames(300);
        const Pt ahead[2] = {{x, y}, {x + 5.0, y}};
        send(400 + round, 0.3, ahead, 2);
        runFrames(100);
        y += 2.0;  // cross-track give-up
        runFrames(10);
    }
    LONGS_EQUAL(0, watch.count());
    CHECK_TRUE(task.counters().runs > 6000);
    LONGS_EQUAL(9, task.counters().trajectoriesAccepted);
    LONGS_EQUAL(3, task.counters().reached);
    LONGS_EQUAL(3, task.counters().gaveUpCrossTrack);
    LONGS_EQUAL(3, task.counters().trajectoriesRefused);
    CHECK_TRUE(task.follower().turnsInPlace() >= 3);
}
