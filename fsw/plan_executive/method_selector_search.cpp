// The selector's search (method_selector.hpp "Search"): depth-first branch
// and bound over the choices in their order, each choice's options cheapest
// first, a branch pruned when its bound reaches the incumbent; a complete
// selection's plan-variable Asks checked for support (a Tell's end that
// precedes the Ask's start in every schedule) before it becomes the
// incumbent. One action a call, each bounded (kMaxActionWork).
#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/method_selector_detail.hpp"

namespace rse::plan_executive {

namespace {

// Whether a Tell (plan variable, value) answers an Ask.
bool tellSupports(const Condition& tell, const Condition& ask) {
    return tell.planVariable && tell.variable == ask.variable && (tell.value == ask.value) != ask.negated;
}

}  // namespace

void MethodSelector::searchAction() {
    switch (search_) {
        case SearchStep::kNextOption:
            nextOption();
            break;
        case SearchStep::kAddThread:
            threadAction();
            if (thread_ == ThreadState::kDone) {
                thread_ = ThreadState::kIdle;
                search_ = SearchStep::kDescend;
            } else if (thread_ == ThreadState::kFailed) {
                thread_ = ThreadState::kIdle;
                reject(RejectReason::kInconsistent);
                search_ = SearchStep::kNextOption;
            }
            break;
        case SearchStep::kDescend:
            descend();
            break;
        case SearchStep::kSupports:
            supportAction();
            break;
    }
}

void MethodSelector::nextOption() {
    ++stats_.work;
    if (depth_ == 0) {
        finish(best_.hasSelection ? SelectionStatus::kSelected : SelectionStatus::kNoneExists);
        return;
    }
    Level& level = level_[depth_ - 1];
    const std::size_t c = level.choice;
    if (level.applied != kNoOption) {
        // Leave the option tried last: its edges off (pi still meets the
        // rest), the choice undecided, the costs as they were.
        undoThread(group(c, level.applied));
        chosen_.option[c] = kNoOption;
        cost_ = level.costBefore;
        open_ = level.openBefore;
        level.applied = kNoOption;
        return;
    }
    // Options cheapest first (their subtree's cost; unusable ones last).
    // The bound: what is decided, this option's subtree and the other open
    // choices' cheapest. It grows with the rank, so the first option pruned
    // prunes the rest.
    const std::size_t options = plan_->choices[c].optionCount;
    if (level.next < options) {
        const std::uint8_t o = rankedOption_[c][level.next];
        const double cost = level.costBefore + optionOwn_[c][o];
        const double open = level.openBefore - choiceMin_[c] + (optionCost_[c][o] - optionOwn_[c][o]);
        if (!optionOk_[c][o] || (best_.hasSelection && cost + open >= best_.cost)) {
            for (std::size_t r = level.next; r < options; ++r) {
                stats_.prunedByBound += optionOk_[c][rankedOption_[c][r]] ? 1U : 0U;
            }
            level.next = static_cast<std::uint8_t>(options);
            return;
        }
        ++level.next;
        level.applied = o;
        chosen_.option[c] = o;
        cost_ = cost;
        open_ = open;
        ++stats_.nodes;
        beginThread(group(c, o));
        search_ = SearchStep::kAddThread;
        return;
    }
    --depth_;  // this choice is done; its parent's option is left next
}

void MethodSelector::descend() {
    std::size_t p = depth_ == 0 ? 0 : level_[depth_ - 1].pos + 1U;
    ++stats_.work;
    for (; p < choiceCount_; ++p) {
        ++stats_.work;
        const std::uint8_t c = order_[p];
        if (exists(plan_->choices[c].guard, chosen_)) {
            level_[depth_++] = Level{c, static_cast<std::uint8_t>(p), 0, kNoOption, cost_, open_};
            search_ = SearchStep::kNextOption;
            return;
        }
    }
    // Every existing choice is decided: a complete selection.
    search_ = SearchStep::kNextOption;
    if (best_.hasSelection && cost_ >= best_.cost) {
        ++stats_.prunedByBound;  // rounding let it through: no better than the incumbent
        return;
    }
    ++stats_.leaves;
    supportAsker_ = supportAsk_ = 0;
    search_ = SearchStep::kSupports;
}

bool MethodSelector::beginSupportCheck() {
    // The next plan-variable Ask of an existing activity; its candidate
    // supports: the end events of existing activities that Tell an answer.
    ++stats_.work;
    for (std::size_t i = 0; i < candidateCount_; ++i) {
        candidate_[candidateList_[i]] = false;
    }
    stats_.work += candidateCount_;
    candidateCount_ = 0;
    const Tpn& plan = *plan_;
    for (; supportAsker_ < askerCount_; ++supportAsker_, supportAsk_ = 0) {
        const Activity& asker = plan.activities[askers_[supportAsker_]];
        ++stats_.work;
        if (!exists(asker.guard, chosen_)) {
            continue;
        }
        for (; supportAsk_ < asker.askCount; ++supportAsk_) {
            const Condition& ask = asker.asks[supportAsk_];
            if (!ask.planVariable) {
                continue;
            }
            for (std::size_t b = 0; b < plan.activityCount; ++b) {
                const Activity& teller = plan.activities[b];
                stats_.work += 1U + teller.tellCount;
                bool tells = false;
                for (std::size_t k = 0; k < teller.tellCount; ++k) {
                    tells = tells || tellSupports(teller.tells[k], ask);
                }
                if (tells && !candidate_[teller.to] && exists(teller.guard, chosen_)) {
                    candidate_[teller.to] = true;
                    candidateList_[candidateCount_++] = teller.to;
                }
            }
            ++supportAsk_;
            supportFound_ = false;
            candidatesLeft_ = candidateCount_;
            supportSource_ = asker.from;
            if (candidateCount_ > 0) {
                beginDijkstra(asker.from, 0);
            }
            return true;
        }
    }
    return false;
}

void MethodSelector::supportAction() {
    if (!dijkstraRunning_) {
        if (!beginSupportCheck()) {
            // Every Ask supported: a valid selection, better than the incumbent.
            best_.hasSelection = true;
            best_.cost = cost_;
            best_.selection = chosen_;
            ++stats_.incumbents;
            search_ = SearchStep::kNextOption;
        } else if (!dijkstraRunning_) {
            reject(RejectReason::kCausalLinkMissing);  // no existing activity Tells an answer
            search_ = SearchStep::kNextOption;
        }
        return;
    }
    // Distances from the Ask's start: d(s, x) = key(x) - pi(s) + pi(x).
    const std::uint16_t x = popMin();
    if (candidate_[x]) {
        --candidatesLeft_;
        supportFound_ = key_[x] - pi_[supportSource_] + pi_[x] <= 0;
    }
    if (!supportFound_ && candidatesLeft_ > 0) {
        relaxFrom(x, selector_detail::kNoCutoff);
    }
    if (supportFound_ || candidatesLeft_ == 0 || queueSize_ == 0) {
        endDijkstra();
        if (!supportFound_) {
            reject(RejectReason::kCausalLinkMissing);
            search_ = SearchStep::kNextOption;
        }
    }
}

}  // namespace rse::plan_executive
