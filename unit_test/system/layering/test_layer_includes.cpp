// "Layers meet only through fsw/msg/ and the bus: what two layers both need
// (2-D geometry, the map) lives below both, not inside one that the other
// includes." This test reads the flight sources (run from the repository root
// as every suite is) and fails for any #include "..." that breaks the rule:
//
// - a file in a layer folder (fsw/estimator, fsw/reflexive, fsw/habitual,
//   fsw/deliberative, fsw/fault_protection, fsw/plan_executive) includes only its own folder and
//   the folders below every layer: fsw/msg, fsw/core, fsw/geometry, fsw/tables,
//   fsw/rover_model, fsw/site_map. Not another layer, not fsw/cmdtlm or fsw/app, not hal/
//   (no layer uses it), not the simulator or the ground tools;
// - a file in a folder below the layers includes only folders below the layers
//   (what sits below both cannot reach back up into either);
// - the exception to both: a layer, fsw/tables and fsw/site_map may include the application
//   interface of fsw/cmdtlm (the headers kCmdTlmInterface names, listed in
//   fsw/cmdtlm/app_commands.hpp), through which an application owns its
//   commands and its telemetry packets and names its events' numbers
//   (event_data.hpp); nothing else of fsw/cmdtlm. Not the mode owner
//   (rover_mode.hpp): a layer that holds the e-stop sees only its switch
//   (estop_switch.hpp), so none can change the rover's mode by a call. The list
//   here is the one app_commands.hpp gives, and this test checks they agree;
// - fsw/cmdtlm (the command and telemetry service, below every layer) includes
//   only itself, fsw/core, fsw/msg and what lies outside fsw/ (hal/): no
//   layer, no table, no fsw/io, no fsw/app.
//
// fsw/app (the composition root) is not checked: it may include every layer.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;

namespace {

const std::vector<std::string> kLayers = {"estimator", "reflexive", "habitual", "deliberative", "fault_protection",
                                          "plan_executive"};
const std::vector<std::string> kBelowLayers = {"msg", "core", "geometry", "tables", "rover_model", "site_map"};
const std::vector<std::string> kCmdTlmInterface = {
    "fsw/cmdtlm/dictionary.hpp",     "fsw/cmdtlm/command_verdict.hpp",  "fsw/cmdtlm/app_commands.hpp",
    "fsw/cmdtlm/telemetry_sink.hpp", "fsw/cmdtlm/telemetry_packer.hpp", "fsw/cmdtlm/housekeeping_contributor.hpp",
    "fsw/cmdtlm/estop_switch.hpp",   "fsw/cmdtlm/event_data.hpp"};

bool contains(const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
}

// The quoted include paths of one file, with their line numbers.
struct Include {
    std::size_t line;
    std::string path;
};

std::vector<Include> quotedIncludes(const fs::path& file) {
    std::vector<Include> out;
    std::ifstream in(file);
    std::string text;
    for (std::size_t line = 1; std::getline(in, text); ++line) {
        const std::size_t hash = text.find_first_not_of(" \t");
        if (hash == std::string::npos || text[hash] != '#') {
            continue;
        }
        const std::size_t word = text.find_first_not_of(" \t", hash + 1);
        if (word == std::string::npos || text.compare(word, 7, "include") != 0) {
            continue;
        }
        const std::size_t open = text.find('"', word + 7);
        const std::size_t close = open == std::string::npos ? open : text.find('"', open + 1);
        if (close != std::string::npos) {
            out.push_back(Include{line, text.substr(open + 1, close - open - 1)});
        }
    }
    return out;
}

// The folder under fsw/ a path names ("fsw/habitual/x.hpp" -> "habitual"), or "" outside fsw/.
std::string fswFolder(const std::string& path) {
    if (path.rfind("fsw/", 0) != 0) {
        return "";
    }
    const std::size_t slash = path.find('/', 4);
    return slash == std::string::npos ? "" : path.substr(4, slash - 4);
}

// What a scan of some folders found: how many files it read, and every include
// that is not into the file's own folder or an allowed one, as "file:line
// includes path" lines.
struct Scan {
    std::size_t files = 0;
    std::string violations;
};

// Whether a file in folder may include path: its own folder, an allowed one,
// or one of the interface's single headers.
bool mayInclude(const std::string& folder, const std::string& path, const std::vector<std::string>& allowed,
                const std::vector<std::string>& interface) {
    const std::string target = fswFolder(path);
    return target == folder || contains(allowed, target) || contains(interface, path);
}

// The headers fsw/cmdtlm/app_commands.hpp lists as the application interface:
// its comment lines "//   name.hpp   what it is", as "fsw/cmdtlm/name.hpp".
std::vector<std::string> documentedInterface() {
    std::vector<std::string> out;
    std::ifstream in("fsw/cmdtlm/app_commands.hpp");
    std::string line;
    const std::string lead = "//   ";
    while (std::getline(in, line)) {
        const std::size_t end = line.find(".hpp ");
        if (line.rfind(lead, 0) == 0 && end != std::string::npos && line.find(' ', lead.size()) > end) {
            out.push_back("fsw/cmdtlm/" + line.substr(lead.size(), end + 4 - lead.size()));
        }
    }
    return out;
}

// interface: single headers allowed besides the allowed folders.
Scan scan(const std::vector<std::string>& folders, const std::vector<std::string>& allowed,
          const std::vector<std::string>& interface = {}) {
    Scan out;
    for (const std::string& folder : folders) {
        const fs::path root = fs::path("fsw") / folder;
        if (!fs::is_directory(root)) {
            continue;
        }
        for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
            const std::string ext = e.path().extension().string();
            if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp" && ext != ".def")) {
                continue;
            }
            ++out.files;
            for (const Include& inc : quotedIncludes(e.path())) {
                if (!mayInclude(folder, inc.path, allowed, interface)) {
                    out.violations += "\n  " + e.path().generic_string() + ":" + std::to_string(inc.line) +
                                      " includes " + inc.path;
                }
            }
        }
    }
    return out;
}

}  // namespace

TEST_GROUP(LayerIncludes){};

TEST(LayerIncludes, ALayerIncludesOnlyItselfAndWhatLiesBelowEveryLayer) {
    const Scan s = scan(kLayers, kBelowLayers, kCmdTlmInterface);
    CHECK_TEXT(s.files > 50, "layer sources not found (run from the repository root)");
    CHECK_TEXT(s.violations.empty(),
               ("a layer includes another layer's (or a non-shared) folder:" + s.violations).c_str());
}

TEST(LayerIncludes, WhatLiesBelowTheLayersIncludesNoLayer) {
    std::vector<std::string> belowButServices = kBelowLayers;
    for (const char* service : {"tables", "site_map"}) {
        belowButServices.erase(std::find(belowButServices.begin(), belowButServices.end(), service));
    }
    Scan s = scan(belowButServices, kBelowLayers);
    // The table service and the site map service own their commands.
    const Scan tables = scan({"tables", "site_map"}, kBelowLayers, kCmdTlmInterface);
    s.files += tables.files;
    s.violations += tables.violations;
    CHECK_TEXT(s.files > 20, "shared sources not found (run from the repository root)");
    CHECK_TEXT(s.violations.empty(), ("a folder below the layers includes a layer:" + s.violations).c_str());
}

TEST(LayerIncludes, TheCommandAndTelemetryServiceIncludesNoApplication) {
    const Scan s = scan({"cmdtlm"}, {"core", "msg", ""});  // "": outside fsw/ (hal/)
    CHECK_TEXT(s.files > 20, "fsw/cmdtlm sources not found (run from the repository root)");
    CHECK_TEXT(s.violations.empty(), ("fsw/cmdtlm includes an application:" + s.violations).c_str());
}

// The folder an include names: the one under fsw/, none outside fsw/ (which is
// then never an allowed folder: hal/, the simulator, the ground tools, a bare name).
TEST(LayerIncludes, TheFolderOfAnIncludeIsReadFromItsPath) {
    STRCMP_EQUAL("habitual", fswFolder("fsw/habitual/local_map.hpp").c_str());
    STRCMP_EQUAL("geometry", fswFolder("fsw/geometry/geometry2d.hpp").c_str());
    STRCMP_EQUAL("", fswFolder("hal/can/can_bus.hpp").c_str());
    STRCMP_EQUAL("", fswFolder("sim_stub/world/world.hpp").c_str());
    STRCMP_EQUAL("", fswFolder("local.hpp").c_str());
}

// The interface this test holds the layers to is the one app_commands.hpp
// documents, header for header.
TEST(LayerIncludes, TheInterfaceIsTheOneAppCommandsLists) {
    std::vector<std::string> documented = documentedInterface();
    std::vector<std::string> held = kCmdTlmInterface;
    std::sort(documented.begin(), documented.end());
    std::sort(held.begin(), held.end());
    CHECK_TEXT(documented.size() >= 5, "fsw/cmdtlm/app_commands.hpp's list not found (run from the repository root)");
    std::string shown;
    for (const std::string& h : documented) {
        shown += "\n  " + h;
    }
    CHECK_TEXT(documented == held, ("app_commands.hpp lists another interface:" + shown).c_str());
}

// The mode owner is not part of the interface: a layer (or fsw/tables) that
// includes rover_mode.hpp fails; the e-stop's switch is what it may hold.
TEST(LayerIncludes, ALayerMayHoldTheEstopSwitchButNotTheModeOwner) {
    for (const char* folder : {"reflexive", "deliberative", "plan_executive", "tables"}) {
        CHECK_FALSE(mayInclude(folder, "fsw/cmdtlm/rover_mode.hpp", kBelowLayers, kCmdTlmInterface));
        CHECK_TRUE(mayInclude(folder, "fsw/cmdtlm/estop_switch.hpp", kBelowLayers, kCmdTlmInterface));
    }
    CHECK_FALSE(mayInclude("reflexive", "fsw/cmdtlm/command_router.hpp", kBelowLayers, kCmdTlmInterface));
    CHECK_FALSE(mayInclude("reflexive", "fsw/plan_executive/goal_list.hpp", kBelowLayers, kCmdTlmInterface));
    CHECK_TRUE(mayInclude("plan_executive", "fsw/plan_executive/goal_list.hpp", kBelowLayers, kCmdTlmInterface));
}
