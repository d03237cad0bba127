#include "sim_stub/scenario/scenario_parser.hpp"

#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <utility>
#include <vector>

#include <toml++/toml.h>

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::sim {

namespace {

constexpr double kMaxTimeS = 1e7;  // about four months: far beyond any run, far below TimeNs overflow

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

class Parser {
public:
    explicit Parser(std::string source) : source_(std::move(source)) {}

    Scenario parse(std::string_view text);

private:
    [[noreturn]] void fail(const std::string& path, const std::string& what) const {
        throw ScenarioError(source_ + ": " + path + ": " + what);
    }

    void onlyKeys(const toml::table& t, const std::string& path, std::initializer_list<std::string_view> allowed,
                  const std::string& context = {}) const {
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

    const toml::node* node(const toml::table& t, const std::string& path, std::string_view key,
                           bool required) const {
        const toml::node* n = t.get(key);
        if (n == nullptr && required) {
            fail(join(path, key), "missing (required)");
        }
        return n;
    }

    const toml::table* table(const toml::table& t, const std::string& path, std::string_view key,
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

    double number(const toml::node& n, const std::string& path) const {
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

    double number(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                  bool required = false) const {
        const toml::node* n = node(t, path, key, required);
        return n == nullptr ? fallback : number(*n, join(path, key));
    }

    std::int64_t integer(const toml::node& n, const std::string& path) const {
        if (!n.is_integer()) {
            fail(path, std::string("must be an integer (got ") + typeName(n) + ")");
        }
        return n.as_integer()->get();
    }

    std::int64_t integer(const toml::table& t, const std::string& path, std::string_view key, std::int64_t fallback,
                         bool required = false) const {
        const toml::node* n = node(t, path, key, required);
        return n == nullptr ? fallback : integer(*n, join(path, key));
    }

    bool boolean(const toml::table& t, const std::string& path, std::string_view key, bool fallback,
                 bool required = false) const {
        const toml::node* n = node(t, path, key, required);
        if (n == nullptr) {
            return fallback;
        }
        if (!n->is_boolean()) {
            fail(join(path, key), std::string("must be true or false (got ") + typeName(*n) + ")");
        }
        return n->as_boolean()->get();
    }

    std::string string(const toml::table& t, const std::string& path, std::string_view key,
                       const std::string& fallback, bool required = false) const {
        const toml::node* n = node(t, path, key, required);
        if (n == nullptr) {
            return fallback;
        }
        if (!n->is_string()) {
            fail(join(path, key), std::string("must be a string (got ") + typeName(*n) + ")");
        }
        return n->as_string()->get();
    }

    // An array of tables ([[p]]): every element must be a table.
    const toml::array& tableArray(const toml::node& n, const std::string& p) const {
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
    void above(const std::string& path, double v, double lo) const {
        if (!(v > lo)) {
            fail(path, "must be > " + num(lo) + " (got " + num(v) + ")");
        }
    }
    void atLeast(const std::string& path, double v, double lo) const {
        if (!(v >= lo)) {
            fail(path, "must be >= " + num(lo) + " (got " + num(v) + ")");
        }
    }
    void within(const std::string& path, double v, double lo, double hi) const {
        if (!(v >= lo && v <= hi)) {
            fail(path, "must be in [" + num(lo) + ", " + num(hi) + "] (got " + num(v) + ")");
        }
    }
    void withinOpenLow(const std::string& path, double v, double lo, double hi) const {
        if (!(v > lo && v <= hi)) {
            fail(path, "must be in (" + num(lo) + ", " + num(hi) + "] (got " + num(v) + ")");
        }
    }

    // Reads key as a number in (lo, hi] (positive quantities) or [lo, hi].
    double positive(const toml::table& t, const std::string& path, std::string_view key, double fallback,
                    double hi, bool required = false) const {
        const double v = number(t, path, key, fallback, required);
        withinOpenLow(join(path, key), v, 0.0, hi);
        return v;
    }
    double ranged(const toml::table& t, const std::string& path, std::string_view key, double fallback, double lo,
                  double hi, bool required = false) const {
        const double v = number(t, path, key, fallback, required);
        within(join(path, key), v, lo, hi);
        return v;
    }

    void parseRover(const toml::table& t, RoverParams* rover) const;
    void parseBattery(const toml::table& t, BatteryParams* battery) const;
    void parseSolar(const toml::table& t, SolarParams* solar) const;
    void parseMap(const toml::table& t, MapBounds* map) const;
    void parseObstacles(const toml::node& n, const MapBounds& map, std::vector<Obstacle>* out) const;
    void parseStart(const toml::table& t, const Scenario& s, Pose2* start) const;
    void parseDevices(const toml::table& t, DeviceParams* devices) const;
    void parseInstrument(const toml::table& devices, const std::string& path, hal::instrument::Kind kind,
                         InstrumentParams* params) const;
    void parseTargets(const toml::node& n, const MapBounds& map, std::vector<ScienceTarget>* out) const;
    void parseDrives(const toml::table& t, DriveNoiseParams* drives) const;
    void parseFaults(const toml::node& n, std::vector<FaultSpec>* out) const;
    FaultSpec parseFault(const toml::table& t, const std::string& path) const;
    std::size_t wheel(const toml::table& t, const std::string& path) const;
    SimDevice device(const toml::table& t, const std::string& path, bool instrumentsOnly = false) const;
    std::uint32_t cobId(const toml::table& t, const std::string& path, std::string_view key, std::uint32_t fallback,
                        bool required) const;
    core::TimeNs intervalEnd(const toml::table& t, const std::string& path, double atS) const;
    // task_stall's `task`: a rate-group row (integer) or a task name (string).
    void parseTask(const toml::table& t, const std::string& path, FaultSpec* f) const;
    void parseMission(const toml::table& t, const MapBounds& map, MissionSpec* mission) const;

    std::string source_;
};

void Parser::parseRover(const toml::table& t, RoverParams* r) const {
    const std::string p = "rover";
    onlyKeys(t, p,
             {"wheel_radius_m", "track_width_m", "mass_kg", "radius_m", "skid_factor", "gravity_m_s2",
              "rolling_coefficient", "turn_torque_nm_per_rad_s", "slide_friction", "slip_sigma", "drive_nodes"});
    r->wheelRadiusM = positive(t, p, "wheel_radius_m", r->wheelRadiusM, 2.0);
    r->trackWidthM = positive(t, p, "track_width_m", r->trackWidthM, 10.0);
    r->massKg = positive(t, p, "mass_kg", r->massKg, 10000.0);
    r->radiusM = number(t, p, "radius_m", r->radiusM);
    above(join(p, "radius_m"), r->radiusM, 0.0);
    within(join(p, "radius_m"), r->radiusM, 0.0, 10.0);
    r->skidFactor = ranged(t, p, "skid_factor", r->skidFactor, 1.0, 10.0);
    r->gravityMS2 = positive(t, p, "gravity_m_s2", r->gravityMS2, 30.0);
    r->rollingCoefficient = ranged(t, p, "rolling_coefficient", r->rollingCoefficient, 0.0, 1.0);
    r->turnTorquePerRadS = ranged(t, p, "turn_torque_nm_per_rad_s", r->turnTorquePerRadS, 0.0, 1000.0);
    r->slideFriction = ranged(t, p, "slide_friction", r->slideFriction, 0.0, 2.0);
    r->slipSigma = ranged(t, p, "slip_sigma", r->slipSigma, 0.0, 0.5);
    if (const toml::node* n = node(t, p, "drive_nodes", false)) {
        const std::string np = join(p, "drive_nodes");
        const toml::array* a = n->as_array();
        if (a == nullptr) {
            fail(np, std::string("must be an array of ") + std::to_string(kWheelCount) + " node ids (got " +
                         typeName(*n) + ")");
        }
        if (a->size() != kWheelCount) {
            fail(np, "must list " + std::to_string(kWheelCount) + " node ids (got " + std::to_string(a->size()) +
                         ")");
        }
        for (std::size_t i = 0; i < kWheelCount; ++i) {
            const std::string ip = indexed(np, i);
            const std::int64_t id = integer(*a->get(i), ip);
            if (id < 1 || id > 127) {
                fail(ip, "must be 1..127 (got " + std::to_string(id) + ")");
            }
            if (id >= kImuNodeId && id <= hal::instrument::kCameraNodeId) {
                fail(ip, "node " + std::to_string(id) + " belongs to an RSE device (0x20-0x25)");
            }
            for (std::size_t j = 0; j < i; ++j) {
                if (r->driveNodes[j] == id) {
                    fail(ip, "node " + std::to_string(id) + " is listed twice");
                }
            }
            r->driveNodes[i] = static_cast<std::uint8_t>(id);
        }
    }
}

void Parser::parseBattery(const toml::table& t, BatteryParams* b) const {
    const std::string p = "battery";
    onlyKeys(t, p, {"capacity_ah", "initial_soc", "base_load_w", "internal_resistance_ohm"});
    b->capacityAh = positive(t, p, "capacity_ah", b->capacityAh, 10000.0);
    b->initialSoc = ranged(t, p, "initial_soc", b->initialSoc, 0.0, 1.0);
    b->baseLoadW = ranged(t, p, "base_load_w", b->baseLoadW, 0.0, 10000.0);
    b->internalResistanceOhm = ranged(t, p, "internal_resistance_ohm", b->internalResistanceOhm, 0.0, 10.0);
}

void Parser::parseSolar(const toml::table& t, SolarParams* s) const {
    const std::string p = "solar";
    onlyKeys(t, p, {"profile", "peak_current_a", "day_length_s", "day_phase"});
    const std::string profile = string(t, p, "profile", "constant");
    if (profile == "constant") {
        s->profile = SolarProfile::kConstant;
    } else if (profile == "day") {
        s->profile = SolarProfile::kDay;
    } else {
        fail(join(p, "profile"), "unknown profile \"" + profile + "\" (expected constant or day)");
    }
    s->peakCurrentA = ranged(t, p, "peak_current_a", s->peakCurrentA, 0.0, 100.0);
    s->dayLengthS = positive(t, p, "day_length_s", s->dayLengthS, kMaxTimeS);
    s->phase = number(t, p, "day_phase", s->phase);
    if (!(s->phase >= 0.0 && s->phase < 1.0)) {
        fail(join(p, "day_phase"), "must be in [0, 1) (got " + num(s->phase) + ")");
    }
}

void Parser::parseMap(const toml::table& t, MapBounds* m) const {
    const std::string p = "map";
    onlyKeys(t, p, {"x_min_m", "x_max_m", "y_min_m", "y_max_m"});
    m->xMin = ranged(t, p, "x_min_m", 0.0, -1e5, 1e5, true);
    m->xMax = ranged(t, p, "x_max_m", 0.0, -1e5, 1e5, true);
    m->yMin = ranged(t, p, "y_min_m", 0.0, -1e5, 1e5, true);
    m->yMax = ranged(t, p, "y_max_m", 0.0, -1e5, 1e5, true);
    if (!(m->xMax > m->xMin)) {
        fail(join(p, "x_max_m"), "must be greater than x_min_m (" + num(m->xMin) + ")");
    }
    if (!(m->yMax > m->yMin)) {
        fail(join(p, "y_max_m"), "must be greater than y_min_m (" + num(m->yMin) + ")");
    }
}

void Parser::parseObstacles(const toml::node& n, const MapBounds& map, std::vector<Obstacle>* out) const {
    const std::string p = "obstacles";
    const toml::array& a = tableArray(n, p);
    out->reserve(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string op = indexed(p, i);
        const toml::table& t = *a.get(i)->as_table();
        onlyKeys(t, op, {"id", "known", "vertices"});
        Obstacle o;
        o.id = uniqueId(t, p, i, *out);
        o.known = boolean(t, op, "known", true, true);
        const std::string vp = join(op, "vertices");
        const toml::node* vn = node(t, op, "vertices", true);
        const toml::array* va = vn->as_array();
        if (va == nullptr) {
            fail(vp, std::string("must be an array of [x, y] pairs (got ") + typeName(*vn) + ")");
        }
        if (va->size() < 3 || va->size() > kMaxPolygonVertices) {
            fail(vp, "needs 3 to " + std::to_string(kMaxPolygonVertices) + " vertices (got " +
                         std::to_string(va->size()) + ")");
        }
        for (std::size_t k = 0; k < va->size(); ++k) {
            const std::string kp = indexed(vp, k);
            const toml::array* pair = va->get(k)->as_array();
            if (pair == nullptr || pair->size() != 2) {
                fail(kp, "must be a pair [x, y] of numbers in metres");
            }
            const Vec2 v{number(*pair->get(0), kp), number(*pair->get(1), kp)};
            if (!map.contains(v)) {
                fail(kp, "(" + num(v.x) + ", " + num(v.y) + ") is outside the map");
            }
            o.shape.v[k] = v;
        }
        o.shape.n = va->size();
        if (!isConvexCcw(o.shape.v.data(), o.shape.n)) {
            fail(vp, "polygon must be convex and counter-clockwise");
        }
        out->push_back(o);
    }
}

void Parser::parseStart(const toml::table& t, const Scenario& s, Pose2* start) const {
    const std::string p = "start";
    onlyKeys(t, p, {"x_m", "y_m", "heading_deg"});
    start->x = number(t, p, "x_m", 0.0, true);
    start->y = number(t, p, "y_m", 0.0, true);
    start->theta = ranged(t, p, "heading_deg", 0.0, -360.0, 360.0) * kPi / 180.0;
    const Vec2 c{start->x, start->y};
    if (!s.map.containsDisc(c, s.rover.radiusM)) {
        fail(p, "rover footprint (radius " + num(s.rover.radiusM) + " m) at (" + num(c.x) + ", " + num(c.y) +
                    ") is not inside the map");
    }
    for (const Obstacle& o : s.obstacles) {
        if (circleIntersectsPolygon(c, s.rover.radiusM, o.shape)) {
            fail(p, "rover footprint (radius " + num(s.rover.radiusM) + " m) overlaps obstacle " +
                        std::to_string(o.id));
        }
    }
}

void Parser::parseDevices(const toml::table& t, DeviceParams* d) const {
    const std::string p = "devices";
    onlyKeys(t, p, {"imu", "power", "hazard", "position_fix", "grinder", "camera"});
    if (const toml::table* imu = table(t, p, "imu", false)) {
        const std::string ip = join(p, "imu");
        onlyKeys(*imu, ip, {"noise_sigma_rad_s", "bias_rad_s"});
        d->imu.noiseSigmaRadS = ranged(*imu, ip, "noise_sigma_rad_s", d->imu.noiseSigmaRadS, 0.0, 1.0);
        d->imu.biasRadS = ranged(*imu, ip, "bias_rad_s", d->imu.biasRadS, -1.0, 1.0);
    }
    if (const toml::table* pw = table(t, p, "power", false)) {
        const std::string pp = join(p, "power");
        onlyKeys(*pw, pp, {"voltage_sigma_v", "current_sigma_a"});
        d->power.voltageSigmaV = ranged(*pw, pp, "voltage_sigma_v", d->power.voltageSigmaV, 0.0, 5.0);
        d->power.currentSigmaA = ranged(*pw, pp, "current_sigma_a", d->power.currentSigmaA, 0.0, 5.0);
    }
    if (const toml::table* hz = table(t, p, "hazard", false)) {
        const std::string hp = join(p, "hazard");
        onlyKeys(*hz, hp, {"range_m", "half_fov_deg", "range_sigma_m", "bearing_sigma_rad"});
        d->hazard.rangeM = positive(*hz, hp, "range_m", d->hazard.rangeM, 300.0);
        d->hazard.halfFovRad =
            positive(*hz, hp, "half_fov_deg", d->hazard.halfFovRad * 180.0 / kPi, 90.0) * kPi / 180.0;
        d->hazard.rangeSigmaM = ranged(*hz, hp, "range_sigma_m", d->hazard.rangeSigmaM, 0.0, 10.0);
        d->hazard.bearingSigmaRad = ranged(*hz, hp, "bearing_sigma_rad", d->hazard.bearingSigmaRad, 0.0, 1.0);
    }
    if (const toml::table* fx = table(t, p, "position_fix", false)) {
        const std::string fp = join(p, "position_fix");
        onlyKeys(*fx, fp, {"sigma_m", "heading_sigma_rad"});
        d->positionFix.sigmaM = ranged(*fx, fp, "sigma_m", d->positionFix.sigmaM, 0.0, 60.0);
        d->positionFix.headingSigmaRad =
            ranged(*fx, fp, "heading_sigma_rad", d->positionFix.headingSigmaRad, 0.0, 1.0);
    }
    parseInstrument(t, p, hal::instrument::Kind::kGrinder, &d->grinder);
    parseInstrument(t, p, hal::instrument::Kind::kCamera, &d->camera);
}

void Parser::parseInstrument(const toml::table& devices, const std::string& path, hal::instrument::Kind kind,
                             InstrumentParams* ip) const {
    const char* name = hal::instrument::toString(kind);
    const toml::table* t = table(devices, path, name, false);
    if (t == nullptr) {
        return;
    }
    const std::string p = join(path, name);
    // Durations up to the command's largest max duration (6553.5 s); the
    // camera's reach is its range, and is called so in the file.
    const bool grinder = kind == hal::instrument::Kind::kGrinder;
    const char* reachKey = grinder ? "reach_m" : "range_m";
    if (grinder) {
        onlyKeys(*t, p, {"sample_s", "dig_s", "duration_sigma", reachKey});
        ip->sampleS = positive(*t, p, "sample_s", ip->sampleS, hal::instrument::kMaxDurationS);
        ip->digS = positive(*t, p, "dig_s", ip->digS, hal::instrument::kMaxDurationS);
    } else {
        onlyKeys(*t, p, {"image_s", "duration_sigma", reachKey});
        ip->imageS = positive(*t, p, "image_s", ip->imageS, hal::instrument::kMaxDurationS);
    }
    ip->durationSigma = ranged(*t, p, "duration_sigma", ip->durationSigma, 0.0, 0.5);
    ip->reachM = positive(*t, p, reachKey, ip->reachM, 100.0);
}

void Parser::parseTargets(const toml::node& n, const MapBounds& map, std::vector<ScienceTarget>* out) const {
    const std::string p = "targets";
    const toml::array& a = tableArray(n, p);
    out->reserve(a.size());
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string tp = indexed(p, i);
        const toml::table& t = *a.get(i)->as_table();
        onlyKeys(t, tp, {"id", "x_m", "y_m"});
        ScienceTarget target;
        target.id = uniqueId(t, p, i, *out);
        target.position.x = number(t, tp, "x_m", 0.0, true);
        target.position.y = number(t, tp, "y_m", 0.0, true);
        if (!map.containsDisc(target.position, 0.0)) {
            fail(tp, "(" + num(target.position.x) + ", " + num(target.position.y) + ") is not inside the map");
        }
        out->push_back(target);
    }
}

void Parser::parseDrives(const toml::table& t, DriveNoiseParams* d) const {
    const std::string p = "drives";
    onlyKeys(t, p, {"current_sigma_a", "velocity_sigma_rad_s", "ambient_c"});
    d->ambientC = ranged(t, p, "ambient_c", d->ambientC, -120.0, 80.0);
    d->currentSigmaA = ranged(t, p, "current_sigma_a", d->currentSigmaA, 0.0, 1.0);
    d->velocitySigmaRadS = ranged(t, p, "velocity_sigma_rad_s", d->velocitySigmaRadS, 0.0, 1.0);
}

std::size_t Parser::wheel(const toml::table& t, const std::string& path) const {
    const std::int64_t w = integer(t, path, "wheel", 0, true);
    if (w < 1 || w > static_cast<std::int64_t>(kWheelCount)) {
        fail(join(path, "wheel"), "must be 1..6 (got " + std::to_string(w) + ")");
    }
    return static_cast<std::size_t>(w - 1);
}

SimDevice Parser::device(const toml::table& t, const std::string& path, bool instrumentsOnly) const {
    const std::string name = string(t, path, "device", "", true);
    // The list is the enum's, so a new device cannot be left out of it.
    std::vector<std::string> names;
    for (std::size_t i = 0; i < kSimDeviceCount; ++i) {
        const SimDevice d = static_cast<SimDevice>(i);
        if (instrumentsOnly && !isInstrument(d)) {
            continue;
        }
        if (name == toString(d)) {
            return d;
        }
        names.emplace_back(toString(d));
    }
    std::string expected;
    for (std::size_t i = 0; i < names.size(); ++i) {
        expected += (i == 0 ? "" : (i + 1 == names.size() ? " or " : ", ")) + names[i];
    }
    fail(join(path, "device"), std::string(instrumentsOnly ? "unknown instrument" : "unknown device") + " \"" + name +
                                   "\" (expected " + expected + ")");
}

std::uint32_t Parser::cobId(const toml::table& t, const std::string& path, std::string_view key,
                            std::uint32_t fallback, bool required) const {
    const std::int64_t id = integer(t, path, key, fallback, required);
    if (id < 0 || id > 0x7FF) {
        fail(join(path, key), "must be an 11-bit CAN id 0..0x7FF (got " + std::to_string(id) + ")");
    }
    return static_cast<std::uint32_t>(id);
}

void Parser::parseTask(const toml::table& t, const std::string& p, FaultSpec* f) const {
    const toml::node* n = node(t, p, "task", true);
    const std::string path = join(p, "task");
    if (n->is_integer()) {
        // The row range is EXEC_SET_TASK's, the command the ground stalls it with;
        // whether the flight software's table has that row is its to say (CMD_ACK).
        const cmdtlm::CommandDesc* command = cmdtlm::findCommand("EXEC_SET_TASK");
        const auto maxRow = static_cast<std::int64_t>(command != nullptr ? command->args[0].max : 0.0);
        const std::int64_t row = n->as_integer()->get();
        if (row < 0 || row > maxRow) {
            fail(path, "a row must be 0.." + std::to_string(maxRow) + " (got " + std::to_string(row) + ")");
        }
        f->taskRow = static_cast<std::size_t>(row);
        return;
    }
    if (!n->is_string()) {
        fail(path, std::string("must be a rate-group row (integer) or a task name (string) (got ") + typeName(*n) + ")");
    }
    const std::string name = n->as_string()->get();
    bool wellFormed = !name.empty() && name.size() < sizeof(cmdtlm::TASK_TIMING_Tlm{}.task_name);
    for (char c : name) {
        wellFormed = wellFormed && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_');
    }
    if (!wellFormed) {
        fail(path, "\"" + name + "\" is not a task name (1 to 15 of a-z, 0-9, _; as TASK_TIMING names it)");
    }
    f->taskName = name;
}

void Parser::parseMission(const toml::table& t, const MapBounds& map, MissionSpec* m) const {
    const std::string p = "mission";
    onlyKeys(t, p, {"goal_x_m", "goal_y_m", "risk_bound", "plan_file"});
    m->present = true;
    const bool x = t.contains("goal_x_m");
    const bool y = t.contains("goal_y_m");
    const bool plan = t.contains("plan_file");
    if (x != y) {
        fail(join(p, x ? "goal_y_m" : "goal_x_m"), std::string("missing (a goal needs both; ") +
                                                       (x ? "goal_x_m" : "goal_y_m") + " is given)");
    }
    if (x == plan) {
        fail(p, plan ? "give a goal (goal_x_m, goal_y_m) or a plan_file, not both"
                     : "needs a goal (goal_x_m, goal_y_m) or a plan_file");
    }
    // The operator's bound, in the range GOTO and SET_RISK_BOUND take (the dictionary's).
    const cmdtlm::CommandDesc* command = cmdtlm::findCommand("GOTO");
    const double riskMin = command != nullptr ? command->args[2].min : 0.0;
    const double riskMax = command != nullptr ? command->args[2].max : 0.0;
    m->riskBound = ranged(t, p, "risk_bound", kDefaultMissionRiskBound, riskMin, riskMax);
    if (x) {
        m->hasGoal = true;
        m->goalX = number(t, p, "goal_x_m", 0.0, true);
        m->goalY = number(t, p, "goal_y_m", 0.0, true);
        if (!map.contains({m->goalX, m->goalY})) {
            fail(p, "goal (" + num(m->goalX) + ", " + num(m->goalY) + ") is outside the map");
        }
        return;
    }
    // A plan file is named relative to the scenario file's folder.
    const std::string name = string(t, p, "plan_file", "", true);
    const std::string path = join(p, "plan_file");
    if (name.empty()) {
        fail(path, "must name a plan file");
    }
    const std::size_t slash = source_.find_last_of('/');
    const std::string joined =
        name.front() == '/' || slash == std::string::npos ? name : source_.substr(0, slash + 1) + name;
    m->planFile = std::filesystem::path(joined).lexically_normal().string();
    std::ifstream in(m->planFile, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    if (!in) {
        fail(path, "cannot read '" + m->planFile + "'");
    }
    m->planText = text.str();
    if (m->planText.empty()) {
        fail(path, "'" + m->planFile + "' is empty");
    }
}

core::TimeNs Parser::intervalEnd(const toml::table& t, const std::string& path, double atS) const {
    const toml::node* duration = t.get("duration_s");
    const toml::node* until = t.get("until_s");
    if (duration == nullptr && until == nullptr) {
        fail(path, "needs duration_s or until_s");
    }
    if (duration != nullptr && until != nullptr) {
        fail(path, "give duration_s or until_s, not both");
    }
    if (duration != nullptr) {
        const double d = number(*duration, join(path, "duration_s"));
        withinOpenLow(join(path, "duration_s"), d, 0.0, kMaxTimeS);
        return toNs(atS + d);
    }
    const double u = number(*until, join(path, "until_s"));
    if (!(u > atS)) {
        fail(join(path, "until_s"), "must be after at_s (" + num(atS) + ") (got " + num(u) + ")");
    }
    within(join(path, "until_s"), u, 0.0, kMaxTimeS);
    return toNs(u);
}

FaultSpec Parser::parseFault(const toml::table& t, const std::string& p) const {
    FaultSpec f;
    const std::string type = string(t, p, "type", "", true);
    bool known = false;
    for (std::uint8_t i = 0; i <= static_cast<std::uint8_t>(kLastFaultType); ++i) {
        if (type == toString(static_cast<FaultType>(i))) {
            f.type = static_cast<FaultType>(i);
            known = true;
        }
    }
    if (!known) {
        // The list is the enum's, so a new fault type cannot be left out of it.
        std::string expected;
        const auto last = static_cast<std::uint8_t>(kLastFaultType);
        for (std::uint8_t i = 0; i <= last; ++i) {
            expected += (i == 0 ? "" : (i == last ? " or " : ", "));
            expected += toString(static_cast<FaultType>(i));
        }
        fail(join(p, "type"), "unknown fault type \"" + type + "\" (expected " + expected + ")");
    }
    const double atS = ranged(t, p, "at_s", 0.0, 0.0, kMaxTimeS, true);
    f.at = toNs(atS);
    const std::string ctx = "for fault type " + type;
    switch (f.type) {
        case FaultType::kMotorDegradation:
            onlyKeys(t, p, {"type", "at_s", "wheel", "current_factor"}, ctx);
            f.wheel = wheel(t, p);
            f.value = ranged(t, p, "current_factor", 0.0, 1.0, 10.0, true);
            break;
        case FaultType::kMotorFailure:
            onlyKeys(t, p, {"type", "at_s", "wheel"}, ctx);
            f.wheel = wheel(t, p);
            break;
        case FaultType::kDriveFault:
            onlyKeys(t, p, {"type", "at_s", "wheel", "emcy_code"}, ctx);
            f.wheel = wheel(t, p);
            f.cobId = static_cast<std::uint32_t>(integer(t, p, "emcy_code", 0x4310, false));
            if (f.cobId == 0 || f.cobId > 0xFFFF) {
                fail(join(p, "emcy_code"), "must be 1..0xFFFF (got " + std::to_string(f.cobId) + ")");
            }
            break;
        case FaultType::kMotorOverheat:
            onlyKeys(t, p, {"type", "at_s", "wheel", "heat_factor"}, ctx);
            f.wheel = wheel(t, p);
            f.value = ranged(t, p, "heat_factor", 0.0, 1.0, 100.0, true);
            break;
        case FaultType::kDriveHeartbeatLoss:
            onlyKeys(t, p, {"type", "at_s", "wheel", "duration_s", "until_s"}, ctx);
            f.wheel = wheel(t, p);
            f.until = intervalEnd(t, p, atS);
            break;
        case FaultType::kDriveCrash:
        case FaultType::kDeviceCrash:
            if (f.type == FaultType::kDriveCrash) {
                onlyKeys(t, p, {"type", "at_s", "wheel", "restart_at_s"}, ctx);
                f.wheel = wheel(t, p);
            } else {
                onlyKeys(t, p, {"type", "at_s", "device", "restart_at_s"}, ctx);
                f.device = device(t, p);
            }
            if (const toml::node* r = t.get("restart_at_s")) {
                const double rs = number(*r, join(p, "restart_at_s"));
                if (!(rs > atS)) {
                    fail(join(p, "restart_at_s"), "must be after at_s (" + num(atS) + ") (got " + num(rs) + ")");
                }
                within(join(p, "restart_at_s"), rs, 0.0, kMaxTimeS);
                f.until = toNs(rs);
            }
            break;
        case FaultType::kSensorDropout:
            onlyKeys(t, p, {"type", "at_s", "device", "duration_s", "until_s"}, ctx);
            f.device = device(t, p);
            f.until = intervalEnd(t, p, atS);
            break;
        case FaultType::kImuBiasStep:
            onlyKeys(t, p, {"type", "at_s", "delta_rad_s"}, ctx);
            f.value = ranged(t, p, "delta_rad_s", 0.0, -1.0, 1.0, true);
            break;
        case FaultType::kBusFault: {
            const std::string action = string(t, p, "action", "", true);
            const std::string actx = "for bus_fault action \"" + action + "\"";
            if (action == "drop") {
                onlyKeys(t, p, {"type", "at_s", "action", "cob_id", "mask", "frames"}, actx);
                f.busRule.kind = hal::CanFaultKind::kDrop;
            } else if (action == "corrupt") {
                onlyKeys(t, p, {"type", "at_s", "action", "cob_id", "mask", "frames", "byte", "xor"}, actx);
                f.busRule.kind = hal::CanFaultKind::kCorrupt;
                const std::int64_t byte = integer(t, p, "byte", 0);
                if (byte < 0 || byte > 7) {
                    fail(join(p, "byte"), "must be 0..7 (got " + std::to_string(byte) + ")");
                }
                const std::int64_t x = integer(t, p, "xor", 0xFF);
                if (x < 1 || x > 255) {
                    fail(join(p, "xor"), "must be 1..255 (got " + std::to_string(x) + ")");
                }
                f.busRule.corruptByte = static_cast<std::uint8_t>(byte);
                f.busRule.corruptXor = static_cast<std::uint8_t>(x);
            } else if (action == "delay") {
                onlyKeys(t, p, {"type", "at_s", "action", "cob_id", "mask", "frames", "delay_s"}, actx);
                f.busRule.kind = hal::CanFaultKind::kDelay;
                f.busRule.delay = toNs(positive(t, p, "delay_s", 0.0, 10.0, true));
            } else {
                fail(join(p, "action"), "unknown bus fault action \"" + action + "\" (expected drop, corrupt or delay)");
            }
            f.busRule.id = cobId(t, p, "cob_id", 0, true);
            f.busRule.mask = cobId(t, p, "mask", 0x7FF, false);
            const std::int64_t frames = integer(t, p, "frames", 1);
            if (frames < 1 || frames > 1000000) {
                fail(join(p, "frames"), "must be 1..1000000 (got " + std::to_string(frames) + ")");
            }
            f.busRule.count = static_cast<std::uint32_t>(frames);
            break;
        }
        case FaultType::kBabblingNode:
            onlyKeys(t, p, {"type", "at_s", "cob_id", "rate_hz", "duration_s", "until_s"}, ctx);
            f.cobId = cobId(t, p, "cob_id", 0, true);
            f.value = positive(t, p, "rate_hz", kDefaultBabbleRateHz, 20000.0);
            f.until = intervalEnd(t, p, atS);
            break;
        case FaultType::kPositionFixOutlier: {
            onlyKeys(t, p, {"type", "at_s", "offset_m", "count", "bearing_deg"}, ctx);
            f.value = positive(t, p, "offset_m", 0.0, 1000.0, true);
            const std::int64_t count = integer(t, p, "count", 1);
            if (count < 1 || count > 1000) {
                fail(join(p, "count"), "must be 1..1000 (got " + std::to_string(count) + ")");
            }
            f.count = static_cast<std::uint32_t>(count);
            f.bearingRad = ranged(t, p, "bearing_deg", 0.0, -360.0, 360.0) * kPi / 180.0;
            break;
        }
        case FaultType::kSlide:
            onlyKeys(t, p, {"type", "at_s", "offset_m", "bearing_deg", "duration_s", "until_s"}, ctx);
            f.value = positive(t, p, "offset_m", 0.0, 100.0, true);
            f.bearingRad = ranged(t, p, "bearing_deg", 0.0, -360.0, 360.0) * kPi / 180.0;
            f.until = intervalEnd(t, p, atS);
            break;
        case FaultType::kTaskStall:
            onlyKeys(t, p, {"type", "at_s", "task", "duration_s", "until_s"}, ctx);
            parseTask(t, p, &f);
            // Without an end the schedule never enables the row again: fault protection must.
            if (t.get("duration_s") != nullptr || t.get("until_s") != nullptr) {
                f.until = intervalEnd(t, p, atS);
            }
            break;
        case FaultType::kInstrumentFailure: {
            onlyKeys(t, p, {"type", "at_s", "device", "fault_code", "silent", "duration_s", "until_s"}, ctx);
            f.device = device(t, p, true);
            const std::int64_t code = integer(t, p, "fault_code", 1);
            if (code < 1 || code > 255) {
                fail(join(p, "fault_code"), "must be 1..255 (got " + std::to_string(code) + ")");
            }
            f.faultCode = static_cast<std::uint8_t>(code);
            f.silent = boolean(t, p, "silent", false);
            // Without an end the instrument stays failed.
            if (t.get("duration_s") != nullptr || t.get("until_s") != nullptr) {
                f.until = intervalEnd(t, p, atS);
            }
            break;
        }
    }
    return f;
}

void Parser::parseFaults(const toml::node& n, std::vector<FaultSpec>* out) const {
    const std::string p = "faults";
    const toml::array& a = tableArray(n, p);
    out->reserve(a.size());
    double previousS = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string fp = indexed(p, i);
        const FaultSpec f = parseFault(*a.get(i)->as_table(), fp);
        const double atS = static_cast<double>(f.at) * 1e-9;
        if (i > 0 && f.at < out->back().at) {
            fail(join(fp, "at_s"), num(atS) + " is earlier than the previous fault's " + num(previousS) +
                                       ": faults must be listed in time order");
        }
        previousS = atS;
        out->push_back(f);
    }
}

Scenario Parser::parse(std::string_view text) {
    toml::table root;
    try {
        root = toml::parse(text, source_);
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << source_ << ":" << e.source().begin.line << ":" << e.source().begin.column << ": " << e.description();
        throw ScenarioError(os.str());
    }
    onlyKeys(root, "",
             {"name", "description", "seed", "duration_s", "rover", "battery", "solar", "map", "start", "obstacles",
              "targets", "devices", "drives", "faults", "mission"});
    Scenario s;
    s.source = source_;
    s.name = string(root, "", "name", source_);
    s.description = string(root, "", "description", "");
    const std::int64_t seed = integer(root, "", "seed", 0, true);
    if (seed < 0) {
        fail("seed", "must be >= 0 (got " + std::to_string(seed) + ")");
    }
    s.seed = static_cast<std::uint64_t>(seed);
    s.durationS = positive(root, "", "duration_s", s.durationS, kMaxTimeS);
    if (const toml::table* t = table(root, "", "rover", false)) {
        parseRover(*t, &s.rover);
    }
    if (const toml::table* t = table(root, "", "battery", false)) {
        parseBattery(*t, &s.battery);
    }
    if (const toml::table* t = table(root, "", "solar", false)) {
        parseSolar(*t, &s.solar);
    }
    parseMap(*table(root, "", "map", true), &s.map);
    if (const toml::node* n = node(root, "", "obstacles", false)) {
        parseObstacles(*n, s.map, &s.obstacles);
    }
    parseStart(*table(root, "", "start", true), s, &s.start);
    if (const toml::node* n = node(root, "", "targets", false)) {
        parseTargets(*n, s.map, &s.targets);
    }
    if (const toml::table* t = table(root, "", "devices", false)) {
        parseDevices(*t, &s.devices);
    }
    if (const toml::table* t = table(root, "", "drives", false)) {
        parseDrives(*t, &s.drives);
    }
    if (const toml::node* n = node(root, "", "faults", false)) {
        parseFaults(*n, &s.faults);
    }
    if (const toml::table* t = table(root, "", "mission", false)) {
        parseMission(*t, s.map, &s.mission);
    }
    return s;
}

}  // namespace

Scenario parseScenario(std::string_view text, const std::string& sourceName) {
    Parser parser(sourceName);
    return parser.parse(text);
}

Scenario loadScenarioFile(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw ScenarioError(path + ": cannot open the file");
    }
    std::ostringstream text;
    text << in.rdbuf();
    return parseScenario(text.str(), path);
}

bool tryParseScenario(std::string_view text, const std::string& sourceName, Scenario* out, std::string* error) {
    try {
        *out = parseScenario(text, sourceName);
        return true;
    } catch (const ScenarioError& e) {
        if (error != nullptr) {
            *error = e.what();
        }
        return false;
    }
}

bool tryLoadScenarioFile(const std::string& path, Scenario* out, std::string* error) {
    try {
        *out = loadScenarioFile(path);
        return true;
    } catch (const ScenarioError& e) {
        if (error != nullptr) {
            *error = e.what();
        }
        return false;
    }
}

}  // namespace rse::sim
