#include "fsw/app/fsw_app.hpp"

#include "fsw/app/app_events.hpp"

namespace rse::app {

FswApp::FswApp(core::Clock& clock, hal::CanBus& can)
    : events_(clock),
      bus_(clock, events_),
      executive_(clock, events_),
      canIo_(can, clock, bus_, events_),
      housekeeping_(executive_, bus_, events_),
      console_(bus_, events_) {}

core::Status FswApp::init(std::FILE* console) {
    core::Status status = console_.init(console);
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical,
                       "app: console task init failed (%s)", core::toString(status));
        return status;
    }
    status = canIo_.init();
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical,
                       "app: CAN I/O task init failed (%s)", core::toString(status));
        return status;
    }

    // The rate-group table. Divisors count 100 Hz minor frames (10 = 10 Hz,
    // 100 = 1 Hz); offsets spread tasks of one rate over different frames; budgets
    // are the longest acceptable run. Keep docs/architecture.md in step.
    const core::RateGroupEntry table[] = {
        // name            task            divisor offset budget_us
        {"can_io", &canIo_, 1, 0, 1000},
        {"housekeeping", &housekeeping_, 100, 0, 500},
        {"console", &console_, 10, 1, 2000},
    };
    const core::ExecutiveConfig config{kMinorFramePeriod, kMinorFramesPerMajor};
    status = executive_.init(config, table, sizeof table / sizeof table[0]);
    if (!core::isOk(status)) {
        events_.report(events::kAppInitFailed, core::Severity::kCritical,
                       "app: rate-group table rejected (%s)", core::toString(status));
        return status;
    }
    events_.report(events::kAppStarted, core::Severity::kInfo,
                   "app: rse-fsw initialised, %zu tasks, %zu bytes reserved", executive_.taskCount(),
                   sizeof(FswApp));
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
    std::fprintf(out, "  %-14s %8s %8s %9s %9s %9s %9s %9s\n", "task", "runs", "over", "last_us", "mean_us",
                 "max_us", "cpu_mean", "cpu_max");
    for (std::size_t i = 0; i < executive_.taskCount(); ++i) {
        const core::RateGroupEntry* e = executive_.entry(i);
        const core::TaskStats* t = executive_.taskStats(i);
        std::fprintf(out, "  %-14s %8u %8u %9lld %9lld %9lld %9.1f %9.1f\n", e->name,
                     static_cast<unsigned>(t->runs), static_cast<unsigned>(t->overBudget),
                     static_cast<long long>(t->last / core::kNsPerUs),
                     static_cast<long long>(t->mean() / core::kNsPerUs),
                     static_cast<long long>(t->max / core::kNsPerUs),
                     static_cast<double>(t->hostMean()) / static_cast<double>(core::kNsPerUs),
                     static_cast<double>(t->hostMax) / static_cast<double>(core::kNsPerUs));
    }
    std::fprintf(out, "  (last/mean/max on the executive clock; cpu_* is host CPU time in us)\n");
    const core::BusStats& b = bus_.stats();
    std::fprintf(out, "  bus: %u published, %u delivered, %u dropped, %u too large, %u unsubscribed\n",
                 static_cast<unsigned>(b.published), static_cast<unsigned>(b.delivered),
                 static_cast<unsigned>(b.dropped), static_cast<unsigned>(b.rejectedTooLarge),
                 static_cast<unsigned>(b.noSubscribers));
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
