// Regeneration's triggers and input (docs/plan_executive.md "Regeneration",
// "Component states"). Each run while the plan dispatches, every activity of
// the selection not yet done (waiting or running) whose component Ask no
// longer holds is dealt with (973): a running one failed (its device told to
// stop first), the option of a waiting one deprecated; the plan is then
// regenerated from where it stands (reason component failed). The other
// triggers are the dispatcher's: it holds (late, missed window, early
// inconsistent, failed), or an extension committed left the network out of
// its range. For each, the re-selection's input: the input of the selection
// in force with where execution stands (PlanDispatcher::regenerationInput),
// the components as now and the executive's deprecations kept; counted, its
// reason kept for PLAN_EXEC and evented (962). The selection itself is
// PlanAdoption's. No bus.
#pragma once

#include <cstdint>

#include "fsw/msg/plan_executive_msgs.hpp"
#include "fsw/plan_executive/activity_lifecycle.hpp"
#include "fsw/plan_executive/component_states.hpp"
#include "fsw/plan_executive/executive_context.hpp"
#include "fsw/plan_executive/method_selector.hpp"

namespace rse::plan_executive {

struct RegenerationCounters {
    std::uint32_t regenerations = 0;
    msg::PlanRegeneration last = msg::PlanRegeneration::kNone;
};

class PlanRegeneration {
public:
    PlanRegeneration(ExecutiveContext& ctx, const ComponentStates& components, ActivityLifecycle& lifecycle)
        : ctx_(ctx), components_(components), lifecycle_(lifecycle) {}

    // Activities not yet done that ask what a component no longer is: the
    // running ones failed, the waiting ones' options deprecated (973). True
    // when there were any: the plan is to be regenerated now.
    bool checkComponents();
    // A regeneration begins at nowMs: its input made from inForce's (the
    // selection in force's input), counted and evented (962, with the cost
    // before). The input stays valid until the next prepare().
    const SelectionInput& prepare(std::int32_t nowMs, const SelectionInput& inForce, double costBefore);
    // The input of the last regeneration prepared.
    const SelectionInput& input() const { return input_; }
    // A new plan: the executive has deprecated none of its options.
    void clearDeprecations();
    // Options deprecated among the first `choices` choices.
    std::uint32_t deprecatedCount(std::size_t choices) const;
    const RegenerationCounters& counters() const { return counters_; }

private:
    ExecutiveContext& ctx_;
    const ComponentStates& components_;
    ActivityLifecycle& lifecycle_;
    // Options the executive deprecated (a component they ask failed).
    bool deprecated_[kMaxChoices][kMaxOptions] = {};
    SelectionInput input_{};  // the regeneration's (under way, or last)
    bool forComponent_ = false;                   // the next regeneration is checkComponents'
    std::uint16_t componentActivity_ = kNoIndex;  // the first activity a component failure hit
    RegenerationCounters counters_{};
};

}  // namespace rse::plan_executive
