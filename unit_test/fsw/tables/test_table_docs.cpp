// docs/tables.md against the table definitions (fsw/tables/table_defs.def,
// tableDescs()) and the table service's events: every table, field and event
// documented, the stated count and one section per table in id order. The
// document is written by hand; this keeps it from drifting.
#include <cstddef>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "fsw/tables/table_events.hpp"
#include "fsw/tables/table_types.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse::tables;

namespace {

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

std::string readText(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

}  // namespace

TEST_GROUP(TableDocs){};

// docs/tables.md is written by hand from the .def; this keeps it from drifting.
TEST(TableDocs, EveryTableFieldAndEventIsDocumented) {
    const std::string doc = readText("docs/tables.md");
    CHECK_TEXT(doc.size() > 1000, "docs/tables.md missing or empty (run from the repository root)");
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    for (std::size_t t = 0; t < count; ++t) {
        CHECK_TEXT(contains(doc, descs[t].name), descs[t].name);
        for (std::size_t f = 0; f < descs[t].fieldCount; ++f) {
            const std::string name = std::string("`") + descs[t].fields[f].name + "`";
            CHECK_TEXT(contains(doc, name), name.c_str());
        }
    }
    for (unsigned id = events::kTableActivated; id <= events::kRejectNoData; ++id) {
        if (id > events::kTableStartupInvalid && id < events::kRejectTooShort) {
            continue;
        }
        const std::string text = "| " + std::to_string(id) + " |";
        CHECK_TEXT(contains(doc, text), text.c_str());
    }
    CHECK_TEXT(contains(doc, "0xCBF43926"), "CRC check value");
}

namespace {

// "six" for 6: how docs/tables.md spells a count (numerals are taken too).
std::string countWord(std::size_t n) {
    static const char* const kWords[] = {"zero",    "one",     "two",       "three",    "four",
                                         "five",    "six",     "seven",     "eight",    "nine",
                                         "ten",     "eleven",  "twelve",    "thirteen", "fourteen",
                                         "fifteen", "sixteen", "seventeen", "eighteen", "nineteen", "twenty"};
    return n < sizeof kWords / sizeof kWords[0] ? kWords[n] : std::to_string(n);
}

// The text between the heading line `heading` and the next heading of the same
// level ("\n## "), or "" when there is no such heading.
std::string section(const std::string& doc, const std::string& heading, const std::string& level) {
    const std::size_t at = doc.find("\n" + heading + "\n");
    if (at == std::string::npos) {
        return "";
    }
    const std::size_t begin = at + 1;
    const std::size_t end = doc.find("\n" + level + " ", begin + heading.size());
    return doc.substr(begin, end == std::string::npos ? std::string::npos : end - begin);
}

}  // namespace

// The number of tables docs/tables.md states, and its per-table sections, come
// from fsw/tables/table_defs.def: the count in the opening sentence is the
// .def's, "## The tables" holds one "### <id> `<NAME>`: <description>" section
// per table, in .def order and no other, and each table's fields are described
// in its own section.
TEST(TableDocs, StatedCountAndPerTableSectionsMatchTheDefinitions) {
    const std::string doc = readText("docs/tables.md");
    CHECK_TEXT(doc.size() > 1000, "docs/tables.md missing or empty (run from the repository root)");
    std::size_t count = 0;
    const TableDesc* descs = tableDescs(&count);
    LONGS_EQUAL(kTableCount, count);

    // "... its tunable parameters in <count> **tables**: ..."
    const std::size_t bold = doc.find(" **tables**");
    CHECK_TEXT(bold != std::string::npos, "docs/tables.md: no '<count> **tables**' in the opening");
    const std::size_t wordAt = doc.rfind(' ', bold - 1) + 1;
    const std::string stated = doc.substr(wordAt, bold - wordAt);
    const std::string expected = countWord(count);
    CHECK_TEXT(stated == expected || stated == std::to_string(count),
               ("docs/tables.md says '" + stated + " **tables**'; fsw/tables/table_defs.def defines " +
                std::to_string(count) + " ('" + expected + "')")
                   .c_str());

    const std::string tables = section(doc, "## The tables", "##");
    CHECK_TEXT(!tables.empty(), "docs/tables.md: no '## The tables' section");
    std::vector<std::string> headings;
    std::vector<std::size_t> starts;
    for (std::size_t at = tables.find("\n### "); at != std::string::npos; at = tables.find("\n### ", at + 1)) {
        const std::size_t end = tables.find('\n', at + 1);
        headings.push_back(tables.substr(at + 1, end == std::string::npos ? std::string::npos : end - at - 1));
        starts.push_back(at + 1);
    }
    std::string listed;
    for (const std::string& h : headings) {
        listed += "\n  " + h;
    }
    CHECK_TEXT(headings.size() == count, ("docs/tables.md has " + std::to_string(headings.size()) +
                                          " table sections; fsw/tables/table_defs.def defines " +
                                          std::to_string(count) + ":" + listed)
                                             .c_str());
    for (std::size_t t = 0; t < count; ++t) {
        const std::string want = "### " + std::to_string(static_cast<unsigned>(descs[t].id)) + " `" + descs[t].name +
                                 "`: " + descs[t].description;
        STRCMP_EQUAL_TEXT(want.c_str(), headings[t].c_str(), "docs/tables.md table section heading (in id order)");
        const std::size_t end = t + 1 < starts.size() ? starts[t + 1] : tables.size();
        const std::string own = tables.substr(starts[t], end - starts[t]);
        for (std::size_t f = 0; f < descs[t].fieldCount; ++f) {
            const std::string name = std::string("`") + descs[t].fields[f].name + "`";
            CHECK_TEXT(contains(own, name), (name + " not in the section of " + descs[t].name).c_str());
        }
    }
}
