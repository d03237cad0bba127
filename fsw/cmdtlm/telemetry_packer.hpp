// What an application implements to own one family of telemetry packets (a
// cFS app's HK packet, an F' component's channels): the bus messages its data
// arrives in, and when each packet goes. The telemetry task (telemetry_task.hpp)
// schedules every registered packer and knows no packet itself:
//   start-up    routeInputs(): the packer routes the bus messages it reads on
//               the telemetry task's one input pipe (pipe.route<&P::takeX>(this)),
//               keeping the latest of each (a message that does not decode, or
//               whose handler refuses it, leaves the last good one in place)
//   every run   the pipe is drained (each message to the packers that routed
//               its id), the events go down, then each packer's pack() in
//               registration order: it sends what is due (its slot of the
//               second, a change, a request)
// A packer that must send on receipt (one packet per message) is given its
// sink when it is built.
#pragma once

#include "fsw/cmdtlm/telemetry_sink.hpp"
#include "fsw/core/executive.hpp"
#include "fsw/core/input_pipe.hpp"
#include "fsw/core/status.hpp"

namespace rse::cmdtlm {

class TelemetryPacker {
public:
    // Start-up, once: route the inputs on the telemetry task's pipe.
    virtual core::Status routeInputs(core::InputPipe& pipe) = 0;
    // Every telemetry run (every minor frame): send what is due.
    virtual void pack(const core::FrameContext& frame, TelemetrySink& sink) = 0;

protected:
    ~TelemetryPacker() = default;
};

}  // namespace rse::cmdtlm
