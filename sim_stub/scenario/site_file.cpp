#include "sim_stub/scenario/site_file.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <vector>

#include "fsw/site_map/site_map_image.hpp"
#include "ground/text_format.hpp"
#include "sim_stub/scenario/field_rocks.hpp"
#include "sim_stub/scenario/scenario.hpp"
#include "sim_stub/scenario/scenario_parser.hpp"

namespace rse::sim {

namespace {

constexpr const char* kMagic = "rse-site";
constexpr int kVersion = 1;

// The shortest text that reads back as the same double.
std::string exact(double v) { return ground::formatNumber(v); }

// One line's words, and where it is for errors.
class Line {
public:
    Line(const std::string& path, std::size_t number, const std::string& text) : where_(path + ":" + std::to_string(number)) {
        std::istringstream in(text.substr(0, text.find('#')));
        for (std::string w; in >> w;) {
            words_.push_back(w);
        }
    }
    bool empty() const { return words_.empty(); }
    std::size_t size() const { return words_.size(); }
    const std::string& word(std::size_t i) const { return words_[i]; }
    [[noreturn]] void fail(const std::string& why) const { throw ScenarioError(where_ + ": " + why); }
    double number(std::size_t i) const {
        const std::string& w = words_[i];
        double v = 0.0;
        if (!ground::parseDouble(w, &v)) {
            fail("'" + w + "' is not a number");
        }
        if (!std::isfinite(v)) {
            fail("'" + w + "' is not finite");
        }
        return v;
    }

private:
    std::string where_;
    std::vector<std::string> words_;
};

void checkHeader(const Line& line, const MapBounds& map, int* state) {
    if (*state == 0) {
        if (line.size() != 2 || line.word(0) != kMagic) {
            line.fail(std::string("not a site file (it starts with '") + kMagic + " 1')");
        }
        if (line.word(1) != std::to_string(kVersion)) {
            line.fail("site file version " + line.word(1) + "; this rse-sim reads version " + std::to_string(kVersion));
        }
        *state = 1;
        return;
    }
    if (line.word(0) != "map" || line.size() != 5) {
        line.fail("the second line is 'map X_MIN Y_MIN X_MAX Y_MAX'");
    }
    const double b[4] = {line.number(1), line.number(2), line.number(3), line.number(4)};
    if (b[0] != map.xMin || b[1] != map.yMin || b[2] != map.xMax || b[3] != map.yMax) {
        line.fail("the site file is for the map " + exact(b[0]) + " " + exact(b[1]) + " " + exact(b[2]) + " " +
                  exact(b[3]) + "; the scenario's [map] is " + exact(map.xMin) + " " + exact(map.yMin) + " " +
                  exact(map.xMax) + " " + exact(map.yMax));
    }
    *state = 2;
}

Obstacle readRock(const Line& line, const Scenario& s) {
    if (line.word(0) != "rock") {
        line.fail("unknown line '" + line.word(0) + "' (a rock line is 'rock known|hidden seen|unseen X0 Y0 ...')");
    }
    if (line.size() < 3 || (line.word(1) != "known" && line.word(1) != "hidden") ||
        (line.word(2) != "seen" && line.word(2) != "unseen")) {
        line.fail("a rock line is 'rock known|hidden seen|unseen X0 Y0 ...'");
    }
    const std::size_t coordinates = line.size() - 3;
    if (coordinates % 2 != 0) {
        line.fail("an odd number of coordinates (" + std::to_string(coordinates) + "): vertices are x y pairs");
    }
    const std::size_t n = coordinates / 2;
    if (n < 3 || n > kMaxPolygonVertices) {
        line.fail("needs 3 to " + std::to_string(kMaxPolygonVertices) + " vertices (got " + std::to_string(n) + ")");
    }
    Obstacle o;
    o.known = line.word(1) == "known";
    o.detectable = line.word(2) == "seen";
    for (std::size_t k = 0; k < n; ++k) {
        const Vec2 v{line.number(3 + 2 * k), line.number(4 + 2 * k)};
        if (!s.map.contains(v)) {
            line.fail("vertex " + std::to_string(k) + " (" + exact(v.x) + ", " + exact(v.y) + ") is outside the map");
        }
        o.shape.v[k] = v;
    }
    o.shape.n = n;
    if (!isConvexCcw(o.shape.v.data(), n)) {
        line.fail("the rock is not convex and counter-clockwise");
    }
    if (o.known) {
        // A known rock goes up on the site map, as the image's f32 numbers:
        // held to the flight check here, not refused at MAP_COMMIT later.
        if (n > site_map::kMaxRockVertices) {
            line.fail("a known rock goes up on the site map: at most " + std::to_string(site_map::kMaxRockVertices) +
                      " vertices (got " + std::to_string(n) + ")");
        }
        float fx[kMaxPolygonVertices] = {};
        float fy[kMaxPolygonVertices] = {};
        for (std::size_t k = 0; k < n; ++k) {
            fx[k] = static_cast<float>(o.shape.v[k].x);
            fy[k] = static_cast<float>(o.shape.v[k].y);
        }
        bool clockwise = false;
        if (!site_map::convexCounterClockwise(fx, fy, n, &clockwise)) {
            line.fail("as the site map's f32 numbers the rock is not convex and counter-clockwise");
        }
    }
    const Vec2 start{s.start.x, s.start.y};
    if (circleIntersectsPolygon(start, s.rover.radiusM, o.shape)) {
        line.fail("the rock overlaps the rover's footprint at the start");
    }
    if (s.mission.present && s.mission.hasGoal &&
        circleIntersectsPolygon(Vec2{s.mission.goalX, s.mission.goalY}, s.rover.radiusM, o.shape)) {
        line.fail("the rock overlaps the rover's footprint at the mission's goal");
    }
    return o;
}

}  // namespace

std::string siteFileText(const Scenario& s) {
    std::ostringstream out;
    out << "# The rocks of " << s.name << " (" << s.source << "): " << s.obstacles.size()
        << " rocks, written by rse-sim --site-file.\n"
        << "# rock known|hidden seen|unseen x0 y0 x1 y1 ... (m, map frame, convex, counter-clockwise)\n"
        << kMagic << " " << kVersion << "\n"
        << "map " << exact(s.map.xMin) << " " << exact(s.map.yMin) << " " << exact(s.map.xMax) << " "
        << exact(s.map.yMax) << "\n";
    for (const Obstacle& o : s.obstacles) {
        out << "rock " << (o.known ? "known" : "hidden") << " " << (o.detectable ? "seen" : "unseen");
        for (std::size_t k = 0; k < o.shape.n; ++k) {
            out << " " << exact(o.shape.v[k].x) << " " << exact(o.shape.v[k].y);
        }
        out << "\n";
    }
    return out.str();
}

void addSiteFileRocks(const std::string& path, Scenario* s) {
    std::ifstream in(path, std::ios::binary);
    if (!in) {
        throw ScenarioError(path + ": cannot read the site file");
    }
    int state = 0;   // 0: the magic line next, 1: the map line, 2: rocks
    std::size_t rocks = 0, known = 0, number = 0;
    for (std::string text; std::getline(in, text);) {
        const Line line(path, ++number, text);
        if (line.empty()) {
            continue;
        }
        if (state < 2) {
            checkHeader(line, s->map, &state);
            continue;
        }
        if (rocks == kMaxSiteFileRocks) {
            line.fail("more than " + std::to_string(kMaxSiteFileRocks) + " rocks");
        }
        Obstacle o = readRock(line, *s);
        o.id = static_cast<std::uint16_t>(kFirstFieldRockId + rocks++);
        known += o.known ? 1U : 0U;
        s->obstacles.push_back(o);
    }
    if (state < 2) {
        throw ScenarioError(path + ": ends before its " + (state == 0 ? "'rse-site 1' line" : "map line"));
    }
    if (known > site_map::kMaxSiteRocks) {
        throw ScenarioError(path + ": " + std::to_string(known) + " known rocks; the site map holds at most " +
                            std::to_string(site_map::kMaxSiteRocks));
    }
}

}  // namespace rse::sim
