#include "sim_stub/scenario/scenario_toml.hpp"

#include <cmath>
#include <sstream>

namespace rse::sim::scenario_toml {

std::string num(double v) {
    std::ostringstream os;
    os << v;
    return os.str();
}

std::string join(const std::string& base, std::string_view key) {
    return base.empty() ? std::string(key) : base + "." + std::string(key);
}

std::string indexed(const std::string& base, std::size_t i) { return base + "[" + std::to_string(i) + "]"; }

const char* typeName(const toml::node& n) {
    switch (n.type()) {
        case toml::node_type::table:
            return "a table";
        case toml::node_type::array:
            return "an array";
        case toml::node_type::string:
            return "a string";
        case toml::node_type::integer:
            return "an integer";
        case toml::node_type::floating_point:
            return "a floating-point number";
        case toml::node_type::boolean:
            return "a boolean";
        case toml::node_type::date:
        case toml::node_type::time:
        case toml::node_type::date_time:
            return "a date or time";
        default:
            return "nothing";
    }
}

core::TimeNs toNs(double seconds) { return static_cast<core::TimeNs>(std::llround(seconds * 1e9)); }

void Reader::fail(const std::string& path, const std::string& what) const {
    throw ScenarioError(source_ + ": " + path + ": " + what);
}

void Reader::onlyKeys(const toml::table& t, const std::string& path, std::initializer_list<std::string_view> allowed,
                      const std::string& context) const {
    for (auto&& [key, value] : t) {
        (void)value;
        bool ok = false;
        for (std::string_view a : allowed) {
            ok = ok || key.str() == a;
        }
        if (!ok) {
            fail(join(path, key.str()), context.empty() ? "unknown key" : "unknown key " + context);
        }
    }
}

const toml::node* Reader::node(const toml::table& t, const std::string& path, std::string_view key,
                               bool required) const {
    const toml::node* n = t.get(key);
    if (n == nullptr && required) {
        fail(join(path, key), "missing (required)");
    }
    return n;
}

const toml::table* Reader::table(const toml::table& t, const std::string& path, std::string_view key,
                                 bool required) const {
    const toml::node* n = node(t, path, key, required);
    if (n == nullptr) {
        return nullptr;
    }
    if (!n->is_table()) {
        fail(join(path, key), std::string("must be a table (got ") + typeName(*n) + ")");
    }
    return n->as_table();
}

double Reader::number(const toml::node& n, const std::string& path) const {
    double v = 0.0;
    if (n.is_integer()) {
        v = static_cast<double>(n.as_integer()->get());
    } else if (n.is_floating_point()) {
        v = n.as_floating_point()->get();
    } else {
        fail(path, std::string("must be a number (got ") + typeName(n) + ")");
    }
    if (!std::isfinite(v)) {
        fail(path, "must be a finite number (got " + num(v) + ")");
    }
    return v;
}

double Reader::number(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                      bool required) const {
    const toml::node* n = node(t, path, key, required);
    return n == nullptr ? fallback : number(*n, join(path, key));
}

std::int64_t Reader::integer(const toml::node& n, const std::string& path) const {
    if (!n.is_integer()) {
        fail(path, std::string("must be an integer (got ") + typeName(n) + ")");
    }
    return n.as_integer()->get();
}

std::int64_t Reader::integer(const toml::table& t, const std::string& path, std::string_view key,
                             std::int64_t fallback, bool required) const {
    const toml::node* n = node(t, path, key, required);
    return n == nullptr ? fallback : integer(*n, join(path, key));
}

bool Reader::boolean(const toml::table& t, const std::string& path, std::string_view key, bool fallback,
                     bool required) const {
    const toml::node* n = node(t, path, key, required);
    if (n == nullptr) {
        return fallback;
    }
    if (!n->is_boolean()) {
        fail(join(path, key), std::string("must be true or false (got ") + typeName(*n) + ")");
    }
    return n->as_boolean()->get();
}

std::string Reader::string(const toml::table& t, const std::string& path, std::string_view key,
                           const std::string& fallback, bool required) const {
    const toml::node* n = node(t, path, key, required);
    if (n == nullptr) {
        return fallback;
    }
    if (!n->is_string()) {
        fail(join(path, key), std::string("must be a string (got ") + typeName(*n) + ")");
    }
    return n->as_string()->get();
}

const toml::array& Reader::tableArray(const toml::node& n, const std::string& p) const {
    const toml::array* a = n.as_array();
    if (a == nullptr) {
        fail(p, "must be an array of tables ([[" + p + "]]) (got " + typeName(n) + ")");
    }
    for (std::size_t i = 0; i < a->size(); ++i) {
        const toml::node& e = *a->get(i);
        if (!e.is_table()) {
            fail(indexed(p, i), std::string("must be a table (got ") + typeName(e) + ")");
        }
    }
    return *a;
}

void Reader::above(const std::string& path, double v, double lo) const {
    if (!(v > lo)) {
        fail(path, "must be > " + num(lo) + " (got " + num(v) + ")");
    }
}

void Reader::atLeast(const std::string& path, double v, double lo) const {
    if (!(v >= lo)) {
        fail(path, "must be >= " + num(lo) + " (got " + num(v) + ")");
    }
}

void Reader::within(const std::string& path, double v, double lo, double hi) const {
    if (!(v >= lo && v <= hi)) {
        fail(path, "must be in [" + num(lo) + ", " + num(hi) + "] (got " + num(v) + ")");
    }
}

void Reader::withinOpenLow(const std::string& path, double v, double lo, double hi) const {
    if (!(v > lo && v <= hi)) {
        fail(path, "must be in (" + num(lo) + ", " + num(hi) + "] (got " + num(v) + ")");
    }
}

double Reader::positive(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                        double hi, bool required) const {
    const double v = number(t, path, key, fallback, required);
    withinOpenLow(join(path, key), v, 0.0, hi);
    return v;
}

double Reader::ranged(const toml::table& t, const std::string& path, std::string_view key, double fallback, double lo,
                      double hi, bool required) const {
    const double v = number(t, path, key, fallback, required);
    within(join(path, key), v, lo, hi);
    return v;
}

}  // namespace rse::sim::scenario_toml
