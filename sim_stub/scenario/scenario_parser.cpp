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
#include "sim_stub/scenario/fault_parser.hpp"
#include "sim_stub/scenario/site_file.hpp"
#include "sim_stub/scenario/scenario_toml.hpp"

namespace rse::sim {

namespace {

using namespace scenario_toml;

// The scenario's sections, read with the shared field reader (scenario_toml.hpp);
// the faults by the fault parser (fault_parser.hpp).
class Parser : private Reader {
public:
    explicit Parser(std::string source) : Reader(std::move(source)) {}

    Scenario parse(std::string_view text);

private:
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
    void parseMission(const toml::table& t, const MapBounds& map, MissionSpec* mission) const;
    void parseField(const toml::table& t, std::uint64_t scenarioSeed, FieldSpec* field) const;
    void parseSite(const toml::table& t, Scenario* s) const;
    // A file the scenario names, relative to the scenario file's folder.
    std::string besideScenario(const std::string& name) const;
};

std::string Parser::besideScenario(const std::string& name) const {
    const std::size_t slash = source().find_last_of('/');
    const std::string joined =
        name.front() == '/' || slash == std::string::npos ? name : source().substr(0, slash + 1) + name;
    return std::filesystem::path(joined).lexically_normal().string();
}

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
        onlyKeys(t, op, {"id", "known", "detectable", "vertices"});
        Obstacle o;
        o.id = uniqueId(t, p, i, *out);
        o.known = boolean(t, op, "known", true, true);
        o.detectable = boolean(t, op, "detectable", true, false);
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
    m->planFile = besideScenario(name);
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

void Parser::parseSite(const toml::table& t, Scenario* s) const {
    const std::string p = "site";
    onlyKeys(t, p, {"file"});
    const std::string name = string(t, p, "file", "", true);
    if (name.empty()) {
        fail(join(p, "file"), "must name a site file");
    }
    s->siteFile = besideScenario(name);
    addSiteFileRocks(s->siteFile, s);
}

void Parser::parseField(const toml::table& t, std::uint64_t scenarioSeed, FieldSpec* f) const {
    const std::string p = "field";
    onlyKeys(t, p, {"k", "seed", "min_diameter_m", "max_diameter_m", "orbital_resolution_m", "clear_m"});
    f->present = true;
    f->rocks.k = ranged(t, p, "k", 0.0, 0.001, 0.5, true);
    const std::int64_t seed = integer(t, p, "seed", static_cast<std::int64_t>(scenarioSeed));
    if (seed < 0) {
        fail(join(p, "seed"), "must be >= 0 (got " + std::to_string(seed) + ")");
    }
    f->rocks.seed = static_cast<std::uint64_t>(seed);
    f->rocks.minDiameterM = ranged(t, p, "min_diameter_m", 0.5, 0.05, 10.0);
    f->rocks.maxDiameterM = ranged(t, p, "max_diameter_m", 8.0, 0.1, 50.0);
    if (!(f->rocks.maxDiameterM > f->rocks.minDiameterM)) {
        fail(join(p, "max_diameter_m"), "must be greater than min_diameter_m (" + num(f->rocks.minDiameterM) + ")");
    }
    f->rocks.orbitalResolutionM = ranged(t, p, "orbital_resolution_m", 1.0, 0.05, 50.0);
    f->clearM = ranged(t, p, "clear_m", 5.0, 0.0, 100.0);
}

Scenario Parser::parse(std::string_view text) {
    toml::table root;
    try {
        root = toml::parse(text, source());
    } catch (const toml::parse_error& e) {
        std::ostringstream os;
        os << source() << ":" << e.source().begin.line << ":" << e.source().begin.column << ": " << e.description();
        throw ScenarioError(os.str());
    }
    onlyKeys(root, "",
             {"name", "description", "seed", "duration_s", "rover", "battery", "solar", "map", "start", "obstacles",
              "targets", "devices", "drives", "faults", "mission", "field", "site"});
    Scenario s;
    s.source = source();
    s.name = string(root, "", "name", source());
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
        parseFaults(*this, *n, &s.faults);
    }
    if (const toml::table* t = table(root, "", "mission", false)) {
        parseMission(*t, s.map, &s.mission);
    }
    // After the start and the mission: the field keeps clear of both, and a
    // site file's rocks must.
    const toml::table* field = table(root, "", "field", false);
    const toml::table* site = table(root, "", "site", false);
    if (field != nullptr && site != nullptr) {
        fail("site", "a scenario has a [field] or a [site] file, not both");
    }
    if (field != nullptr) {
        parseField(*field, s.seed, &s.field);
        addFieldRocks(s.field, &s);
    }
    if (site != nullptr) {
        parseSite(*site, &s);
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
