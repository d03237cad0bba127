#include "sim_stub/scenario/fault_parser.hpp"

#include <cstdint>
#include <string>
#include <string_view>

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::sim::scenario_toml {

namespace {

// One fault's table and what every kind's parser needs of it.
struct FaultInput {
    const Reader& r;
    const toml::table& t;
    const std::string& p;   // its key path, faults[i]
    double atS;             // its at_s
    const std::string& ctx;  // "for fault type <type>": the context of an unknown key
};

// `wheel`: 1..6 in the file, 0..5 in FaultSpec.
std::size_t wheel(const FaultInput& in) {
    const std::int64_t w = in.r.integer(in.t, in.p, "wheel", 0, true);
    if (w < 1 || w > static_cast<std::int64_t>(kWheelCount)) {
        in.r.fail(join(in.p, "wheel"), "must be 1..6 (got " + std::to_string(w) + ")");
    }
    return static_cast<std::size_t>(w - 1);
}

// `device`: a device's name (instrumentsOnly: an instrument's).
SimDevice device(const FaultInput& in, bool instrumentsOnly = false) {
    const std::string name = in.r.string(in.t, in.p, "device", "", true);
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
    in.r.fail(join(in.p, "device"), std::string(instrumentsOnly ? "unknown instrument" : "unknown device") + " \"" +
                                        name + "\" (expected " + expected + ")");
}

std::uint32_t cobId(const FaultInput& in, std::string_view key, std::uint32_t fallback, bool required) {
    const std::int64_t id = in.r.integer(in.t, in.p, key, fallback, required);
    if (id < 0 || id > 0x7FF) {
        in.r.fail(join(in.p, key), "must be an 11-bit CAN id 0..0x7FF (got " + std::to_string(id) + ")");
    }
    return static_cast<std::uint32_t>(id);
}

// An interval fault's end: duration_s after at_s, or until_s.
core::TimeNs intervalEnd(const FaultInput& in) {
    const toml::node* duration = in.t.get("duration_s");
    const toml::node* until = in.t.get("until_s");
    if (duration == nullptr && until == nullptr) {
        in.r.fail(in.p, "needs duration_s or until_s");
    }
    if (duration != nullptr && until != nullptr) {
        in.r.fail(in.p, "give duration_s or until_s, not both");
    }
    if (duration != nullptr) {
        const double d = in.r.number(*duration, join(in.p, "duration_s"));
        in.r.withinOpenLow(join(in.p, "duration_s"), d, 0.0, kMaxTimeS);
        return toNs(in.atS + d);
    }
    const double u = in.r.number(*until, join(in.p, "until_s"));
    if (!(u > in.atS)) {
        in.r.fail(join(in.p, "until_s"), "must be after at_s (" + num(in.atS) + ") (got " + num(u) + ")");
    }
    in.r.within(join(in.p, "until_s"), u, 0.0, kMaxTimeS);
    return toNs(u);
}

// An end that is optional: without duration_s or until_s, kNever.
core::TimeNs optionalEnd(const FaultInput& in) {
    return in.t.get("duration_s") != nullptr || in.t.get("until_s") != nullptr ? intervalEnd(in) : kNever;
}

// A bearing in degrees (default 0) as radians.
double bearingRad(const FaultInput& in) {
    return in.r.ranged(in.t, in.p, "bearing_deg", 0.0, -360.0, 360.0) * kPi / 180.0;
}

// A whole number in [lo, hi] (default fallback).
std::int64_t count(const FaultInput& in, std::string_view key, std::int64_t fallback, std::int64_t lo,
                   std::int64_t hi, const char* range) {
    const std::int64_t v = in.r.integer(in.t, in.p, key, fallback);
    if (v < lo || v > hi) {
        in.r.fail(join(in.p, key), std::string("must be ") + range + " (got " + std::to_string(v) + ")");
    }
    return v;
}

// ---- The kinds, each with the keys it allows ----------------------------------

void motorDegradation(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel", "current_factor"}, in.ctx);
    f->wheel = wheel(in);
    f->value = in.r.ranged(in.t, in.p, "current_factor", 0.0, 1.0, 10.0, true);
}

void motorFailure(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel"}, in.ctx);
    f->wheel = wheel(in);
}

void driveHeartbeatLoss(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel", "duration_s", "until_s"}, in.ctx);
    f->wheel = wheel(in);
    f->until = intervalEnd(in);
}

// A crash's restart_at_s, when given (else the node stays down).
void restartTime(const FaultInput& in, FaultSpec* f) {
    if (const toml::node* r = in.t.get("restart_at_s")) {
        const double rs = in.r.number(*r, join(in.p, "restart_at_s"));
        if (!(rs > in.atS)) {
            in.r.fail(join(in.p, "restart_at_s"), "must be after at_s (" + num(in.atS) + ") (got " + num(rs) + ")");
        }
        in.r.within(join(in.p, "restart_at_s"), rs, 0.0, kMaxTimeS);
        f->until = toNs(rs);
    }
}

void driveCrash(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel", "restart_at_s"}, in.ctx);
    f->wheel = wheel(in);
    restartTime(in, f);
}

void sensorDropout(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "device", "duration_s", "until_s"}, in.ctx);
    f->device = device(in);
    f->until = intervalEnd(in);
}

void deviceCrash(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "device", "restart_at_s"}, in.ctx);
    f->device = device(in);
    restartTime(in, f);
}

void imuBiasStep(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "delta_rad_s"}, in.ctx);
    f->value = in.r.ranged(in.t, in.p, "delta_rad_s", 0.0, -1.0, 1.0, true);
}

// bus_fault's action (drop, corrupt or delay) and the keys each allows.
void busFaultAction(const FaultInput& in, FaultSpec* f) {
    const std::string action = in.r.string(in.t, in.p, "action", "", true);
    const std::string actx = "for bus_fault action \"" + action + "\"";
    if (action == "drop") {
        in.r.onlyKeys(in.t, in.p, {"type", "at_s", "action", "cob_id", "mask", "frames"}, actx);
        f->busRule.kind = hal::CanFaultKind::kDrop;
    } else if (action == "corrupt") {
        in.r.onlyKeys(in.t, in.p, {"type", "at_s", "action", "cob_id", "mask", "frames", "byte", "xor"}, actx);
        f->busRule.kind = hal::CanFaultKind::kCorrupt;
        f->busRule.corruptByte = static_cast<std::uint8_t>(count(in, "byte", 0, 0, 7, "0..7"));
        f->busRule.corruptXor = static_cast<std::uint8_t>(count(in, "xor", 0xFF, 1, 255, "1..255"));
    } else if (action == "delay") {
        in.r.onlyKeys(in.t, in.p, {"type", "at_s", "action", "cob_id", "mask", "frames", "delay_s"}, actx);
        f->busRule.kind = hal::CanFaultKind::kDelay;
        f->busRule.delay = toNs(in.r.positive(in.t, in.p, "delay_s", 0.0, 10.0, true));
    } else {
        in.r.fail(join(in.p, "action"), "unknown bus fault action \"" + action + "\" (expected drop, corrupt or delay)");
    }
}

void busFault(const FaultInput& in, FaultSpec* f) {
    busFaultAction(in, f);
    f->busRule.id = cobId(in, "cob_id", 0, true);
    f->busRule.mask = cobId(in, "mask", 0x7FF, false);
    f->busRule.count = static_cast<std::uint32_t>(count(in, "frames", 1, 1, 1000000, "1..1000000"));
}

void babblingNode(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "cob_id", "rate_hz", "duration_s", "until_s"}, in.ctx);
    f->cobId = cobId(in, "cob_id", 0, true);
    f->value = in.r.positive(in.t, in.p, "rate_hz", kDefaultBabbleRateHz, 20000.0);
    f->until = intervalEnd(in);
}

void positionFixOutlier(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "offset_m", "count", "bearing_deg"}, in.ctx);
    f->value = in.r.positive(in.t, in.p, "offset_m", 0.0, 1000.0, true);
    f->count = static_cast<std::uint32_t>(count(in, "count", 1, 1, 1000, "1..1000"));
    f->bearingRad = bearingRad(in);
}

void motorOverheat(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel", "heat_factor"}, in.ctx);
    f->wheel = wheel(in);
    f->value = in.r.ranged(in.t, in.p, "heat_factor", 0.0, 1.0, 100.0, true);
}

void driveFault(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "wheel", "emcy_code"}, in.ctx);
    f->wheel = wheel(in);
    f->cobId = static_cast<std::uint32_t>(in.r.integer(in.t, in.p, "emcy_code", 0x4310, false));
    if (f->cobId == 0 || f->cobId > 0xFFFF) {
        in.r.fail(join(in.p, "emcy_code"), "must be 1..0xFFFF (got " + std::to_string(f->cobId) + ")");
    }
}

void slide(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "offset_m", "bearing_deg", "duration_s", "until_s"}, in.ctx);
    f->value = in.r.positive(in.t, in.p, "offset_m", 0.0, 100.0, true);
    f->bearingRad = bearingRad(in);
    f->until = intervalEnd(in);
}

// task_stall's `task`: a rate-group row (integer) or a task name (string).
void stalledTask(const FaultInput& in, FaultSpec* f) {
    const toml::node* n = in.r.node(in.t, in.p, "task", true);
    const std::string path = join(in.p, "task");
    if (n->is_integer()) {
        // The row range is EXEC_SET_TASK's, the command the ground stalls it with;
        // whether the flight software's table has that row is its to say (CMD_ACK).
        const cmdtlm::CommandDesc* command = cmdtlm::findCommand("EXEC_SET_TASK");
        const auto maxRow = static_cast<std::int64_t>(command != nullptr ? command->args[0].max : 0.0);
        const std::int64_t row = n->as_integer()->get();
        if (row < 0 || row > maxRow) {
            in.r.fail(path, "a row must be 0.." + std::to_string(maxRow) + " (got " + std::to_string(row) + ")");
        }
        f->taskRow = static_cast<std::size_t>(row);
        return;
    }
    if (!n->is_string()) {
        in.r.fail(path, std::string("must be a rate-group row (integer) or a task name (string) (got ") +
                            typeName(*n) + ")");
    }
    const std::string name = n->as_string()->get();
    bool wellFormed = !name.empty() && name.size() < sizeof(cmdtlm::TASK_TIMING_Tlm{}.task_name);
    for (char c : name) {
        wellFormed = wellFormed && ((c >= 'a' && c <= 'z') || (c >= '0' && c <= '9') || c == '_');
    }
    if (!wellFormed) {
        in.r.fail(path, "\"" + name + "\" is not a task name (1 to 15 of a-z, 0-9, _; as TASK_TIMING names it)");
    }
    f->taskName = name;
}

void taskStall(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "task", "duration_s", "until_s"}, in.ctx);
    stalledTask(in, f);
    // Without an end the schedule never enables the row again: fault protection must.
    f->until = optionalEnd(in);
}

void instrumentFailure(const FaultInput& in, FaultSpec* f) {
    in.r.onlyKeys(in.t, in.p, {"type", "at_s", "device", "fault_code", "silent", "duration_s", "until_s"}, in.ctx);
    f->device = device(in, true);
    f->faultCode = static_cast<std::uint8_t>(count(in, "fault_code", 1, 1, 255, "1..255"));
    f->silent = in.r.boolean(in.t, in.p, "silent", false);
    // Without an end the instrument stays failed.
    f->until = optionalEnd(in);
}

// Every kind's parser, in FaultType's order (checked below).
using KindParser = void (*)(const FaultInput&, FaultSpec*);
struct FaultKind {
    FaultType type;
    KindParser parse;
};
constexpr FaultKind kFaultKinds[] = {
    {FaultType::kMotorDegradation, motorDegradation},
    {FaultType::kMotorFailure, motorFailure},
    {FaultType::kDriveHeartbeatLoss, driveHeartbeatLoss},
    {FaultType::kDriveCrash, driveCrash},
    {FaultType::kSensorDropout, sensorDropout},
    {FaultType::kDeviceCrash, deviceCrash},
    {FaultType::kImuBiasStep, imuBiasStep},
    {FaultType::kBusFault, busFault},
    {FaultType::kBabblingNode, babblingNode},
    {FaultType::kPositionFixOutlier, positionFixOutlier},
    {FaultType::kMotorOverheat, motorOverheat},
    {FaultType::kDriveFault, driveFault},
    {FaultType::kSlide, slide},
    {FaultType::kTaskStall, taskStall},
    {FaultType::kInstrumentFailure, instrumentFailure},
};
constexpr std::size_t kFaultKindCount = sizeof kFaultKinds / sizeof kFaultKinds[0];
static_assert(kFaultKindCount == static_cast<std::size_t>(kLastFaultType) + 1, "a fault type without its parser");
constexpr bool kindsInTypeOrder() {
    for (std::size_t i = 0; i < kFaultKindCount; ++i) {
        if (static_cast<std::size_t>(kFaultKinds[i].type) != i) {
            return false;
        }
    }
    return true;
}
static_assert(kindsInTypeOrder(), "kFaultKinds is indexed by FaultType");

// `type` as a FaultType; an unknown one fails, naming every type.
FaultType faultType(const Reader& r, const toml::table& t, const std::string& p) {
    const std::string type = r.string(t, p, "type", "", true);
    for (std::uint8_t i = 0; i <= static_cast<std::uint8_t>(kLastFaultType); ++i) {
        if (type == toString(static_cast<FaultType>(i))) {
            return static_cast<FaultType>(i);
        }
    }
    // The list is the enum's, so a new fault type cannot be left out of it.
    std::string expected;
    const auto last = static_cast<std::uint8_t>(kLastFaultType);
    for (std::uint8_t i = 0; i <= last; ++i) {
        expected += (i == 0 ? "" : (i == last ? " or " : ", "));
        expected += toString(static_cast<FaultType>(i));
    }
    r.fail(join(p, "type"), "unknown fault type \"" + type + "\" (expected " + expected + ")");
}

FaultSpec parseFault(const Reader& r, const toml::table& t, const std::string& p) {
    FaultSpec f;
    f.type = faultType(r, t, p);
    const double atS = r.ranged(t, p, "at_s", 0.0, 0.0, kMaxTimeS, true);
    f.at = toNs(atS);
    const std::string ctx = std::string("for fault type ") + toString(f.type);
    kFaultKinds[static_cast<std::size_t>(f.type)].parse(FaultInput{r, t, p, atS, ctx}, &f);
    return f;
}

}  // namespace

void parseFaults(const Reader& reader, const toml::node& n, std::vector<FaultSpec>* out) {
    const std::string p = "faults";
    const toml::array& a = reader.tableArray(n, p);
    out->reserve(a.size());
    double previousS = 0.0;
    for (std::size_t i = 0; i < a.size(); ++i) {
        const std::string fp = indexed(p, i);
        const FaultSpec f = parseFault(reader, *a.get(i)->as_table(), fp);
        const double atS = static_cast<double>(f.at) * 1e-9;
        if (i > 0 && f.at < out->back().at) {
            reader.fail(join(fp, "at_s"), num(atS) + " is earlier than the previous fault's " + num(previousS) +
                                              ": faults must be listed in time order");
        }
        previousS = atS;
        out->push_back(f);
    }
}

}  // namespace rse::sim::scenario_toml
