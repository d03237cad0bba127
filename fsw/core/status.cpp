#include "fsw/core/status.hpp"

namespace rse::core {

const char* toString(Status status) {
    switch (status) {
        case Status::kOk: return "ok";
        case Status::kFull: return "full";
        case Status::kEmpty: return "empty";
        case Status::kTooLarge: return "too-large";
        case Status::kInvalidArgument: return "invalid-argument";
        case Status::kNotFound: return "not-found";
        case Status::kNoCapacity: return "no-capacity";
        case Status::kWrongType: return "wrong-type";
        case Status::kNotInitialized: return "not-initialized";
        case Status::kAlreadyExists: return "already-exists";
        case Status::kUnavailable: return "unavailable";
        case Status::kBusy: return "busy";
        case Status::kTimeout: return "timeout";
        case Status::kProtocolError: return "protocol-error";
    }
    return "unknown-status";
}

}  // namespace rse::core
