#include "sim_stub/montecarlo/results.hpp"

#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <initializer_list>
#include <sstream>

namespace rse::sim::mc {

namespace {

// The R line's fields after seed, outcome and reason, in the order written.
// The counts, with their label in the table's "per run" section (none:
// shown in a section of its own).
struct CountField {
    const char* key;
    std::uint32_t Row::*member;
    const char* label;
};
constexpr CountField kCountFields[] = {
    {"collisions", &Row::collisions, nullptr},
    {"plans", &Row::plans, "plans made"},
    {"legs_sent", &Row::legsSent, "legs sent"},
    {"legs_achieved", &Row::legsAchieved, "legs achieved"},
    {"fail_ups", &Row::failUps, "fail-ups"},
    {"replans", &Row::replans, "replans"},
    {"bound_relax", &Row::boundRelaxations, "bound relaxations"},
    {"risk_relax", &Row::riskRelaxations, "risk relaxations"},
    {"call_homes", &Row::callHomes, "call homes"},
    {"hab_replans", &Row::habitualReplans, "habitual replans"},
    {"look_aheads", &Row::lookAheads, "look-aheads (next horizons planned while driving)"},
};
struct RealField {
    const char* key;
    double Row::*member;
    int digits;    // after the point, or significant (general)
    bool general;  // %g style (risks), else fixed
};
constexpr RealField kRealFields[] = {
    {"t", &Row::outcomeS, 3, false},           {"dist", &Row::distanceM, 3, false},
    {"energy", &Row::energyWh, 4, false},      {"goal_dist", &Row::goalDistanceM, 3, false},
    {"clearance", &Row::clearanceM, 3, false}, {"risk_bound", &Row::riskBound, 6, true},
    {"risk_in_force", &Row::riskInForce, 6, true}, {"risk_used", &Row::riskUsed, 6, true},
};

// v with `decimals` after the point, right-aligned in `width` (0: as long as it is).
std::string fixed(double v, int width, int decimals) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%*.*f", width, decimals, v);
    return buf;
}

// v in %g style with `digits` significant digits.
std::string general(double v, int digits) {
    char buf[64];
    std::snprintf(buf, sizeof buf, "%.*g", digits, v);
    return buf;
}

template <typename T, typename F>
std::string joinList(const std::vector<T>& v, F one) {
    if (v.empty()) {
        return "-";
    }
    std::string s;
    for (std::size_t i = 0; i < v.size(); ++i) {
        s += (i == 0 ? "" : ",") + one(v[i]);
    }
    return s;
}

bool parseReal(const std::string& text, double* v) {
    if (text.empty()) {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    *v = std::strtod(text.c_str(), &end);
    return *end == '\0' && errno == 0 && std::isfinite(*v);
}

bool parseUnsigned(const std::string& text, std::uint64_t* v) {
    if (text.empty() || text[0] < '0' || text[0] > '9') {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    const unsigned long long u = std::strtoull(text.c_str(), &end, 10);
    *v = u;
    return *end == '\0' && errno == 0;
}

bool parseCount(const std::string& text, std::uint32_t* v) {
    std::uint64_t u = 0;
    if (!parseUnsigned(text, &u) || u > 0xFFFFFFFFULL) {
        return false;
    }
    *v = static_cast<std::uint32_t>(u);
    return true;
}

std::vector<std::string> split(const std::string& text, char sep) {
    std::vector<std::string> out;
    std::size_t start = 0;
    for (std::size_t at = text.find(sep); at != std::string::npos; at = text.find(sep, start)) {
        out.push_back(text.substr(start, at - start));
        start = at + 1;
    }
    out.push_back(text.substr(start));
    return out;
}

// "X key=value key=value": the record letter and its fields; false when a
// field is not key=value or a key comes twice.
bool splitRecord(const std::string& line, char* kind, std::map<std::string, std::string>* fields,
                 std::string* error) {
    const std::vector<std::string> words = split(line, ' ');
    if (words.empty() || words[0].size() != 1) {
        *error = "not a record";
        return false;
    }
    *kind = words[0][0];
    fields->clear();
    for (std::size_t i = 1; i < words.size(); ++i) {
        const std::size_t eq = words[i].find('=');
        if (eq == std::string::npos || eq == 0) {
            *error = "field '" + words[i] + "' is not key=value";
            return false;
        }
        if (!fields->emplace(words[i].substr(0, eq), words[i].substr(eq + 1)).second) {
            *error = "key '" + words[i].substr(0, eq) + "' twice";
            return false;
        }
    }
    return true;
}

bool take(const std::map<std::string, std::string>& f, const char* key, std::string* value, std::string* error) {
    const auto it = f.find(key);
    if (it == f.end()) {
        *error = std::string("no '") + key + "' field";
        return false;
    }
    *value = it->second;
    return true;
}

template <typename T, typename P>
bool parseList(const std::string& text, std::vector<T>* out, P one) {
    out->clear();
    if (text == "-") {
        return true;
    }
    for (const std::string& item : split(text, ',')) {
        T v{};
        if (!one(item, &v)) {
            return false;
        }
        out->push_back(v);
    }
    return true;
}

bool parseFlag(const std::string& text, std::uint8_t* v) {
    if (text != "0" && text != "1") {
        return false;
    }
    *v = text == "1" ? 1 : 0;
    return true;
}

std::string ms(double v) { return fixed(v, 0, 3); }

std::vector<double> sorted(std::vector<double> v) {
    std::sort(v.begin(), v.end());
    return v;
}

}  // namespace

double percentile(const std::vector<double>& v, double q) {
    const double rank = std::ceil(q * static_cast<double>(v.size()));
    std::size_t i = rank < 1.0 ? 0 : static_cast<std::size_t>(rank) - 1;
    return v[std::min(i, v.size() - 1)];
}

std::string formatRow(const Row& r) {
    std::string s = "R seed=" + std::to_string(r.seed) + " outcome=" + r.outcome + " reason=" + r.reason;
    for (const CountField& f : kCountFields) {
        s += std::string(" ") + f.key + "=" + std::to_string(r.*f.member);
    }
    for (const RealField& f : kRealFields) {
        s += std::string(" ") + f.key + "=" + (f.general ? general(r.*f.member, f.digits) : fixed(r.*f.member, 0, f.digits));
    }
    s += " plan_s=" + joinList(r.planLatencyS, ms);
    s += " plan_slices=" + joinList(r.planSlices, [](std::uint32_t v) { return std::to_string(v); });
    s += " plan_found=" + joinList(r.planFound, [](std::uint8_t v) { return std::to_string(v); });
    s += " field=" + r.field + " rocks=" + r.rocks + " faults=" + r.faults;
    return s;
}

bool parseRow(const std::string& line, Row* r, std::string* error) {
    char kind = 0;
    std::map<std::string, std::string> f;
    if (!splitRecord(line, &kind, &f, error)) {
        return false;
    }
    if (kind != 'R') {
        *error = "not an R line";
        return false;
    }
    std::string v;
    Row row;
    if (!take(f, "seed", &v, error) || !parseUnsigned(v, &row.seed) || !take(f, "outcome", &row.outcome, error) ||
        !take(f, "reason", &row.reason, error)) {
        *error = error->empty() ? "bad seed" : *error;
        return false;
    }
    for (const CountField& c : kCountFields) {
        if (!take(f, c.key, &v, error) || !parseCount(v, &(row.*c.member))) {
            *error = std::string("bad or missing '") + c.key + "'";
            return false;
        }
    }
    for (const RealField& c : kRealFields) {
        if (!take(f, c.key, &v, error) || !parseReal(v, &(row.*c.member))) {
            *error = std::string("bad or missing '") + c.key + "'";
            return false;
        }
    }
    std::string lat, slices, found;
    if (!take(f, "plan_s", &lat, error) || !take(f, "plan_slices", &slices, error) ||
        !take(f, "plan_found", &found, error) || !take(f, "field", &row.field, error) ||
        !take(f, "rocks", &row.rocks, error) ||
        !take(f, "faults", &row.faults, error)) {
        return false;
    }
    std::uint64_t fieldSeed = 0;
    if (row.field != "-" && !parseUnsigned(row.field, &fieldSeed)) {
        *error = "bad 'field' (a field's seed, or -)";
        return false;
    }
    if (!parseList(lat, &row.planLatencyS, parseReal) || !parseList(slices, &row.planSlices, parseCount) ||
        !parseList(found, &row.planFound, parseFlag) || row.planSlices.size() != row.planLatencyS.size() ||
        row.planFound.size() != row.planLatencyS.size()) {
        *error = "bad plan_s / plan_slices / plan_found lists";
        return false;
    }
    *r = row;
    return true;
}

std::string formatTiming(const Timing& t) {
    return "T seed=" + std::to_string(t.seed) + " wall_s=" + fixed(t.wallS, 0, 4) + " cpu_s=" + fixed(t.cpuS, 0, 4) +
           " plan_host_ms=" + joinList(t.planHostMs, ms);
}

bool parseTiming(const std::string& line, Timing* t, std::string* error) {
    char kind = 0;
    std::map<std::string, std::string> f;
    if (!splitRecord(line, &kind, &f, error)) {
        return false;
    }
    std::string seed, wall, cpu, plans;
    Timing out;
    if (kind != 'T' || !take(f, "seed", &seed, error) || !take(f, "wall_s", &wall, error) ||
        !take(f, "cpu_s", &cpu, error) || !take(f, "plan_host_ms", &plans, error) ||
        !parseUnsigned(seed, &out.seed) || !parseReal(wall, &out.wallS) || !parseReal(cpu, &out.cpuS) ||
        !parseList(plans, &out.planHostMs, parseReal)) {
        *error = error->empty() ? "bad T line" : *error;
        return false;
    }
    *t = out;
    return true;
}

std::string blockLine(std::uint64_t first, std::uint64_t count, long task, int jobs) {
    char host[256] = "?";
    if (gethostname(host, sizeof host - 1) != 0) {
        std::strcpy(host, "?");
    }
    std::string s = "B first=" + std::to_string(first) + " count=" + std::to_string(count) +
                    " task=" + (task < 0 ? std::string("-") : std::to_string(task)) + " jobs=" + std::to_string(jobs) +
                    " host=" + host;
    const char* job = std::getenv("SLURM_ARRAY_JOB_ID");
    s += std::string(" slurm_job=") + (job != nullptr && *job != '\0' ? job : "-");
    return s;
}

bool addResultText(const std::string& text, const std::string& path, ResultSet* set, std::string* error) {
    std::istringstream in(text);
    std::string line;
    std::size_t lineNo = 0;
    std::size_t rowCount = 0;
    bool campaignSeen = false;
    bool ended = false;
    const auto fail = [&](const std::string& why) {
        *error = path + ":" + std::to_string(lineNo) + ": " + why;
        return false;
    };
    while (std::getline(in, line)) {
        ++lineNo;
        if (line.empty() || line[0] == '#') {
            continue;
        }
        if (ended) {
            return fail("a record after the E line");
        }
        char kind = 0;
        std::map<std::string, std::string> f;
        std::string why;
        if (!splitRecord(line, &kind, &f, &why)) {
            return fail(why);
        }
        if (kind != 'C' && !campaignSeen) {
            return fail("no C line before the first record");
        }
        if (kind == 'C') {
            if (campaignSeen) {
                return fail("a second C line");
            }
            campaignSeen = true;
            if (set->campaign.empty()) {
                std::uint64_t first = 0, count = 0;
                if (f["format"] != std::to_string(kFormatVersion) || !parseUnsigned(f["first"], &first) ||
                    !parseUnsigned(f["count"], &count)) {
                    return fail("C line of another format, or without first= and count=");
                }
                set->campaign = line;
                set->fields = f;
                set->firstSeed = first;
                set->seedCount = count;
            } else if (line != set->campaign) {
                return fail("another campaign: '" + line + "' is not '" + set->campaign + "'");
            }
        } else if (kind == 'B') {
            // Where the block ran: for the reader (and the Slurm test), not the table.
        } else if (kind == 'R') {
            Row row;
            if (!parseRow(line, &row, &why)) {
                return fail(why);
            }
            const auto known = set->rowText.find(row.seed);
            if (known != set->rowText.end() && known->second != line) {
                return fail("seed " + std::to_string(row.seed) + " again with another result (not reproducible?)");
            }
            set->rowText[row.seed] = line;
            set->rows[row.seed] = row;
            ++rowCount;
        } else if (kind == 'T') {
            Timing t;
            if (!parseTiming(line, &t, &why)) {
                return fail(why);
            }
            set->timings[t.seed] = t;
        } else if (kind == 'E') {
            std::uint64_t rows = 0;
            if (!parseUnsigned(f["rows"], &rows) || rows != rowCount) {
                return fail("E line says rows=" + f["rows"] + " but the file has " + std::to_string(rowCount));
            }
            ended = true;
        } else {
            return fail(std::string("unknown record '") + kind + "'");
        }
    }
    if (!ended) {
        *error = path + ": no E line: the file is incomplete (its writer stopped early?)";
        return false;
    }
    ++set->files;
    return true;
}

bool addResultFile(const std::string& path, ResultSet* set, std::string* error) {
    std::ifstream in(path);
    if (!in) {
        *error = path + ": " + std::strerror(errno);
        return false;
    }
    std::ostringstream text;
    text << in.rdbuf();
    return addResultText(text.str(), path, set, error);
}

std::vector<std::uint64_t> missingSeeds(const ResultSet& set) {
    std::vector<std::uint64_t> missing;
    for (std::uint64_t s = set.firstSeed; s - set.firstSeed < set.seedCount; ++s) {
        if (set.rows.count(s) == 0) {
            missing.push_back(s);
        }
    }
    return missing;
}

std::vector<std::uint64_t> strangerSeeds(const ResultSet& set) {
    std::vector<std::uint64_t> out;
    for (const auto& [seed, row] : set.rows) {
        if (seed < set.firstSeed || seed - set.firstSeed >= set.seedCount) {
            out.push_back(seed);
        }
    }
    return out;
}

bool writeResultFile(const std::string& path, const std::string& campaign, const std::string& block,
                     const std::vector<std::pair<std::string, std::string>>& rowAndTiming, std::string* error) {
    const std::string tmp = path + ".tmp." + std::to_string(getpid());
    {
        std::ofstream out(tmp, std::ios::trunc);
        out << "# rse-montecarlo result file (docs/montecarlo.md, \"Result files\")\n"
            << campaign << "\n"
            << block << "\n";
        for (const auto& [row, timing] : rowAndTiming) {
            out << row << "\n";
            if (!timing.empty()) {
                out << timing << "\n";
            }
        }
        out << "E rows=" << rowAndTiming.size() << "\n";
        out.flush();
        if (!out) {
            *error = tmp + ": write failed";
            std::remove(tmp.c_str());
            return false;
        }
    }
    if (std::rename(tmp.c_str(), path.c_str()) != 0) {
        *error = path + ": " + std::strerror(errno);
        std::remove(tmp.c_str());
        return false;
    }
    return true;
}

namespace {

constexpr const char* kOutcomeOrder[] = {"goal_reached", "called_home", "timed_out", "setup_failed", "crashed"};

std::string field(const ResultSet& set, const char* key) {
    const auto it = set.fields.find(key);
    return it == set.fields.end() ? "?" : it->second;
}

std::string percent(std::size_t n, std::size_t of) {
    return fixed(of == 0 ? 0.0 : 100.0 * static_cast<double>(n) / static_cast<double>(of), 9, 1);
}

std::string padded(const std::string& label, int width) {
    std::string s = label;
    if (static_cast<int>(s.size()) < width) {
        s.append(static_cast<std::size_t>(width - static_cast<int>(s.size())), ' ');
    }
    return s;
}

// A section's first line: its title, then the column names over 9-wide cells.
std::string heading(const std::string& title, std::initializer_list<const char*> columns) {
    std::string s = padded(title, 32);
    for (const char* c : columns) {
        std::string name(c);
        s += std::string(name.size() < 9 ? 9 - name.size() : 1, ' ') + name;
    }
    return s + "\n";
}

std::string cells(const std::vector<double>& values, int decimals, bool total) {
    std::string s;
    const int n = total ? 6 : 5;
    if (values.empty()) {
        for (int i = 0; i < n; ++i) {
            s += "        -";
        }
        return s;
    }
    const std::vector<double> v = sorted(values);
    double sum = 0.0;
    for (double x : v) {
        sum += x;
    }
    const double c[] = {sum / static_cast<double>(v.size()), percentile(v, 0.5), percentile(v, 0.9),
                        percentile(v, 0.99), v.back(), sum};
    for (int i = 0; i < n; ++i) {
        s += fixed(c[i], 9, decimals);
    }
    return s;
}

struct CheckResult {
    std::size_t withinCollided = 0;
    std::size_t broken = 0;  // crashed or not set up
};

CheckResult checks(const ResultSet& set) {
    CheckResult c;
    for (const auto& [seed, r] : set.rows) {
        c.withinCollided += r.withinRiskBound() && r.collisions > 0 ? 1U : 0U;
        c.broken += r.outcome == "crashed" || r.outcome == "setup_failed" ? 1U : 0U;
    }
    return c;
}

// The outcomes, with the call homes (and the crashes) by reason.
void outcomeSection(const ResultSet& set, std::ostream& t) {
    const std::size_t n = set.rows.size();
    std::map<std::string, std::size_t> outcomes;
    std::map<std::string, std::map<std::string, std::size_t>> reasons;
    for (const auto& [seed, r] : set.rows) {
        ++outcomes[r.outcome];
        if (r.outcome == "called_home" || r.outcome == "crashed") {
            ++reasons[r.outcome][r.reason];
        }
    }
    t << "\n" << heading("outcome", {"runs", "%"});
    std::vector<std::string> order(std::begin(kOutcomeOrder), std::end(kOutcomeOrder));
    for (const auto& [name, count] : outcomes) {
        if (std::find(order.begin(), order.end(), name) == order.end()) {
            order.push_back(name);
        }
    }
    for (const std::string& name : order) {
        const std::size_t count = outcomes.count(name) != 0 ? outcomes.at(name) : 0;
        t << "  " << padded(name, 30) << fixed(static_cast<double>(count), 9, 0) << percent(count, n) << "\n";
        for (const auto& [reason, rc] : reasons[name]) {
            t << "    " << padded(reason, 28) << fixed(static_cast<double>(rc), 9, 0) << percent(rc, n) << "\n";
        }
    }
}

// Collisions, split by whether every plan was within the risk bound, and the runs that collided.
void collisionSection(const ResultSet& set, std::ostream& t) {
    std::size_t runs[2] = {0, 0}, collided[2] = {0, 0}, contacts[2] = {0, 0};
    std::vector<std::string> listed;
    for (const auto& [seed, r] : set.rows) {
        const int k = r.withinRiskBound() ? 0 : 1;
        ++runs[k];
        collided[k] += r.collisions > 0 ? 1 : 0;
        contacts[k] += r.collisions;
        if (r.collisions > 0) {
            listed.push_back("seed " + std::to_string(seed) + " (" + std::to_string(r.collisions) +
                             (r.collisions == 1 ? " contact, " : " contacts, ") +
                             (k == 0 ? "within the bound" : "bound relaxed") + ")");
        }
    }
    t << "\n" << heading("collisions", {"runs", "collided", "contacts"});
    t << "  " << padded("plans within the risk bound", 30) << fixed(static_cast<double>(runs[0]), 9, 0)
      << fixed(static_cast<double>(collided[0]), 9, 0) << fixed(static_cast<double>(contacts[0]), 9, 0)
      << "   (must be 0)\n";
    t << "  " << padded("risk bound relaxed", 30) << fixed(static_cast<double>(runs[1]), 9, 0)
      << fixed(static_cast<double>(collided[1]), 9, 0) << fixed(static_cast<double>(contacts[1]), 9, 0) << "\n";
    t << "  collided runs:";
    if (listed.empty()) {
        t << " none\n";
    } else {
        for (std::size_t i = 0; i < listed.size(); ++i) {
            t << (i % 4 == 0 ? "\n    " : ", ") << listed[i];
        }
        t << "\n";
    }
}

// The per-run counters.
void perRunSection(const ResultSet& set, std::ostream& t) {
    t << "\n" << heading("per run", {"mean", "p50", "p90", "p99", "max", "total"});
    for (const CountField& c : kCountFields) {
        if (c.label == nullptr) {
            continue;
        }
        std::vector<double> v;
        for (const auto& [seed, r] : set.rows) {
            v.push_back(r.*c.member);
        }
        t << "  " << padded(c.label, 30) << cells(v, 2, true) << "\n";
    }
}

// Time, energy and distance to the goal and over every run; the least clearance.
void distanceSections(const ResultSet& set, std::ostream& t) {
    std::vector<double> time, energy, dist, clearance, allTime, allEnergy, allDist;
    for (const auto& [seed, r] : set.rows) {
        if (r.outcome == "goal_reached") {
            time.push_back(r.outcomeS);
            energy.push_back(r.energyWh);
            dist.push_back(r.distanceM);
        }
        if (r.outcome != "crashed" && r.outcome != "setup_failed") {
            clearance.push_back(r.clearanceM);
            allTime.push_back(r.outcomeS);
            allEnergy.push_back(r.energyWh);
            allDist.push_back(r.distanceM);
        }
    }
    t << "\n" << heading("to the goal (" + std::to_string(time.size()) + " runs)", {"mean", "p50", "p90", "p99", "max"});
    t << "  " << padded("time (s)", 30) << cells(time, 2, false) << "\n";
    t << "  " << padded("energy (Wh)", 30) << cells(energy, 3, false) << "\n";
    t << "  " << padded("distance driven (m)", 30) << cells(dist, 2, false) << "\n";
    t << heading("every run (" + std::to_string(allTime.size()) + ")", {"mean", "p50", "p90", "p99", "max"});
    t << "  " << padded("time of the outcome (s)", 30) << cells(allTime, 2, false) << "\n";
    t << "  " << padded("energy (Wh)", 30) << cells(allEnergy, 3, false) << "\n";
    t << "  " << padded("distance driven (m)", 30) << cells(allDist, 2, false) << "\n";
    const std::vector<double> cl = sorted(clearance);
    t << heading("least clearance to a rock (m)", {"min", "p1", "p10", "p50"});
    if (cl.empty()) {
        t << "  " << padded("all runs", 30) << "        -        -        -        -\n";
    } else {
        t << "  " << padded("all runs", 30) << fixed(cl.front(), 9, 3) << fixed(percentile(cl, 0.01), 9, 3)
          << fixed(percentile(cl, 0.1), 9, 3) << fixed(percentile(cl, 0.5), 9, 3) << "\n";
    }
}

// The planner, per plan: its wait and its slices.
void plannerSection(const ResultSet& set, std::ostream& t) {
    std::vector<double> latency, slices;
    std::size_t found = 0;
    for (const auto& [seed, r] : set.rows) {
        for (std::size_t i = 0; i < r.planLatencyS.size(); ++i) {
            latency.push_back(r.planLatencyS[i]);
            slices.push_back(r.planSlices[i]);
            found += r.planFound[i];
        }
    }
    t << "\nplanner: " << latency.size() << " plans, " << found << " found\n"
      << heading("  per plan", {"mean", "p50", "p90", "p99", "max"});
    t << "  " << padded("wait for the plan (sim. s)", 30) << cells(latency, 3, false) << "\n";
    t << "  " << padded("planner slices (runs)", 30) << cells(slices, 2, false) << "\n";
}

// The table's checks.
void checkLines(const ResultSet& set, std::ostream& t) {
    const CheckResult c = checks(set);
    t << "\nCHECK collisions in runs whose plans were within the risk bound: " << c.withinCollided
      << " (must be 0) " << (c.withinCollided == 0 ? "PASS" : "FAIL") << "\n";
    t << "CHECK runs that crashed or could not be set up: " << c.broken << " (must be 0) "
      << (c.broken == 0 ? "PASS" : "FAIL") << "\n";
}

}  // namespace

std::string formatTable(const ResultSet& set) {
    std::ostringstream t;
    const std::size_t n = set.rows.size();
    const std::uint64_t first = set.firstSeed;
    const std::uint64_t last = set.seedCount == 0 ? first : first + set.seedCount - 1;
    t << "=== rse-montecarlo: " << n << " runs of seeds " << first << ".." << last << " (" << set.seedCount
      << " in the campaign)\n";
    t << "campaign: scenario " << field(set, "scenario") << " (fnv " << field(set, "scenario_fnv") << "), GOTO "
      << field(set, "goal") << " risk bound " << field(set, "risk") << ", up to " << field(set, "duration")
      << " s, faults " << field(set, "faults") << ", variation " << field(set, "variation") << "\n";

    outcomeSection(set, t);
    collisionSection(set, t);
    perRunSection(set, t);
    distanceSections(set, t);
    plannerSection(set, t);
    checkLines(set, t);
    return t.str();
}

int failedChecks(const ResultSet& set) {
    const CheckResult c = checks(set);
    return (c.withinCollided == 0 ? 0 : 1) + (c.broken == 0 ? 0 : 1);
}

std::string formatHostTiming(const ResultSet& set) {
    std::vector<double> planMs, wall, cpu;
    for (const auto& [seed, tm] : set.timings) {
        planMs.insert(planMs.end(), tm.planHostMs.begin(), tm.planHostMs.end());
        wall.push_back(tm.wallS);
        cpu.push_back(tm.cpuS);
    }
    std::ostringstream t;
    t << "host timing (" << set.timings.size() << " runs; measured where they ran: not reproducible, not part of "
      << "the table)\n";
    t << heading("", {"mean", "p50", "p90", "p99", "max", "total"});
    t << "  " << padded("planner per plan (host ms)", 30) << cells(planMs, 3, true) << "\n";
    t << "  " << padded("mission wall time (s)", 30) << cells(wall, 3, true) << "\n";
    t << "  " << padded("mission CPU time (s)", 30) << cells(cpu, 3, true) << "\n";
    return t.str();
}

}  // namespace rse::sim::mc
