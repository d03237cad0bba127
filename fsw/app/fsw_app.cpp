#include "fsw/app/fsw_app.hpp"

#include <ctime>

#include "fsw/app/app_events.hpp"
#include "fsw/tables/default_tables.hpp"

namespace rse::app {

namespace {

// UTC (Unix seconds) at mission elapsed time zero: the time correlation that
// HK carries so ground can turn packet times into UTC.
double utcAtMetZero(const core::Clock& clock) {
    timespec now{};
    if (clock_gettime(CLOCK_REALTIME, &now) != 0) {
        return 0.0;
    }
    return static_cast<double>(now.tv_sec) + static_cast<double>(now.tv_nsec) * 1e-9 -
           static_cast<double>(clock.now()) / static_cast<double>(core::kNsPerSec);
}

// A duration in microseconds with a decimal, as the summary prints it.
double toUs(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(core::kNsPerUs); }

}  // namespace

FswApp::FswApp(core::Clock& clock, hal::CanBus& can)
    : clock_(clock),
      events_(clock),
      bus_(clock, events_),
      executive_(clock, events_),
      tables_(events_),
      telemetryOutput_(clock, events_, groundLinks_),
      mode_(clock, bus_, events_),
      router_(bus_, events_, mode_),
      commands_(clock, events_, groundLinks_, telemetryOutput_, router_),
      housekeeping_(executive_, bus_, events_),
      housekeepingTelemetry_(housekeeping_),
      serviceCommands_(cmdtlm::ServiceCommands::Parts{events_, bus_, executive_, telemetryOutput_, commands_, router_,
                                                      mode_, housekeepingTelemetry_}),
      executiveCommands_(executive_, events_),
      goalCommands_(clock, bus_, events_, tables_),
      mobilityCommands_(clock, bus_, mode_),
      tableTelemetry_(tables_),
      tableCommands_(tables_, tableTelemetry_, telemetryOutput_),
      siteMap_(events_),
      siteMapTelemetry_(siteMap_),
      siteMapCommands_(siteMap_, siteMapTelemetry_, telemetryOutput_),
      planCommands_(clock, bus_),
      planTelemetry_(telemetryOutput_),
      canIo_(can, clock, bus_, events_, tables_),
      poseEstimator_(bus_, events_, tables_),
      driveModes_(bus_, events_, tables_),
      health_(bus_, events_, tables_, executive_),
      faultProtection_(bus_, events_, tables_),
      watchdog_(bus_, events_),
      telemetry_(bus_, events_, telemetryOutput_),
      manualDrive_(clock, bus_, events_, tables_),
      follower_(clock, bus_, events_, tables_),
      console_(bus_, events_),
      habitual_(bus_, events_, tables_, &siteMap_.map()),
      deliberative_(bus_, events_, tables_, &siteMap_.map()),
      planExecutive_(bus_, events_) {}

core::Status FswApp::addGroundLink(hal::PacketLink* link) { return groundLinks_.add(link); }

core::Status FswApp::initStep(core::Status status, const char* what) {
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical, "app: %s failed (%s)", what,
                       core::toString(status));
    }
    return status;
}

core::Status FswApp::checkKeys() const {
    // No key, no commanding: the public lab key is never a silent default.
    return commands_.keys().size() == 0 ? core::Status::kNotInitialized : core::Status::kOk;
}

core::Status FswApp::init(std::FILE* console) {
    // The start-up order: what a step needs is set up by the steps before it
    // (the tables first; every pipe a start-up announcement reaches, before
    // the announcements of the last step). The first failure is evented (201)
    // and ends it.
    const struct {
        const char* what;
        core::Status (*step)(FswApp&);
    } steps[] = {
        {"loading the default tables",
         [](FswApp& a) { return a.tables_.init(tables::kDefaultTableImages, tables::kDefaultTableImageCount); }},
        {"CAN I/O task init", [](FswApp& a) { return a.canIo_.init(); }},
        // Serviced by the CAN I/O task, in the frame that moves its bus frames.
        {"adding the CAN ground link",
         [](FswApp& a) {
             return a.groundLinks_.add(&a.canIo_.groundLink(), cmdtlm::GroundLinks::Service::kByOwner);
         }},
        {"command keys (none: --key-file FILE, or --lab-key in the lab)", [](FswApp& a) { return a.checkKeys(); }},
        {"pose estimator init", [](FswApp& a) { return a.poseEstimator_.init(); }},
        {"drive mode estimator init", [](FswApp& a) { return a.driveModes_.init(); }},
        {"health monitor init", [](FswApp& a) { return a.health_.init(); }},
        {"fault protection init", [](FswApp& a) { return a.faultProtection_.init(); }},
        {"watchdog task init", [](FswApp& a) { return a.watchdog_.init(); }},
        {"command service init", [](FswApp& a) { return a.commands_.init(); }},
        {"telemetry task init", [](FswApp& a) { return a.initTelemetry(); }},
        {"manual drive init", [](FswApp& a) { return a.manualDrive_.init(); }},
        {"trajectory follower init", [](FswApp& a) { return a.follower_.init(); }},
        {"habitual layer init", [](FswApp& a) { return a.habitual_.init(); }},
        {"deliberative layer init", [](FswApp& a) { return a.deliberative_.init(); }},
        {"plan executive init", [](FswApp& a) { return a.planExecutive_.init(); }},
        {"command owners init", [](FswApp& a) { return a.initCommandOwners(); }},
    };
    core::Status status = initStep(console_.init(console), "console task init");
    for (const auto& s : steps) {
        if (!core::isOk(status)) {
            return status;
        }
        status = initStep(s.step(*this), s.what);
    }
    if (!core::isOk(status)) {
        return status;
    }
    housekeepingTelemetry_.setUtcAtMetZero(utcAtMetZero(clock_));
    housekeepingTelemetry_.setTimeScale(timeScale_);
    reportTimeAndLinks();
    status = startExecutive();
    if (!core::isOk(status)) {
        return status;
    }
    events_.report(events::kAppStarted, core::Severity::kInfo,
                   "app: rse-fsw initialised, %zu tasks, %zu bytes reserved", executive_.taskCount(),
                   sizeof(FswApp));
    return core::Status::kOk;
}

core::Status FswApp::initTelemetry() {
    // The packers in the order their packets go within a frame (after the
    // events): HK and TASK_TIMING, DRIVES, ROVER_STATE and HEALTH,
    // FAULT_PROTECTION, INSTRUMENTS, PLAN_EXEC, POWER, HAZARDS, PLAN.
    cmdtlm::TelemetryPacker* const packers[] = {
        &housekeepingTelemetry_, &drivesTelemetry_, &estimatorTelemetry_, &faultProtectionTelemetry_,
        &instrumentsTelemetry_,  &planExecTelemetry_, &powerTelemetry_, &hazardsTelemetry_, &planTelemetry_,
    };
    // The owners of HK's fields.
    const cmdtlm::HousekeepingContributor* const contributors[] = {&commands_, &mode_, &canIo_, &tableTelemetry_,
                                                                   &telemetryOutput_};
    core::Status status = core::Status::kOk;
    for (cmdtlm::TelemetryPacker* packer : packers) {
        status = core::isOk(status) ? telemetry_.add(packer) : status;
    }
    for (const cmdtlm::HousekeepingContributor* contributor : contributors) {
        status = core::isOk(status) ? housekeepingTelemetry_.addContributor(contributor) : status;
    }
    return core::isOk(status) ? telemetry_.init() : status;
}

core::Status FswApp::initCommandOwners() {
    core::Status status = router_.init();
    // The onboard requests, on the router's pipe: call homes to the mode owner,
    // task restarts to the executive's commands.
    status = core::isOk(status) ? mode_.routeRequests(router_.requests()) : status;
    status = core::isOk(status) ? executiveCommands_.routeRequests(router_.requests()) : status;
    cmdtlm::AppCommands* const owners[] = {&serviceCommands_,   &goalCommands_, &mobilityCommands_, &tableCommands_,
                                           &executiveCommands_, &planCommands_, &siteMapCommands_};
    for (cmdtlm::AppCommands* owner : owners) {
        status = core::isOk(status) ? router_.add(owner) : status;
    }
    if (!core::isOk(status)) {
        return status;
    }
    // Every pipe exists now: announce the boot mode and the goal list (with
    // the planner table's default risk bound).
    mode_.announce();
    goalCommands_.init();
    return core::Status::kOk;
}

void FswApp::reportTimeAndLinks() {
    if (timeScale_ > 1) {
        events_.report(events::kTimeScaled, core::Severity::kWarning,
                       "app: time scale %u: mission time runs %u times slower than real time (lab only, never flight)",
                       static_cast<unsigned>(timeScale_), static_cast<unsigned>(timeScale_));
    }
    for (std::size_t i = 0; i < groundLinks_.size(); ++i) {
        events_.report(events::kGroundLinkOpened, core::Severity::kInfo,
                       "app: ground link %s: commands in, telemetry out", groundLinks_.at(i)->name());
    }
}

core::Status FswApp::startExecutive() {
    // The rate-group table. Divisors count 100 Hz minor frames (10 = 10 Hz,
    // 100 = 1 Hz); offsets spread tasks of one rate over different frames; budgets
    // are the longest acceptable run. Tables come first, so an activation lands
    // between frames and every task of a frame sees the same values. The
    // estimator, drive modes and health come right after the CAN I/O task, so
    // what they publish describes this frame's CAN inputs; fault protection
    // answers the health task's faults in the same frame; the follower comes
    // after them so it steers from this frame's pose. The habitual layer runs at
    // 10 Hz on its own offset, so its planning slice does not share a frame with
    // housekeeping or the console; the deliberative layer likewise on offset 7,
    // its planner sliced to about kSliceWork per run, the plan executive just
    // before it (what it asks of the deliberative layer is seen in the same
    // frame; its selection and network check sliced, plan_executive_task.hpp). The watchdog is fed last
    // in its frame, from what every task left behind. Command ingest has 2 ms: draining
    // a 100 000 packet/s flood of the UDP link takes 0.5-0.8 ms a frame (docs/icd.md
    // "Floods"); it is also timed in thread CPU time (cpu_timed), so an overrun it
    // caused can be told from one where it was off the CPU mid-run. The three
    // sliced planners (habitual RRT*, plan executive, deliberative) are CPU-timed
    // too: their slices are sized in work units to fit their budgets, and the
    // thread CPU time is what proves it (bench_plan_executive reads it in
    // lockstep, where the executive's clock is simulated); at 10 Hz the clock
    // costs about 11 us a second for the three. Keep docs/architecture.md in step.
    constexpr std::uint32_t kCommandBudgetUs = 2000;
    const core::RateGroupEntry table[] = {
        // name            task            divisor offset budget_us [cpu_timed]
        {"tables", &tables_, 1, 0, 200},
        {"can_io", &canIo_, 1, 0, 1000},
        {"estimator", &poseEstimator_, 1, 0, 300},
        {"drive_modes", &driveModes_, 1, 0, 200},
        {"health", &health_, 1, 0, 200},
        {"fault_prot", &faultProtection_, 1, 0, 200},
        {"follower", &follower_, 1, 0, 200},
        {"commands", &commands_, 1, 0, kCommandBudgetUs, true},
        {"manual_drive", &manualDrive_, 1, 0, 200},
        {"housekeeping", &housekeeping_, 100, 0, 500},
        {"telemetry", &telemetry_, 1, 0, 2000},
        {"console", &console_, 10, 1, 2000},
        {"habitual", &habitual_, 10, 5, 4000, true},
        {"plan_exec", &planExecutive_, 10, 7, 2000, true},
        {"deliberative", &deliberative_, 10, 7, 5000, true},
        {"watchdog", &watchdog_, 10, 3, 100},
    };
    commands_.setRunBudget(static_cast<core::TimeNs>(kCommandBudgetUs) * core::kNsPerUs);
    const core::ExecutiveConfig config{kMinorFramePeriod, kMinorFramesPerMajor};
    core::Status status = executive_.init(config, table, sizeof table / sizeof table[0]);
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical,
                       "app: rate-group table rejected (%s)", core::toString(status));
        return status;
    }
    status = protectEssentialRows();
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical,
                       "app: an essential task is not in the rate-group table (%s)", core::toString(status));
    }
    return status;
}

core::Status FswApp::protectEssentialRows() {
    // The rows EXEC_SET_TASK may not disable: found by task, not by position,
    // so reordering the table cannot unprotect one. Each must be in the table.
    const struct {
        const core::Task* task;
        cmdtlm::TaskCommandRefusal why;
    } essential[] = {
        {&commands_, cmdtlm::TaskCommandRefusal::kCommandIngest},
        {&canIo_, cmdtlm::TaskCommandRefusal::kCanIo},
        {&health_, cmdtlm::TaskCommandRefusal::kFaultDetection},
        {&faultProtection_, cmdtlm::TaskCommandRefusal::kFaultResponse},
    };
    for (const auto& e : essential) {
        core::Status status = core::Status::kNotFound;
        for (std::size_t row = 0; row < executive_.taskCount(); ++row) {
            if (executive_.entry(row)->task == e.task) {
                status = executiveCommands_.protectRow(row, e.why);
            }
        }
        if (!core::isOk(status)) {
            return status;
        }
    }
    return core::Status::kOk;
}

void FswApp::shutdown(const char* reason) {
    events_.report(events::kAppShutdown, core::Severity::kInfo, "app: %s, shutting down cleanly", reason);
    console_.drain();
}

void FswApp::printSummary(std::FILE* out) const {
    const core::ExecutiveStats& s = executive_.stats();
    std::fprintf(out, "rse-fsw summary: %llu frames run, %u overruns, %u skipped, busy max %lld us, "
                      "start lateness max %lld us\n",
                 static_cast<unsigned long long>(s.framesRun), static_cast<unsigned>(s.frameOverruns),
                 static_cast<unsigned>(s.framesSkipped), static_cast<long long>(s.maxBusy / core::kNsPerUs),
                 static_cast<long long>(s.maxLateness / core::kNsPerUs));
    // Columns are only ever added at the end: scripts read the first ones by position.
    std::fprintf(out, "  %-14s %8s %8s %9s %9s %9s %9s %9s %8s %9s %9s\n", "task", "runs", "over", "last_us",
                 "mean_us", "max_us", "host_mean", "host_max", "cpu_over", "cpu_mean", "cpu_max");
    for (std::size_t i = 0; i < executive_.taskCount(); ++i) {
        const core::RateGroupEntry* e = executive_.entry(i);
        const core::TaskStats* t = executive_.taskStats(i);
        std::fprintf(out, "  %-14s %8u %8u %9lld %9lld %9lld %9.1f %9.1f", e->name, static_cast<unsigned>(t->runs),
                     static_cast<unsigned>(t->overBudget), static_cast<long long>(t->last / core::kNsPerUs),
                     static_cast<long long>(t->mean() / core::kNsPerUs),
                     static_cast<long long>(t->max / core::kNsPerUs), toUs(t->hostMean()), toUs(t->hostMax));
        if (e->cpuTimed) {
            std::fprintf(out, " %8u %9.1f %9.1f\n", static_cast<unsigned>(t->cpuOverBudget), toUs(t->cpuMean()),
                         toUs(t->cpuMax));
        } else {
            std::fprintf(out, " %8s %9s %9s\n", "-", "-", "-");
        }
    }
    std::fprintf(out, "  (last/mean/max on the executive clock; host_* host wall time; cpu_* the task's thread CPU "
                      "time, rows timed in it only; in us. over/cpu_over: runs over budget on each)\n");
    const core::BusStats& b = bus_.stats();
    std::fprintf(out, "  bus: %u published, %u delivered, %u dropped, %u too large, %u unsubscribed\n",
                 static_cast<unsigned>(b.published), static_cast<unsigned>(b.delivered),
                 static_cast<unsigned>(b.dropped), static_cast<unsigned>(b.rejectedTooLarge),
                 static_cast<unsigned>(b.noSubscribers));
    const cmdtlm::CommandCounters& c = commands_.counters();
    std::fprintf(out,
                 "  commands: %u accepted, %u rejected; telemetry: %u packets sent, %u dropped "
                 "(%u acknowledgements, %u events, %u routine)\n",
                 static_cast<unsigned>(c.accepted), static_cast<unsigned>(c.rejected),
                 static_cast<unsigned>(telemetryOutput_.sent()), static_cast<unsigned>(telemetryOutput_.dropped()),
                 static_cast<unsigned>(telemetryOutput_.dropped(hal::TxPriority::kAck)),
                 static_cast<unsigned>(telemetryOutput_.dropped(hal::TxPriority::kEvent)),
                 static_cast<unsigned>(telemetryOutput_.dropped(hal::TxPriority::kRoutine)));
    std::fprintf(out,
                 "  ground links: %u packets read, %u dropped by a link, %u dropped by the OS (receive buffer "
                 "full); ingest at its limit in %u frames, %u rejection acks suppressed\n",
                 static_cast<unsigned>(c.linkRxPackets), static_cast<unsigned>(c.linkRxDropped),
                 static_cast<unsigned>(c.linkRxKernelDropped), static_cast<unsigned>(c.ingestLimited),
                 static_cast<unsigned>(c.acksSuppressed));
    std::fprintf(out,
                 "  command runs: %u stalled (a gap over %lld us between ingest's clock reads), %u over budget "
                 "less their stalls, longest less its stalls %u us\n",
                 static_cast<unsigned>(c.stalledRuns), static_cast<long long>(cmdtlm::kIngestStallGap / core::kNsPerUs),
                 static_cast<unsigned>(c.overBudgetLessStalls), static_cast<unsigned>(c.longestRunLessStallsUs));
    const io::CanGroundLink& can = canIo_.groundLink();
    if (can.downlinkActive()) {
        std::fprintf(out,
                     "  can-isotp downlink: %u packets completed, %u abandoned (%u without flow control), "
                     "%u first frames sent again\n",
                     static_cast<unsigned>(can.txCompleted()), static_cast<unsigned>(can.txAborted()),
                     static_cast<unsigned>(can.channel().stats().timeoutBs),
                     static_cast<unsigned>(can.channel().stats().ffResent));
    }
    if (console_.eventsMissed() > 0) {
        std::fprintf(out, "  console: %u events overwritten before it printed them\n",
                     static_cast<unsigned>(console_.eventsMissed()));
    }
    if (console_.malformed() > 0) {
        std::fprintf(out, "  console: %u malformed housekeeping messages ignored\n",
                     static_cast<unsigned>(console_.malformed()));
    }
    std::fprintf(out, "  events: %u total (%u warning, %u error, %u critical), %u lost\n",
                 static_cast<unsigned>(events_.total()),
                 static_cast<unsigned>(events_.count(core::Severity::kWarning)),
                 static_cast<unsigned>(events_.count(core::Severity::kError)),
                 static_cast<unsigned>(events_.count(core::Severity::kCritical)),
                 static_cast<unsigned>(events_.lost()));
}

}  // namespace rse::app
