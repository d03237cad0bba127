#include "fsw/app/console_task.hpp"

#include "fsw/msg/housekeeping_msg.hpp"

namespace rse::app {

namespace {

double seconds(core::TimeNs t) { return static_cast<double>(t) / static_cast<double>(core::kNsPerSec); }

}  // namespace

core::Status ConsoleTask::init(std::FILE* stream) {
    stream_ = stream;
    core::Status status = bus_.createPipe("console", kPipeDepth, &pipe_);
    if (!core::isOk(status)) {
        return status;
    }
    return bus_.subscribe(pipe_, msg::ids::kHousekeeping);
}

void ConsoleTask::run(const core::FrameContext&) { drain(); }

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
    while (core::isOk(bus_.receive(pipe_, &inbox_))) {
        msg::HousekeepingMsg hk;
        if (!core::isOk(inbox_.decode(&hk))) {
            ++malformed_;  // not our layout: counted (and visible in the summary), never printed
            continue;
        }
        ++housekeepingSeen_;
        wrote = true;
        if (stream_ != nullptr) {
            std::fprintf(stream_,
                         "[%10.3f] HK  #%u frames=%llu overruns=%u skipped=%u busy_max=%uus "
                         "late_max=%uus bus pub=%u drop=%u events=%u lost=%u\n",
                         seconds(hk.timeNs), static_cast<unsigned>(hk.housekeepingCount),
                         static_cast<unsigned long long>(hk.framesRun),
                         static_cast<unsigned>(hk.frameOverruns), static_cast<unsigned>(hk.framesSkipped),
                         static_cast<unsigned>(hk.frameBusyMaxUs),
                         static_cast<unsigned>(hk.frameLatenessMaxUs),
                         static_cast<unsigned>(hk.busPublished), static_cast<unsigned>(hk.busDropped),
                         static_cast<unsigned>(hk.eventsTotal), static_cast<unsigned>(hk.eventsLost));
        }
    }
    if (wrote && stream_ != nullptr) {
        std::fflush(stream_);
    }
}

}  // namespace rse::app
