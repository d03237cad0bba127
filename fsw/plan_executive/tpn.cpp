#include "fsw/plan_executive/tpn.hpp"

namespace rse::plan_executive {

// The names are the plan text's spelling (docs/plan_executive.md).
const char* toString(ActivityKind k) {
    static const char* const kNames[kActivityKindCount] = {"drive", "sample", "image", "dig", "wait", "communicate"};
    const auto i = static_cast<std::size_t>(k);
    return i < kActivityKindCount ? kNames[i] : "?";
}

const char* toString(Component c) {
    static const char* const kNames[kComponentCount] = {"drive_FL", "drive_ML", "drive_RL", "drive_FR",
                                                        "drive_MR", "drive_RR", "grinder",  "camera"};
    const auto i = static_cast<std::size_t>(c);
    return i < kComponentCount ? kNames[i] : "?";
}

const char* toString(ComponentState s) {
    static const char* const kNames[kComponentStateCount] = {"ok", "degraded", "failed"};
    const auto i = static_cast<std::size_t>(s);
    return i < kComponentStateCount ? kNames[i] : "?";
}

}  // namespace rse::plan_executive
