#include "fsw/core/input_pipe.hpp"

#include <cstdarg>
#include <cstdio>

namespace rse::core {

Status InputPipe::create() {
    if (created_) {
        return Status::kAlreadyExists;
    }
    const Status status = bus_.createPipe(config_.name, config_.depth, &pipe_);
    created_ = isOk(status);
    return status;
}

Status InputPipe::addRoute(MsgId id, void* owner, Deliver deliverFn) {
    if (!created_) {
        return Status::kNotInitialized;
    }
    if (owner == nullptr) {
        return Status::kInvalidArgument;
    }
    if (routeCount_ >= kMaxInputRoutes) {
        return Status::kNoCapacity;
    }
    bool subscribed = false;
    for (std::size_t i = 0; i < routeCount_; ++i) {
        subscribed = subscribed || routes_[i].id == id;
    }
    if (!subscribed) {
        const Status status = bus_.subscribe(pipe_, id);
        if (!isOk(status)) {
            return status;
        }
    }
    routes_[routeCount_++] = Route{id, owner, deliverFn};
    return Status::kOk;
}

std::uint16_t InputPipe::drain() {
    if (!created_) {
        return 0;
    }
    // The pipe never holds more than its depth, so this empties it.
    std::uint16_t count = 0;
    while (count < config_.depth && isOk(bus_.receive(pipe_, &inbox_))) {
        ++count;
        ++taken_;
        detail_[0] = '\0';
        const Status status = dispatch();
        if (!isOk(status)) {
            refuse(status);
        }
    }
    return count;
}

Status InputPipe::dispatch() {
    // Every route of the id gets the message; one refusal refuses it (counted
    // once). No route: the pipe is subscribed only to routed ids, so this is a
    // message nobody here takes (kWrongType, as a failed decode would be).
    bool routed = false;
    Status result = Status::kOk;
    for (std::size_t i = 0; i < routeCount_; ++i) {
        if (routes_[i].id != inbox_.header.id) {
            continue;
        }
        routed = true;
        const Status status = routes_[i].deliver(routes_[i].owner, inbox_, storage_);
        if (isOk(result)) {
            result = status;
        }
    }
    return routed ? result : Status::kWrongType;
}

void InputPipe::refuse(Status why) {
    ++malformed_;
    if (!isReportableOccurrence(malformed_)) {
        return;
    }
    // An event's text holds 95 characters: with a handler's explanation, the
    // id and what is wrong come first, the size and pipe are left out.
    if (detail_[0] != '\0') {
        events_.report(config_.malformedEvent, config_.severity, "%s: bus message 0x%04x refused: %s (%u so far)",
                       config_.owner, static_cast<unsigned>(inbox_.header.id), detail_,
                       static_cast<unsigned>(malformed_));
        return;
    }
    events_.report(config_.malformedEvent, config_.severity,
                   "%s: bus message 0x%04x (%u B) on pipe %s refused: %s (%u so far)", config_.owner,
                   static_cast<unsigned>(inbox_.header.id), static_cast<unsigned>(inbox_.header.length),
                   config_.name, toString(why), static_cast<unsigned>(malformed_));
}

void InputPipe::explain(const char* format, ...) {
    va_list args;
    va_start(args, format);
    (void)std::vsnprintf(detail_, sizeof detail_, format, args);
    va_end(args);
}

}  // namespace rse::core
