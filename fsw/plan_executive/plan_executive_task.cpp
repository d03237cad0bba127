#include "fsw/plan_executive/plan_executive_task.hpp"

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

PlanExecutiveTask::PlanExecutiveTask(core::SoftwareBus& bus, core::EventLog& events)
    : ctx_(bus, events),
      upload_(events),
      components_(events),
      devices_(ctx_),
      extension_(ctx_, devices_, *this),
      lifecycle_(ctx_, devices_, extension_),
      regeneration_(ctx_, components_, lifecycle_),
      adoption_(ctx_, components_, lifecycle_, regeneration_),
      goals_(ctx_, devices_, lifecycle_, adoption_),
      commandPipe_(bus, events, core::InputPipeConfig{"plan_exec", kPipeDepth, events::kMalformedInput, "plan_exec"}),
      inputs_(bus, events,
              core::InputPipeConfig{"plan_exec_in", kStatusPipeDepth, events::kMalformedInput, "plan_exec"}) {}

core::Status PlanExecutiveTask::init() {
    // The status pipe's ids are routed (and so subscribed) in the order they always were.
    core::Status status = commandPipe_.create();
    if (core::isOk(status)) {
        status = commandPipe_.route<&PlanExecutiveTask::takeCommand>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.create();
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeInstrument>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeDriveModes>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takePlanStatus>(this);
    }
    if (core::isOk(status)) {
        status = inputs_.route<&PlanExecutiveTask::takeGoalList>(this);
    }
    if (!core::isOk(status)) {
        ctx_.events.report(events::kInitFailed, core::Severity::kError, "plan_exec: init failed (%s)",
                           core::toString(status));
        return status;
    }
    ready_ = true;
    return core::Status::kOk;
}

void PlanExecutiveTask::run(const core::FrameContext& frame) {
    if (!ready_) {
        return;
    }
    ctx_.now = frame.scheduledStart;
    ++runs_;
    commandPipe_.drain();
    inputs_.drain();
    if (goals_.pending() && ctx_.job == SelectionJob::kNone) {
        goals_.begin();
    }
    if (ctx_.job != SelectionJob::kNone) {
        adoption_.stepSelection();
    }
    if (ctx_.checking) {
        adoption_.stepCheck();
    }
    if (dispatchDue()) {
        dispatch();
    }
    if (ctx_.changed || runs_ % kStatusPeriodRuns == 0) {
        ctx_.changed = false;
        publishStatus();
    }
}

// ---------------------------------------------------------------------------
// Inputs. A command whose kind or length is out of range, a status naming no
// instrument or a state or drive mode out of range, a goal list not usable:
// refused, counted and evented as malformed by the pipe.

core::Status PlanExecutiveTask::takeCommand(const msg::PlanCommandMsg& m) {
    if (static_cast<std::uint8_t>(m.kind) > static_cast<std::uint8_t>(msg::PlanCommandKind::kExtend) ||
        m.length > msg::kPlanChunkBytes) {
        return core::Status::kInvalidArgument;
    }
    switch (m.kind) {
        case msg::PlanCommandKind::kChunk: takeChunk(m); break;
        case msg::PlanCommandKind::kStart: startUpload(m); break;
        case msg::PlanCommandKind::kShort: startShort(m); break;
        case msg::PlanCommandKind::kAbort: adoption_.abort(false); break;
        case msg::PlanCommandKind::kExtend: extension_.request(m); break;
    }
    return core::Status::kOk;
}

core::Status PlanExecutiveTask::takeInstrument(const msg::InstrumentStatusMsg& m) {
    if (static_cast<std::size_t>(m.instrument) >= msg::kInstrumentCount ||
        static_cast<std::uint8_t>(m.state) > static_cast<std::uint8_t>(msg::InstrumentState::kFailed)) {
        return core::Status::kInvalidArgument;
    }
    devices_.record(m);
    if (components_.takeInstrument(m)) {
        ctx_.changed = true;
    }
    lifecycle_.takeInstrument(m);
    return core::Status::kOk;
}

core::Status PlanExecutiveTask::takeDriveModes(const msg::DriveModesMsg& m) {
    for (std::size_t w = 0; w < msg::kWheelCount; ++w) {
        if (static_cast<std::uint8_t>(m.drives[w].declared) >= msg::kDriveModeCount) {
            return core::Status::kInvalidArgument;
        }
    }
    if (components_.takeDriveModes(m)) {
        ctx_.changed = true;
    }
    return core::Status::kOk;
}

void PlanExecutiveTask::takePlanStatus(const msg::PlanStatusMsg& m) { lifecycle_.takePlanStatus(m); }

core::Status PlanExecutiveTask::takeGoalList(const msg::GoalListMsg& m) {
    if (!msg::goalListUsable(m)) {
        return core::Status::kInvalidArgument;
    }
    goals_.take(m);
    return core::Status::kOk;
}

void PlanExecutiveTask::takeChunk(const msg::PlanCommandMsg& m) {
    const UploadVerdict v = upload_.takeChunk(m);
    if (!v.taken()) {
        adoption_.refuse(v.refusal, events::kUploadRefused, v.detail);
        return;
    }
    ctx_.changed = true;
}

void PlanExecutiveTask::startUpload(const msg::PlanCommandMsg& m) {
    if (ctx_.job != SelectionJob::kNone) {
        adoption_.refuse(msg::PlanRefusal::kBusy, events::kUploadRefused, "PLAN_START while a selection is under way");
        return;
    }
    const UploadVerdict v = upload_.checkStart(m);
    if (!v.taken()) {
        adoption_.refuse(v.refusal, events::kUploadRefused, v.detail);
        return;
    }
    adoption_.beginNewPlan(upload_.text(), upload_.length(), false);
}

// The short form's text is parsed where it is (the pipe's copy of the
// command): the upload buffer is not touched.
void PlanExecutiveTask::startShort(const msg::PlanCommandMsg& m) {
    if (ctx_.job != SelectionJob::kNone) {
        adoption_.refuse(msg::PlanRefusal::kBusy, events::kUploadRefused, "PLAN_SHORT while a selection is under way");
        return;
    }
    adoption_.beginNewPlan(m.data, m.length, false);
}

// ---------------------------------------------------------------------------
// Dispatch.

// Not while the dispatcher's check runs, nor while a regeneration's selection
// runs (no activity starts from the old selection; completions are still
// taken as they come). A plan with nothing to run is complete when its check
// ends: seen here too.
bool PlanExecutiveTask::dispatchDue() const {
    const DispatchPhase phase = ctx_.dispatcher.phase();
    return !ctx_.checking && ctx_.state != msg::PlanExecutiveState::kRegenerating &&
           (phase == DispatchPhase::kDispatching || phase == DispatchPhase::kHolding ||
            (ctx_.dispatcher.complete() && ctx_.state == msg::PlanExecutiveState::kDispatching));
}

void PlanExecutiveTask::dispatch() {
    const std::int32_t nowMs = ctx_.planMs();
    if (ctx_.job == SelectionJob::kNone && ctx_.state == msg::PlanExecutiveState::kDispatching &&
        regeneration_.checkComponents()) {
        startRegeneration(nowMs);
        return;
    }
    if (lifecycle_.advance(nowMs)) {
        return;  // complete
    }
    if (ctx_.dispatcher.regenerationNeeded() && ctx_.job == SelectionJob::kNone) {
        if (ctx_.goalPlan) {
            goals_.stop();
        } else {
            startRegeneration(nowMs);
        }
    }
}

void PlanExecutiveTask::startRegeneration(std::int32_t nowMs) { adoption_.startRegeneration(nowMs); }

// ---------------------------------------------------------------------------
// Status.

void PlanExecutiveTask::publishStatus() {
    StatusFigures f;
    f.timeNs = ctx_.now;
    f.state = ctx_.state;
    f.selectionStatus = adoption_.selectionStatus();
    f.cost = adoption_.cost();
    f.costBefore = adoption_.costBefore();
    f.plans = adoption_.counters();
    f.activities = lifecycle_.counters();
    f.regeneration = regeneration_.counters();
    f.extensions = extension_.counters();
    StatusPlanView v;
    if (ctx_.planLoaded) {
        v.plan = &ctx_.plan();
        v.selection = &adoption_.selection();
        v.dispatcher = &ctx_.dispatcher;
        v.planMs = ctx_.planMs();
        v.deprecatedCount = regeneration_.deprecatedCount(ctx_.plan().choiceCount);
    }
    status_.publish(ctx_, f, v);
}

}  // namespace rse::plan_executive
