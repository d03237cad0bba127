// Reading a scenario file's TOML (sim_stub/scenario/scenario_parser.hpp):
// the typed, range-checked fields and the error wording every section and
// every fault kind share. A problem throws ScenarioError
//   <source>: <key path>: <what is wrong>
// (array indices from 0). Used by the scenario parser and the fault parser
// (fault_parser.hpp); not for other code.
//
// Host start-up code: uses exceptions and the heap.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

#include <toml++/toml.h>

#include "fsw/core/clock.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim::scenario_toml {

constexpr double kMaxTimeS = 1e7;  // about four months: far beyond any run, far below TimeNs overflow

// A number as the messages print it.
std::string num(double v);
// A key path: base.key (key alone at the top), base[i].
std::string join(const std::string& base, std::string_view key);
std::string indexed(const std::string& base, std::size_t i);
// "a table", "an integer", ...: what a node is, for the messages.
const char* typeName(const toml::node& n);
core::TimeNs toNs(double seconds);

// The fields of one scenario file (source names it in the messages).
class Reader {
public:
    explicit Reader(std::string source) : source_(std::move(source)) {}
    const std::string& source() const { return source_; }

    // Throws ScenarioError "<source>: <path>: <what>".
    [[noreturn]] void fail(const std::string& path, const std::string& what) const;

    // Fails on a key of t not in allowed ("unknown key", then context if any).
    void onlyKeys(const toml::table& t, const std::string& path, std::initializer_list<std::string_view> allowed,
                  const std::string& context = {}) const;

    // t's key: nullptr when absent, a failure when absent and required.
    const toml::node* node(const toml::table& t, const std::string& path, std::string_view key,
                           bool required) const;

    // Typed values: the node's (path names it), or t's key's (fallback when
    // absent and not required); the wrong type fails.
    const toml::table* table(const toml::table& t, const std::string& path, std::string_view key,
                             bool required) const;

    double number(const toml::node& n, const std::string& path) const;

    double number(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                  bool required = false) const;

    std::int64_t integer(const toml::node& n, const std::string& path) const;

    std::int64_t integer(const toml::table& t, const std::string& path, std::string_view key, std::int64_t fallback,
                         bool required = false) const;

    bool boolean(const toml::table& t, const std::string& path, std::string_view key, bool fallback,
                 bool required = false) const;

    std::string string(const toml::table& t, const std::string& path, std::string_view key,
                       const std::string& fallback, bool required = false) const;

    // An array of tables ([[p]]): every element must be a table.
    const toml::array& tableArray(const toml::node& n, const std::string& p) const;

    // The id (1..255) of element i of the array p, unused by the elements before it.
    template <typename T>
    std::uint8_t uniqueId(const toml::table& t, const std::string& p, std::size_t i, const std::vector<T>& before) const {
        const std::string path = join(indexed(p, i), "id");
        const std::int64_t id = integer(t, indexed(p, i), "id", 0, true);
        if (id < 1 || id > 255) {
            fail(path, "must be 1..255 (got " + std::to_string(id) + ")");
        }
        for (std::size_t j = 0; j < before.size(); ++j) {
            if (before[j].id == id) {
                fail(path, std::to_string(id) + " is already used by " + indexed(p, j));
            }
        }
        return static_cast<std::uint8_t>(id);
    }

    // Range checks; the message names the bound.
    void above(const std::string& path, double v, double lo) const;
    void atLeast(const std::string& path, double v, double lo) const;
    void within(const std::string& path, double v, double lo, double hi) const;
    void withinOpenLow(const std::string& path, double v, double lo, double hi) const;

    // Reads key as a number in (lo, hi] (positive quantities) or [lo, hi].
    double positive(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                    double hi, bool required = false) const;
    double ranged(const toml::table& t, const std::string& path, std::string_view key, double fallback, double lo,
                  double hi, bool required = false) const;

private:
    std::string source_;
};

}  // namespace rse::sim::scenario_toml
