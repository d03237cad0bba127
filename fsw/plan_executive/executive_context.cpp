#include "fsw/plan_executive/executive_context.hpp"

namespace rse::plan_executive {

std::int32_t ExecutiveContext::planMs() const {
    const core::TimeNs t = (now - planStartNs) / core::kNsPerMs;
    if (t <= 0) {
        return 0;
    }
    return t > kMaxBoundMs ? kMaxBoundMs : static_cast<std::int32_t>(t);
}

}  // namespace rse::plan_executive
