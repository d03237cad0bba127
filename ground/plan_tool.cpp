#include "ground/plan_tool.hpp"

#include <fstream>
#include <iomanip>
#include <iterator>
#include <memory>
#include <ostream>
#include <sstream>

#include "fsw/plan_executive/method_selector.hpp"
#include "fsw/plan_executive/plan_parser.hpp"
#include "fsw/plan_executive/stn.hpp"

namespace rse::ground {

namespace {

using namespace rse::plan_executive;

constexpr int kExitOk = 0;
constexpr int kExitRead = 1;
constexpr int kExitBad = 2;

constexpr const char* kPlanCheckUsage = "usage: rse-ground plan check FILE [--failed C,...] [--degraded C,...]";

std::string seconds(std::int32_t ms) {
    if (ms >= kInfiniteMs) {
        return "inf";
    }
    std::ostringstream s;
    s << std::fixed << std::setprecision(3) << static_cast<double>(ms) / 1000.0;
    return s.str();
}

}  // namespace

std::vector<CliOption> componentStateOptions() { return {{"failed", 0, true}, {"degraded", 0, true}}; }

std::optional<std::string> applyComponentStates(const ParsedOptions& parsed, SelectionInput* input) {
    for (const auto& [option, list] : parsed.given) {
        if (option != "--failed" && option != "--degraded") {
            continue;
        }
        const ComponentState state = option == "--failed" ? ComponentState::kFailed : ComponentState::kDegraded;
        std::stringstream names(list);
        std::string name;
        while (std::getline(names, name, ',')) {
            bool found = false;
            for (std::size_t c = 0; c < kComponentCount; ++c) {
                if (name == toString(static_cast<Component>(c))) {
                    input->components[c] = state;
                    found = true;
                }
            }
            if (!found) {
                return "unknown component '" + name + "'";
            }
        }
    }
    return std::nullopt;
}

bool checkPlanText(const std::string& text, const std::string& where, const SelectionInput& input, bool windows,
                   std::ostream& out, std::ostream& err) {
    // The flight objects are large (the STN holds a 256 KiB matrix): heap here, on the ground.
    const auto plan = std::make_unique<Tpn>();
    const ParseResult parsed = parsePlan(text.data(), text.size(), plan.get());
    if (parsed.error != PlanError::kOk) {
        err << where << ":" << parsed.line << ": " << toString(parsed.error);
        if (parsed.token[0] != '\0') {
            err << " at '" << parsed.token << "'";
        }
        err << " (the rover would refuse this plan)\n";
        return false;
    }
    out << "plan '" << plan->name << "': " << plan->eventCount << " events, " << plan->activityCount
        << " activities, " << plan->constraintCount << " constraints, " << static_cast<unsigned>(plan->choiceCount)
        << " choices\n";
    const auto selector = std::make_unique<MethodSelector>();
    SelectionResult result;
    const SelectionParams params;
    const SelectionStatus status = selector->solve(*plan, input, params, &result);
    out << "selection: " << toString(status) << " (" << selector->work() << " work units)\n";
    if (!result.hasSelection) {
        const SelectionStats& st = selector->stats();
        err << where << ": no valid selection of methods: " << toString(status) << " (rejected: ask failed "
            << st.rejected[0] << ", deprecated " << st.rejected[1] << ", causal link missing " << st.rejected[2]
            << ", inconsistent " << st.rejected[3] << ")\n";
        return false;
    }
    for (std::size_t c = 0; c < plan->choiceCount; ++c) {
        const std::uint8_t o = result.selection.option[c];
        out << "  choice " << plan->choices[c].name << ": "
            << (o == kNoOption ? std::string("(does not exist)") : std::string(plan->choices[c].options[o].name))
            << "\n";
    }
    std::ostringstream cost;
    cost << std::fixed << std::setprecision(3) << result.cost;
    out << "expected cost: " << cost.str() << "\n";
    const auto stn = std::make_unique<Stn>();
    if (loadStn(*plan, result.selection, stn.get()) != core::Status::kOk || stn->check() != StnState::kConsistent) {
        err << where << ": the selected plan's temporal network is not consistent\n";
        return false;
    }
    if (!windows) {
        return true;
    }
    out << "event windows (s from the plan's start):\n";
    for (std::size_t e = 0; e < plan->eventCount; ++e) {
        if (!exists(plan->events[e].guard, result.selection)) {
            continue;
        }
        const Window w = stn->window(e);
        out << "  " << plan->events[e].name << ": [" << seconds(w.earliestMs) << ", " << seconds(w.latestMs) << "]\n";
    }
    // Where each selected drive goes: its point, or the region round it the
    // rover may stop in (`within R`).
    bool drivesShown = false;
    for (std::size_t a = 0; a < plan->activityCount; ++a) {
        const Activity& act = plan->activities[a];
        if (act.kind != ActivityKind::kDrive || !exists(act.guard, result.selection)) {
            continue;
        }
        if (!drivesShown) {
            out << "drives (m):\n";
            drivesShown = true;
        }
        std::ostringstream line;
        line << std::fixed << std::setprecision(3) << "  " << act.name << ": to (" << act.x << ", " << act.y << ")";
        if (act.radiusMm > 0) {
            line << " within " << static_cast<double>(act.radiusMm) / 1000.0;
        } else {
            line << " (the point)";
        }
        out << line.str() << "\n";
    }
    return true;
}

int runPlanCommand(const std::vector<std::string>& args, std::ostream& out, std::ostream& err) {
    SelectionInput input;
    std::string path;
    try {
        if (args.empty() || args[0] != "check") {
            throw UsageError("plan: check, load, short or abort");
        }
        const ParsedOptions parsed = parseCliOptions(
            "plan check", std::vector<std::string>(args.begin() + 1, args.end()), componentStateOptions());
        expectOperands(parsed, 1, "plan check", kPlanCheckUsage);
        if (const std::optional<std::string> why = applyComponentStates(parsed, &input)) {
            throw UsageError("plan check: " + *why);
        }
        path = parsed.operands[0];
    } catch (const UsageError& e) {
        return reportUsageError(err, e.what());
    } catch (const HelpRequested&) {
        out << groundUsage();
        return kExitOk;
    }
    std::ifstream file(path, std::ios::binary);
    if (!file) {
        err << "rse-ground: plan check: cannot read '" << path << "'\n";
        return kExitRead;
    }
    const std::string text((std::istreambuf_iterator<char>(file)), std::istreambuf_iterator<char>());
    return checkPlanText(text, path, input, true, out, err) ? kExitOk : kExitBad;
}

}  // namespace rse::ground
