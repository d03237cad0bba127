// "Each application owns its commands and its packets, as a cFS app does; fsw/app
// only composes" (docs/architecture.md, "Commands and telemetry by owner" and
// "A map for a newcomer"). This test reads the flight sources (run from the
// repository root as every suite is) and holds the code to that:
//
// - every command of the dictionary is named (CommandCode::NAME) only in the
//   folder that owns its APID, besides fsw/cmdtlm's generic service code
//   (the dictionary itself, and the command task's and validator's special
//   cases of the service's own commands, which live in fsw/cmdtlm anyway);
// - every telemetry packet of the dictionary is packed (NAME_Tlm) only in the
//   folder that owns it; HK alone is filled by several owners, each through
//   cmdtlm::HousekeepingContributor (its own fields);
// - fsw/app only composes: it defines no task, no command handler and no
//   packer, names no command and packs no packet;
// - fsw/io (the tasks that drive the hardware through hal/) includes no layer;
// - the rover mode has one owner (cmdtlm::RoverMode): only fsw/cmdtlm (SET_MODE,
//   call homes) and fsw/app (which composes it) name it; an application that
//   holds the e-stop does so through cmdtlm::EstopSwitch.
//
// The owners are the table below; a new APID or packet must be given one here
// and in docs/architecture.md, or this test fails.
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"

#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;
using namespace rse;

namespace {

// The folder under fsw/ that owns each command APID.
const std::map<std::uint16_t, std::string> kCommandOwners = {
    {0x180, "cmdtlm"},          // command and telemetry service: NOOP, RESET_COUNTERS, REQUEST_HK, SET_MODE, AUTH_RESYNC
    {0x181, "plan_executive"},  // mission goals: the plan executive owns the mission (goals and plans)
    {0x182, "reflexive"},       // mobility: e-stop, manual drive, interlock reset
    {0x183, "tables"},          // the table service
    {0x184, "cmdtlm"},          // the executive's commands (its face in the command service)
    {0x185, "plan_executive"},  // plans
    {0x186, "site_map"},        // the site map service
};

// The folder under fsw/ that packs each telemetry packet.
const std::map<std::string, std::string> kPacketOwners = {
    {"HK", "cmdtlm"},           {"CMD_ACK", "cmdtlm"},          {"EVENT", "cmdtlm"},
    {"EVENT_DATA", "cmdtlm"},
    {"TASK_TIMING", "cmdtlm"},  {"ROVER_STATE", "estimator"},   {"HEALTH", "estimator"},
    {"DRIVES", "io"},           {"POWER", "io"},                {"INSTRUMENTS", "io"},
    {"PLAN", "deliberative"},   {"PLAN_PATH", "deliberative"},  {"ROUTE", "deliberative"},   {"HAZARDS", "habitual"},
    {"FAULT_PROTECTION", "fault_protection"},                   {"PLAN_EXEC", "plan_executive"},
    {"TABLE_STATUS", "tables"}, {"TABLE_DUMP", "tables"},       {"SITE_MAP", "site_map"},
};

// Packets more than one owner fills, each its own fields, through an interface.
const std::set<std::string> kSharedPackets = {"HK"};

const std::vector<std::string> kLayers = {"estimator", "reflexive", "habitual", "deliberative", "fault_protection",
                                          "plan_executive"};

struct Source {
    std::string path;    // "fsw/plan_executive/goal_commands.cpp"
    std::string folder;  // "plan_executive"
    std::string text;    // comments stripped
};

// The text without // and /* */ comments (a name in a comment is no use of it).
std::string withoutComments(const std::string& in) {
    std::string out;
    out.reserve(in.size());
    for (std::size_t i = 0; i < in.size(); ++i) {
        if (in.compare(i, 2, "//") == 0) {
            while (i < in.size() && in[i] != '\n') {
                ++i;
            }
        } else if (in.compare(i, 2, "/*") == 0) {
            const std::size_t end = in.find("*/", i + 2);
            i = end == std::string::npos ? in.size() : end + 1;
            continue;
        }
        if (i < in.size()) {
            out += in[i];
        }
    }
    return out;
}

std::vector<Source> flightSources() {
    std::vector<Source> out;
    if (!fs::is_directory("fsw")) {
        return out;
    }
    for (const fs::directory_entry& e : fs::recursive_directory_iterator("fsw")) {
        const std::string ext = e.path().extension().string();
        if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) {
            continue;
        }
        std::ifstream in(e.path());
        std::stringstream text;
        text << in.rdbuf();
        const std::string path = e.path().generic_string();
        const std::size_t slash = path.find('/', 4);
        out.push_back(Source{path, path.substr(4, slash - 4), withoutComments(text.str())});
    }
    std::sort(out.begin(), out.end(), [](const Source& a, const Source& b) { return a.path < b.path; });
    return out;
}

bool namesWord(const std::string& text, const std::string& word) {
    for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
        const bool startOk = at == 0 || !(std::isalnum(static_cast<unsigned char>(text[at - 1])) || text[at - 1] == '_');
        const std::size_t end = at + word.size();
        const bool endOk = end >= text.size() || !(std::isalnum(static_cast<unsigned char>(text[end])) || text[end] == '_');
        if (startOk && endOk) {
            return true;
        }
    }
    return false;
}

// The dictionary's own expansions name every command and packet generically.
bool isDictionary(const Source& s) { return s.path.rfind("fsw/cmdtlm/dictionary.", 0) == 0; }

// The file, or its header beside it, implements cmdtlm::HousekeepingContributor.
bool isContributor(const std::vector<Source>& sources, const Source& s) {
    const std::string stem = s.path.substr(0, s.path.rfind('.'));
    for (const Source& other : sources) {
        if ((other.path == s.path || other.path == stem + ".hpp") && namesWord(other.text, "HousekeepingContributor")) {
            return true;
        }
    }
    return false;
}

// Each check returns its breaches, one "\n  ..." line each ("" when none).

// Every command named (CommandCode::NAME) only in its APID's owner, and handled there.
std::string commandBreaches(const std::vector<Source>& sources) {
    std::size_t count = 0;
    const cmdtlm::CommandDesc* commands = cmdtlm::commandDescs(&count);
    std::string wrong;
    for (std::size_t i = 0; i < count; ++i) {
        const auto owner = kCommandOwners.find(commands[i].apid);
        if (owner == kCommandOwners.end()) {
            wrong += std::string("\n  ") + commands[i].name + ": APID has no owner in this test's table";
            continue;
        }
        const std::string word = std::string("CommandCode::") + commands[i].name;
        bool inOwner = false;
        for (const Source& s : sources) {
            if (isDictionary(s) || !namesWord(s.text, word)) {
                continue;
            }
            if (s.folder == owner->second) {
                inOwner = true;
            } else {
                wrong += "\n  " + word + " in " + s.path + " (owner: fsw/" + owner->second + ")";
            }
        }
        if (!inOwner) {
            wrong += "\n  " + word + ": handled nowhere in fsw/" + owner->second;
        }
    }
    return wrong;
}

// Every packet packed (NAME_Tlm) only in its owner, and packed there; HK's
// contributors fill their own fields through the contributor interface.
std::string packetBreaches(const std::vector<Source>& sources) {
    std::size_t count = 0;
    const cmdtlm::TelemetryDesc* packets = cmdtlm::telemetryDescs(&count);
    std::string wrong;
    for (std::size_t i = 0; i < count; ++i) {
        const auto owner = kPacketOwners.find(packets[i].name);
        if (owner == kPacketOwners.end()) {
            wrong += std::string("\n  ") + packets[i].name + ": no owner in this test's table";
            continue;
        }
        const std::string word = std::string(packets[i].name) + "_Tlm";
        bool inOwner = false;
        for (const Source& s : sources) {
            if (isDictionary(s) || !namesWord(s.text, word)) {
                continue;
            }
            const bool contributor = kSharedPackets.count(packets[i].name) != 0 && isContributor(sources, s);
            if (s.folder == owner->second) {
                inOwner = true;
            } else if (!contributor) {
                wrong += "\n  " + word + " in " + s.path + " (owner: fsw/" + owner->second + ")";
            }
        }
        if (!inOwner) {
            wrong += "\n  " + word + ": packed nowhere in fsw/" + owner->second;
        }
    }
    return wrong;
}

// fsw/app defines no task, handler or packer (whatever the access of the
// derivation) and names no command or packet.
std::string compositionBreaches(const std::vector<Source>& sources) {
    const std::regex derived(
        R"(:\s*(?:(?:public|protected|private|virtual)\s+)*(?:rse::)?(core::Task|cmdtlm::AppCommands|cmdtlm::CommandHandler|cmdtlm::TelemetryPacker|cmdtlm::HousekeepingContributor)\b)");
    const std::regex commandOrPacket(R"(\bCommandCode::[A-Z_]+|\b[A-Z][A-Z_]*_Tlm\b)");
    std::string wrong;
    for (const Source& s : sources) {
        if (s.folder != "app") {
            continue;
        }
        std::smatch m;
        if (std::regex_search(s.text, m, derived)) {
            wrong += "\n  " + s.path + " defines a " + m[1].str() + " (a task, handler or packer belongs to its owner)";
        }
        if (std::regex_search(s.text, m, commandOrPacket)) {
            wrong += "\n  " + s.path + " names " + m[0].str() + " (commands and packets belong to their owners)";
        }
    }
    return wrong;
}

// fsw/io includes no layer (and not the composition).
std::string hardwareTaskBreaches(const std::vector<Source>& sources) {
    const std::regex include(R"(#\s*include\s+"fsw/([a-z_]+)/)");
    std::string wrong;
    for (const Source& s : sources) {
        if (s.folder != "io") {
            continue;
        }
        for (std::sregex_iterator it(s.text.begin(), s.text.end(), include), end; it != end; ++it) {
            const std::string target = (*it)[1].str();
            if (std::find(kLayers.begin(), kLayers.end(), target) != kLayers.end() || target == "app") {
                wrong += "\n  " + s.path + " includes fsw/" + target;
            }
        }
    }
    return wrong;
}

std::size_t filesIn(const std::vector<Source>& sources, const std::string& folder) {
    return static_cast<std::size_t>(
        std::count_if(sources.begin(), sources.end(), [&](const Source& s) { return s.folder == folder; }));
}

// A planted source, as flightSources() would read it.
Source planted(const std::string& path, const std::string& text) {
    const std::size_t slash = path.find('/', 4);
    return Source{path, path.substr(4, slash - 4), withoutComments(text)};
}

}  // namespace

TEST_GROUP(Ownership) {
    std::vector<Source> sources;
    void setup() override { sources = flightSources(); }
};

TEST(Ownership, EveryCommandIsHandledInTheFolderThatOwnsItsApid) {
    CHECK_TEXT(sources.size() > 100, "flight sources not found (run from the repository root)");
    std::size_t count = 0;
    (void)cmdtlm::commandDescs(&count);
    CHECK_TEXT(count > 20, "the dictionary lists too few commands");
    const std::string wrong = commandBreaches(sources);
    CHECK_TEXT(wrong.empty(), ("a command outside its owner:" + wrong).c_str());
}

TEST(Ownership, EveryPacketIsPackedInTheFolderThatOwnsIt) {
    std::size_t count = 0;
    (void)cmdtlm::telemetryDescs(&count);
    CHECK_TEXT(count > 10, "the dictionary lists too few packets");
    const std::string wrong = packetBreaches(sources);
    CHECK_TEXT(wrong.empty(), ("a packet packed outside its owner:" + wrong).c_str());
}

TEST(Ownership, FswAppOnlyComposes) {
    CHECK_TEXT(filesIn(sources, "app") >= 3, "fsw/app sources not found (run from the repository root)");
    const std::string wrong = compositionBreaches(sources);
    CHECK_TEXT(wrong.empty(), ("fsw/app does more than compose:" + wrong).c_str());
}

TEST(Ownership, TheHardwareTasksIncludeNoLayer) {
    CHECK_TEXT(filesIn(sources, "io") >= 6, "fsw/io sources not found (run from the repository root)");
    const std::string wrong = hardwareTaskBreaches(sources);
    CHECK_TEXT(wrong.empty(), ("fsw/io includes a layer:" + wrong).c_str());
}

TEST(Ownership, OnlyTheCommandServiceNamesTheModeOwner) {
    std::string wrong;
    std::size_t holders = 0;
    for (const Source& s : sources) {
        if (s.folder != "cmdtlm" && s.folder != "app" && namesWord(s.text, "RoverMode")) {
            wrong += "\n  " + s.path + " names RoverMode (the mode is the command service's; hold cmdtlm::EstopSwitch)";
        }
        holders += s.folder != "cmdtlm" && s.folder != "app" && namesWord(s.text, "EstopSwitch") ? 1U : 0U;
    }
    CHECK_TEXT(holders >= 1, "no application holds the e-stop switch (the mobility commands should)");
    CHECK_TEXT(wrong.empty(), ("the mode owner named outside fsw/cmdtlm:" + wrong).c_str());
}

// The checks see a breach: each planted into the real sources is named.
TEST(Ownership, APlantedBreachOfEachRuleIsFound) {
    std::vector<Source> s = sources;
    s.push_back(planted("fsw/app/planted.cpp",
                        "struct Sneaky : core::Task {};\n"  // private derivation still counts
                        "int f() { return static_cast<int>(cmdtlm::CommandCode::GOTO); }\n"
                        "cmdtlm::PLAN_Tlm packed;\n"));
    s.push_back(planted("fsw/io/planted.cpp", "#include \"fsw/habitual/local_map.hpp\"\n"));
    const std::string commands = commandBreaches(s);
    CHECK_TEXT(commands.find("CommandCode::GOTO in fsw/app/planted.cpp") != std::string::npos, commands.c_str());
    const std::string packets = packetBreaches(s);
    CHECK_TEXT(packets.find("PLAN_Tlm in fsw/app/planted.cpp") != std::string::npos, packets.c_str());
    const std::string app = compositionBreaches(s);
    CHECK_TEXT(app.find("defines a core::Task") != std::string::npos, app.c_str());
    CHECK_TEXT(app.find("names CommandCode::GOTO") != std::string::npos, app.c_str());
    const std::string io = hardwareTaskBreaches(s);
    CHECK_TEXT(io.find("fsw/io/planted.cpp includes fsw/habitual") != std::string::npos, io.c_str());
}

// A command its owner no longer handles is named too.
TEST(Ownership, ACommandHandledNowhereIsFound) {
    std::vector<Source> s;
    for (const Source& source : sources) {
        if (source.folder != "reflexive") {
            s.push_back(source);
        }
    }
    const std::string wrong = commandBreaches(s);
    CHECK_TEXT(wrong.find("CommandCode::DRIVE: handled nowhere in fsw/reflexive") != std::string::npos, wrong.c_str());
}

// The checks read names; a name is a whole word outside comments.
TEST(Ownership, ANameIsAWholeWordOutsideComments) {
    CHECK(namesWord("x = CommandCode::GOTO;", "CommandCode::GOTO"));
    CHECK_FALSE(namesWord("x = CommandCode::GOTO_LATER;", "CommandCode::GOTO"));
    CHECK_FALSE(namesWord(withoutComments("// CommandCode::GOTO\n/* CommandCode::GOTO */ y"), "CommandCode::GOTO"));
}
