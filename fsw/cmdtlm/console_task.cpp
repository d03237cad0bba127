#include "fsw/cmdtlm/console_task.hpp"

#include "fsw/cmdtlm/cmdtlm_events.hpp"

namespace rse::cmdtlm {

namespace {

double seconds(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(core::kNsPerSec); }

}  // namespace

ConsoleTask::ConsoleTask(core::SoftwareBus& bus, core::EventLog& events)
    : events_(events),
      input_(bus, events, core::InputPipeConfig{"console", kPipeDepth, events::kBusMessageMalformed, "console"}) {}

core::Status ConsoleTask::init(std::FILE* stream) {
    stream_ = stream;
    const core::Status status = input_.create();
    return core::isOk(status) ? input_.route<&ConsoleTask::writeHousekeeping>(this) : status;
}

void ConsoleTask::run(const core::FrameContext&) { drain(); }

void ConsoleTask::writeHousekeeping(const msg::HousekeepingMsg& hk) {
    ++housekeepingSeen_;
    if (stream_ != nullptr) {
        std::fprintf(stream_,
                     "[%10.3f] HK  #%u frames=%llu overruns=%u skipped=%u busy_max=%uus "
                     "late_max=%uus bus pub=%u drop=%u events=%u lost=%u\n",
                     seconds(hk.timeNs), static_cast<unsigned>(hk.housekeepingCount),
                     static_cast<unsigned long long>(hk.framesRun), static_cast<unsigned>(hk.frameOverruns),
                     static_cast<unsigned>(hk.framesSkipped), static_cast<unsigned>(hk.frameBusyMaxUs),
                     static_cast<unsigned>(hk.frameLatenessMaxUs), static_cast<unsigned>(hk.busPublished),
                     static_cast<unsigned>(hk.busDropped), static_cast<unsigned>(hk.eventsTotal),
                     static_cast<unsigned>(hk.eventsLost));
    }
}

void ConsoleTask::drain() {
    bool wrote = false;
    core::Event event;
    while (core::isOk(events_.read(&cursor_, &event))) {
        ++eventsWritten_;
        wrote = true;
        if (stream_ != nullptr) {
            std::fprintf(stream_, "[%10.3f] EVT %3u %-5s %s\n", seconds(event.time),
                         static_cast<unsigned>(event.id), core::toString(event.severity), event.text);
        }
    }
    const std::uint32_t seenBefore = housekeepingSeen_;
    (void)input_.drain();  // writeHousekeeping for each; bounded by the pipe's depth
    wrote = wrote || housekeepingSeen_ != seenBefore;
    if (wrote && stream_ != nullptr) {
        std::fflush(stream_);
    }
}

}  // namespace rse::cmdtlm
