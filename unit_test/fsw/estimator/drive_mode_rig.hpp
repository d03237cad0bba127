// Test-only: the drive mode task on a real software bus, a virtual clock and the
// default tables, fed one DriveStatusMsg per frame from a DriveModel, plus a
// seeded driving profile (speed changes, turns both ways, turns in place, stops).
#pragma once

#include <cstdint>
#include <random>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/estimator/drive_mode_task.hpp"
#include "fsw/tables/default_tables.hpp"
#include "fsw/tables/table_service.hpp"
#include "unit_test/fsw/estimator/drive_model.hpp"

namespace rse::test {

class DriveModeRig {
public:
    explicit DriveModeRig(std::uint64_t seed, double currentSigmaA = 0.03)
        : events(clock), bus(clock, events), tables(events), task(bus, events, tables), drives(seed, currentSigmaA) {}

    // Tables and task; drains the start-up events so tests see only their own.
    bool init() {
        if (!core::isOk(tables.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount))) {
            return false;
        }
        if (!core::isOk(bus.createPipe("listener", 4, &listener)) ||
            !core::isOk(bus.subscribe(listener, msg::ids::kDriveModes))) {
            return false;
        }
        if (!core::isOk(task.init())) {
            return false;
        }
        core::Event e;
        while (core::isOk(events.pop(&e))) {
        }
        return true;
    }

    // One minor frame as the executive runs it: tables first, the status as CAN
    // I/O publishes it, then the task.
    void frame() {
        const msg::DriveStatusMsg status = drives.step();
        lastStatus = status;
        clock.sleepUntil(status.timeNs);
        const core::FrameContext context = nextContext();
        tables.run(context);
        (void)bus.publish(status);
        task.run(context);
        drainListener();
    }
    // A frame whose bus input is given (malformed or hand-made).
    void frameWith(const void* payload, std::size_t length) {
        clock.advance(DriveModel::kFrame);
        const core::FrameContext context = nextContext();
        tables.run(context);
        (void)bus.publish(msg::ids::kDriveStatus, payload, length);
        task.run(context);
        drainListener();
    }
    // A frame in which no drive status arrives.
    void frameWithoutStatus() {
        clock.advance(DriveModel::kFrame);
        const core::FrameContext context = nextContext();
        tables.run(context);
        task.run(context);
        drainListener();
    }
    void runFor(core::TimeNs duration) {
        const core::TimeNs end = clock.now() + duration;
        while (clock.now() < end) {
            frame();
        }
    }

    msg::DriveStatusMsg lastStatus{};  // what frame() published last
    std::uint32_t published = 0;        // DriveModesMsg seen on the bus
    msg::DriveModesMsg lastPublished{};

    core::VirtualClock clock;
    core::EventLog events;
    core::SoftwareBus bus;
    tables::TableService tables;
    estimator::DriveModeTask task;
    DriveModel drives;
    core::PipeId listener = 0;

private:
    core::FrameContext nextContext() {
        core::FrameContext c;
        c.frame = frames_++;
        c.slot = static_cast<std::uint32_t>(c.frame % 100);
        c.scheduledStart = clock.now();
        c.actualStart = clock.now();
        return c;
    }
    void drainListener() {
        core::Message m;
        while (core::isOk(bus.receive(listener, &m))) {
            if (core::isOk(m.decode(&lastPublished))) {
                ++published;
            }
        }
    }
    std::uint64_t frames_ = 0;
};

// Segments of 2..10 s: 10 % stopped, 10 % turning in place, else driving forward
// or (1 in 5) backward at 0.5..3.5 rad/s with a left/right difference of up to
// +-1.2 rad/s. Targets change as steps, the hardest case for the lag.
class DriveProfile {
public:
    explicit DriveProfile(std::uint64_t seed) : rng_(seed ^ 0xD21FEULL) {}

    void apply(core::TimeNs now, DriveModel* drives) {
        if (now >= segmentEnd_) {
            next();
            segmentEnd_ = now + static_cast<core::TimeNs>(seconds_ * 1e9);
            drives->command(left_, right_);
        }
    }

private:
    void next() {
        std::uniform_real_distribution<double> u(0.0, 1.0);
        const double kind = u(rng_);
        seconds_ = 2.0 + 8.0 * u(rng_);
        if (kind < 0.1) {
            left_ = right_ = 0.0;
        } else if (kind < 0.2) {
            const double spin = 0.5 + 1.0 * u(rng_);
            left_ = u(rng_) < 0.5 ? -spin : spin;
            right_ = -left_;
        } else {
            const double speed = (0.5 + 3.0 * u(rng_)) * (u(rng_) < 0.2 ? -1.0 : 1.0);
            const double diff = -1.2 + 2.4 * u(rng_);
            left_ = speed - 0.5 * diff;
            right_ = speed + 0.5 * diff;
        }
    }

    std::mt19937_64 rng_;
    core::TimeNs segmentEnd_ = 0;
    double seconds_ = 0.0;
    double left_ = 0.0;
    double right_ = 0.0;
};

}  // namespace rse::test
