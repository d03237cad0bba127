// Test helper: the plan executive's parts wired as PlanExecutiveTask wires
// them, without its pipes, on a bus with a probe on what they publish (drive
// goals, instrument commands, safe requests) and the events counted. A test
// drives the parts directly: ctx.now is the run's time (tick() advances it by
// a run, 100 ms), adopt() runs a plan text to dispatching.
#pragma once

#include <cstdint>
#include <cstring>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/deliberative_msgs.hpp"
#include "fsw/msg/instrument_msgs.hpp"
#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_devices.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/component_states.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/goal_plan.hpp"
#include "fsw/plan_executive/plan_adoption.hpp"
#include "fsw/plan_executive/plan_extension.hpp"
#include "fsw/plan_executive/plan_regeneration.hpp"

namespace rse::test {

struct ExecutiveParts final : private plan_executive::RegenerationStarter {
    static constexpr core::TimeNs kRun = 100 * core::kNsPerMs;

    core::VirtualClock clock{0};
    core::EventLog events{clock};
    core::SoftwareBus bus{clock, events};
    plan_executive::ExecutiveContext ctx{bus, events};
    plan_executive::ComponentStates components{events};
    plan_executive::ActivityDevices devices{ctx};
    plan_executive::PlanExtension extension{ctx, devices, *this};
    plan_executive::ActivityLifecycle lifecycle{ctx, devices, extension};
    plan_executive::PlanRegeneration regeneration{ctx, components, lifecycle};
    plan_executive::PlanAdoption adoption{ctx, components, lifecycle, regeneration};
    plan_executive::GoalPlans goals{ctx, devices, lifecycle, adoption};

    core::PipeId probe = 0;
    core::Message inbox{};
    msg::PlanGoalMsg lastGoal{};
    std::uint32_t goalsSent = 0;
    msg::InstrumentCommandMsg lastInstrument{};
    std::uint32_t instrumentCommands = 0;
    std::uint32_t safeRequests = 0;
    std::uint32_t regenerationsStarted = 0;  // by the extension (RegenerationStarter)
    std::uint32_t seen[100] = {};            // events 950.. seen

    bool init() {
        return core::isOk(bus.createPipe("probe", 32, &probe)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kPlanGoal)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kInstrumentCommand)) &&
               core::isOk(bus.subscribe(probe, msg::ids::kSafeRequest));
    }
    // The next run's time.
    void tick(int runs = 1) {
        for (int i = 0; i < runs; ++i) {
            clock.advance(kRun);
            ctx.now = clock.now();
        }
    }
    // The text selected and adopted, its check done: dispatching (or not, when refused).
    bool adopt(const char* text) {
        adoption.beginNewPlan(text, std::strlen(text), false);
        for (int i = 0; i < 50 && ctx.job != plan_executive::SelectionJob::kNone; ++i) {
            adoption.stepSelection();
        }
        for (int i = 0; i < 50 && ctx.checking; ++i) {
            adoption.stepCheck();
        }
        drain();
        return ctx.planLoaded && ctx.state == msg::PlanExecutiveState::kDispatching &&
               ctx.dispatcher.phase() == plan_executive::DispatchPhase::kDispatching;
    }
    // A run of dispatch as the task does it (no component check): ticks first.
    bool advance() {
        tick();
        const bool complete = lifecycle.advance(ctx.planMs());
        drain();
        return complete;
    }
    void drain() {
        while (core::isOk(bus.receive(probe, &inbox))) {
            if (inbox.header.id == msg::ids::kPlanGoal && core::isOk(inbox.decode(&lastGoal))) {
                ++goalsSent;
            } else if (inbox.header.id == msg::ids::kInstrumentCommand && core::isOk(inbox.decode(&lastInstrument))) {
                ++instrumentCommands;
            } else if (inbox.header.id == msg::ids::kSafeRequest) {
                ++safeRequests;
            }
        }
        core::Event e;
        while (core::isOk(events.pop(&e))) {
            if (e.id >= 950 && e.id < 1050) {
                ++seen[e.id - 950];
            }
        }
    }
    std::uint32_t count(core::EventId id) const { return seen[id - 950]; }
    plan_executive::ActivityState state(std::uint16_t a) const { return ctx.dispatcher.state(a); }

    // An instrument's report on a command.
    msg::InstrumentStatusMsg instrumentStatus(msg::Instrument which, msg::InstrumentState s, std::uint16_t commandId) {
        msg::InstrumentStatusMsg m{};
        m.timeNs = clock.now();
        m.lastReportNs = clock.now();
        m.instrument = which;
        m.state = s;
        m.commandId = commandId;
        return m;
    }
    // As the task takes it: kept, the components, then the activities.
    void reportInstrument(const msg::InstrumentStatusMsg& m) {
        devices.record(m);
        components.takeInstrument(m);
        lifecycle.takeInstrument(m);
        drain();
    }

private:
    void startRegeneration(std::int32_t nowMs) override {
        ++regenerationsStarted;
        adoption.startRegeneration(nowMs);
    }
};

}  // namespace rse::test
