// "A parameter is a promise": every table field must be read by the flight
// code it configures. This test reads the flight sources (fsw/ and hal/, run
// from the repository root as every suite is) and fails for any field of any
// table whose name appears nowhere outside fsw/tables/ (where every field is
// defined, validated and copied, which configures nothing). A field read only
// through a differently named variable still has to be named where it is read
// (tables.faultResponse().heartbeat_loss_ms), so this catches a field left
// defined, validated and documented while a constant stands in for it.
#include <cctype>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fsw/tables/table_types.hpp"

#include <CppUTest/TestHarness.h>

namespace fs = std::filesystem;

namespace {

std::vector<std::string> flightSourcesOutsideTables() {
    std::vector<std::string> texts;
    for (const char* root : {"fsw", "hal"}) {
        for (const fs::directory_entry& e : fs::recursive_directory_iterator(root)) {
            const std::string path = e.path().generic_string();
            const std::string ext = e.path().extension().string();
            if (!e.is_regular_file() || path.rfind("fsw/tables/", 0) == 0 || (ext != ".cpp" && ext != ".hpp")) {
                continue;
            }
            std::ifstream in(path);
            texts.emplace_back(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
        }
    }
    return texts;
}

bool isIdentChar(char c) { return std::isalnum(static_cast<unsigned char>(c)) != 0 || c == '_'; }

// The name as a whole identifier, and not only inside a comment line.
bool readIn(const std::string& text, const std::string& name) {
    for (std::size_t at = text.find(name); at != std::string::npos; at = text.find(name, at + 1)) {
        const bool startOk = at == 0 || !isIdentChar(text[at - 1]);
        const bool endOk = at + name.size() >= text.size() || !isIdentChar(text[at + name.size()]);
        if (!startOk || !endOk) {
            continue;
        }
        const std::size_t lineStart = text.rfind('\n', at) == std::string::npos ? 0 : text.rfind('\n', at) + 1;
        const std::size_t comment = text.find("//", lineStart);
        if (comment == std::string::npos || comment > at) {
            return true;
        }
    }
    return false;
}

}  // namespace

TEST_GROUP(TableReaders){};

TEST(TableReaders, EveryTableFieldIsReadOutsideTheTableService) {
    const std::vector<std::string> sources = flightSourcesOutsideTables();
    CHECK_TEXT(sources.size() > 50, "flight sources not found (run from the repository root)");
    std::size_t count = 0;
    const rse::tables::TableDesc* descs = rse::tables::tableDescs(&count);
    std::string unread;
    for (std::size_t t = 0; t < count; ++t) {
        for (std::size_t f = 0; f < descs[t].fieldCount; ++f) {
            const std::string name = descs[t].fields[f].name;
            bool found = false;
            for (const std::string& text : sources) {
                found = found || readIn(text, name);
            }
            if (!found) {
                unread += std::string(" ") + descs[t].name + "." + name;
            }
        }
    }
    CHECK_TEXT(unread.empty(), ("table fields no flight code reads:" + unread).c_str());
}

TEST(TableReaders, TheScanFindsReadsAndSkipsCommentsAndLongerNames) {
    CHECK_TRUE(readIn("x = t.heartbeat_loss_ms;", "heartbeat_loss_ms"));
    CHECK_FALSE(readIn("// heartbeat_loss_ms is read elsewhere\n", "heartbeat_loss_ms"));
    CHECK_FALSE(readIn("x = t.heartbeat_loss_ms_max;", "heartbeat_loss_ms"));
    CHECK_FALSE(readIn("x = my_heartbeat_loss_ms;", "heartbeat_loss_ms"));
}
