// Writes housekeeping summaries and events to a console stream (the operator's
// view when no ground tool is attached, and the demo's output). Telemetry output
// is the event log's primary reader; the console reads with its own cursor, so
// a quiet or slow console never costs the ground an event. A housekeeping
// message that does not decode is counted (malformed(), in rse-fsw's summary)
// and evented (211) by its input pipe, never printed.
#pragma once

#include <cstdio>

#include "fsw/core/event_log.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/software_bus.hpp"
#include "fsw/msg/housekeeping_msg.hpp"

namespace rse::cmdtlm {

class ConsoleTask final : public core::Task {
public:
    // events: the log it reads (with its own cursor) and reports a malformed input to.
    ConsoleTask(core::SoftwareBus& bus, core::EventLog& events);

    // Creates and subscribes the task's pipe; stream may be nullptr (quiet).
    core::Status init(std::FILE* stream);
    void run(const core::FrameContext& frame) override;
    // Writes out every queued event and housekeeping message (bounded by the
    // event ring and pipe depths).
    void drain();

    std::uint32_t housekeepingSeen() const { return housekeepingSeen_; }
    std::uint32_t eventsWritten() const { return eventsWritten_; }
    std::uint32_t malformed() const { return input_.malformed(); }
    std::uint32_t eventsMissed() const { return cursor_.lost; }

private:
    static constexpr std::uint16_t kPipeDepth = 4;

    void writeHousekeeping(const msg::HousekeepingMsg& hk);

    const core::EventLog& events_;
    core::InputPipe input_;
    core::EventLog::Cursor cursor_{};
    std::FILE* stream_ = nullptr;
    std::uint32_t housekeepingSeen_ = 0;
    std::uint32_t eventsWritten_ = 0;
};

}  // namespace rse::cmdtlm
