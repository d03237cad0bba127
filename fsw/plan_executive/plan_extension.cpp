#include "fsw/plan_executive/plan_extension.hpp"

#include <cstdio>
#include <cstring>

#include "fsw/plan_executive/plan_executive_events.hpp"

namespace rse::plan_executive {

namespace {

double seconds(std::int32_t ms) { return static_cast<double>(ms) / 1000.0; }

const char* refusalName(msg::PlanExtensionRefusal r) {
    switch (r) {
        case msg::PlanExtensionRefusal::kNone: return "none";
        case msg::PlanExtensionRefusal::kUnknownActivity: return "unknown activity";
        case msg::PlanExtensionRefusal::kNotRunning: return "not running";
        case msg::PlanExtensionRefusal::kNotScience: return "not a science activity";
        case msg::PlanExtensionRefusal::kBeyondUb: return "beyond its ub";
        case msg::PlanExtensionRefusal::kInconsistent: return "plan inconsistent";
        case msg::PlanExtensionRefusal::kBusy: return "busy";
        case msg::PlanExtensionRefusal::kInvalid: return "invalid extra time";
        case msg::PlanExtensionRefusal::kInstrument: return "instrument refused";
    }
    return "?";
}

msg::PlanExtensionRefusal refusalOf(ExtensionRefusal r) {
    switch (r) {
        case ExtensionRefusal::kNone: return msg::PlanExtensionRefusal::kNone;
        case ExtensionRefusal::kNotRunning: return msg::PlanExtensionRefusal::kNotRunning;
        case ExtensionRefusal::kNotScience: return msg::PlanExtensionRefusal::kNotScience;
        case ExtensionRefusal::kBeyondUb: return msg::PlanExtensionRefusal::kBeyondUb;
        case ExtensionRefusal::kInconsistent: return msg::PlanExtensionRefusal::kInconsistent;
        case ExtensionRefusal::kBusy: return msg::PlanExtensionRefusal::kBusy;
        case ExtensionRefusal::kInvalid: return msg::PlanExtensionRefusal::kInvalid;
    }
    return msg::PlanExtensionRefusal::kInvalid;
}

// The name as sent, any bytes, shown printable (the events' text).
void printableName(const msg::PlanCommandMsg& m, char (&name)[kNameSize]) {
    const std::size_t shown = m.length < kNameSize ? m.length : kNameSize - 1;
    for (std::size_t i = 0; i < shown; ++i) {
        const char c = m.data[i];
        name[i] = c >= 0x20 && c < 0x7F ? c : '?';
    }
}

// The dispatcher's refusal, with its numbers, for the event.
void describe(const ExtensionCheck& c, const char* state, const char* kind, char* detail, std::size_t size) {
    switch (c.refusal) {
        case ExtensionRefusal::kNone: break;
        case ExtensionRefusal::kNotRunning: std::snprintf(detail, size, "%s", state); break;
        case ExtensionRefusal::kNotScience: std::snprintf(detail, size, "%s", kind); break;
        case ExtensionRefusal::kBeyondUb:
            std::snprintf(detail, size, "end %.1f > start+ub %.1f s", seconds(c.expectedEndMs), seconds(c.ubEndMs));
            break;
        case ExtensionRefusal::kInconsistent:
            std::snprintf(detail, size, "end %.1f > latest %.1f s", seconds(c.expectedEndMs), seconds(c.latestMs));
            break;
        case ExtensionRefusal::kBusy: std::snprintf(detail, size, "holding"); break;
        case ExtensionRefusal::kInvalid: std::snprintf(detail, size, "times out of range"); break;
    }
}

}  // namespace

void PlanExtension::refuse(msg::PlanExtensionRefusal why, const char* name, std::int32_t extraMs, const char* detail) {
    ++counters_.refused;
    counters_.lastRefusal = why;
    ctx_.changed = true;
    ctx_.events.report(events::kExtensionRefused, core::Severity::kWarning,
                       "plan_exec: extend %s +%.1f s refused: %s (%s)", name, seconds(extraMs), refusalName(why),
                       detail);
}

std::uint16_t PlanExtension::findActivity(const msg::PlanCommandMsg& m) const {
    const Tpn& p = ctx_.plan();
    for (std::uint16_t i = 0; ctx_.planLoaded && i < p.activityCount; ++i) {
        std::size_t n = 0;
        while (n < kNameSize && p.activities[i].name[n] != '\0') {
            ++n;
        }
        if (m.length == n && n > 0 && std::memcmp(p.activities[i].name, m.data, n) == 0) {
            return i;
        }
    }
    return kNoIndex;
}

std::int32_t PlanExtension::expectedOwnEndMs(std::uint16_t a, std::int32_t nowMs) const {
    const Activity& act = ctx_.plan().activities[a];
    const std::int64_t start = ctx_.dispatcher.startMs(a);
    const msg::InstrumentStatusMsg& m =
        devices_.latest(act.kind == ActivityKind::kImage ? msg::Instrument::kCamera : msg::Instrument::kGrinder);
    // Nothing better known: the plan's least duration.
    std::int64_t total = act.duration.lbMs;
    if (m.commandId == devices_.commandId(a) && m.state == msg::InstrumentState::kBusy && m.progressPct > 0 &&
        m.progressPct < 100 && m.lastReportNs > ctx_.planStartNs) {
        // Its progress at its last report: the work is elapsed / progress long.
        const std::int64_t elapsed = (m.lastReportNs - ctx_.planStartNs) / core::kNsPerMs - start;
        if (elapsed > 0) {
            total = (elapsed * 100 + m.progressPct - 1) / m.progressPct;
        }
    }
    std::int64_t end = start + total;
    end = end < nowMs ? nowMs : end;
    return static_cast<std::int32_t>(end > kMaxBoundMs ? kMaxBoundMs : end);
}

void PlanExtension::request(const msg::PlanCommandMsg& m) {
    char name[kNameSize] = {};
    printableName(m, name);
    if (m.extendMs == 0 || m.extendMs > kMaxExtendMs) {
        char detail[64];
        std::snprintf(detail, sizeof detail, "%u ms", static_cast<unsigned>(m.extendMs));
        refuse(msg::PlanExtensionRefusal::kInvalid, name,
               static_cast<std::int32_t>(m.extendMs > kMaxExtendMs ? kMaxExtendMs : m.extendMs), detail);
        return;
    }
    // Whole 0.1 s, as the instruments take it.
    const auto extraMs = static_cast<std::int32_t>((m.extendMs + 99U) / 100U * 100U);
    const std::uint16_t a = findActivity(m);
    if (a == kNoIndex) {
        refuse(msg::PlanExtensionRefusal::kUnknownActivity, name, extraMs, ctx_.planLoaded ? "not in the plan" : "no plan");
        return;
    }
    if (ctx_.job != SelectionJob::kNone || ctx_.checking || pending_.activity != kNoIndex) {
        refuse(msg::PlanExtensionRefusal::kBusy, name, extraMs,
               pending_.activity != kNoIndex ? "an extension pending" : "selecting or checking");
        return;
    }
    const Activity& act = ctx_.plan().activities[a];
    const std::int32_t nowMs = ctx_.planMs();
    const bool commanded = isScience(act.kind) && devices_.commandId(a) != 0;
    const std::int32_t ownEndMs = commanded ? expectedOwnEndMs(a, nowMs) : nowMs;
    const ExtensionCheck c = ctx_.dispatcher.checkExtension(a, nowMs, ownEndMs, extraMs);
    if (c.refusal != ExtensionRefusal::kNone) {
        char detail[120];
        describe(c, toString(ctx_.dispatcher.state(a)), toString(act.kind), detail, sizeof detail);
        refuse(refusalOf(c.refusal), name, extraMs, detail);
        return;
    }
    if (!commanded) {
        refuse(msg::PlanExtensionRefusal::kNotRunning, name, extraMs, "no command in hand");
        return;
    }
    pending_ = PendingExtension{};
    pending_.activity = a;
    pending_.extraMs = extraMs;
    pending_.ownEndMs = ownEndMs;
    pending_.requestMs = nowMs;
    pending_.commandId = devices_.sendFollowOn(a, extraMs);
    ctx_.changed = true;
    ctx_.events.report(events::kExtensionRequested, core::Severity::kInfo,
                       "plan_exec: extend %s +%.1f s sent: end %.1f->%.1f s (start+ub %.1f, latest %.1f s)", act.name,
                       seconds(extraMs), seconds(ownEndMs), seconds(c.expectedEndMs),
                       c.ubEndMs == kInfiniteMs ? -1.0 : seconds(c.ubEndMs),
                       c.latestMs == kInfiniteMs ? -1.0 : seconds(c.latestMs));
}

void PlanExtension::answer(std::uint16_t a, const msg::InstrumentStatusMsg& m) {
    const PendingExtension p = pending_;
    const Activity& act = ctx_.plan().activities[a];
    if (m.commandId == p.commandId) {
        // Taken: the instrument's command is the follow-on from now on.
        pending_ = PendingExtension{};
        devices_.adoptFollowOn(a, p.commandId);
        const ExtensionCheck c = ctx_.dispatcher.extend(a, p.requestMs, p.ownEndMs, p.extraMs);
        if (c.refusal != ExtensionRefusal::kNone) {
            refuse(refusalOf(c.refusal), act.name, p.extraMs, "taken too late: runs on");
            return;
        }
        if (endBeforeExtensionMs_[a] == 0) {
            endBeforeExtensionMs_[a] = p.ownEndMs;
        }
        ++counters_.accepted;
        ctx_.changed = true;
        ctx_.events.report(events::kExtensionAccepted, core::Severity::kInfo,
                           "plan_exec: %s extended by %.1f s: the %s took it; end no earlier than %.1f s", act.name,
                           seconds(p.extraMs), act.kind == ActivityKind::kImage ? "camera" : "grinder",
                           seconds(c.floorMs));
        if (ctx_.dispatcher.regenerationNeeded() && ctx_.job == SelectionJob::kNone) {
            regeneration_.startRegeneration(ctx_.planMs());  // the network left its range (see PlanDispatcher::extend)
        }
        return;
    }
    if (m.lastRefusedCommandId == p.commandId && m.lastRefusal != msg::InstrumentRefusal::kNone) {
        pending_ = PendingExtension{};
        char detail[32];
        std::snprintf(detail, sizeof detail, "refusal %u", static_cast<unsigned>(m.lastRefusal));
        refuse(msg::PlanExtensionRefusal::kInstrument, act.name, p.extraMs, detail);
    }
}

void PlanExtension::drop(std::uint16_t a) {
    if (pending_.activity != a) {
        return;
    }
    const std::int32_t extraMs = pending_.extraMs;
    pending_ = PendingExtension{};
    refuse(msg::PlanExtensionRefusal::kNotRunning, ctx_.plan().activities[a].name, extraMs, "ended first");
}

}  // namespace rse::plan_executive
