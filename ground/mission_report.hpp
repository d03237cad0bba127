// A mission record (ground/mission_record.hpp) written for people: a Markdown
// report (the ten points with their times and layers, the legs and their
// bounds, every fail-up, relaxation, replan and call home, the energy, the
// per-task timing) and an SVG map (the coarse map's rocks, the hidden rocks
// when the record has the truth, the hazard discs seen, every plan with its
// risk ellipses, the driven and the estimated tracks, the ten points numbered
// where they happened). rse-demo writes them to build/mission/report.md and
// build/mission/map.svg; the map is drawn with ground/plan_svg.hpp's pieces.
// Host only.
#pragma once

#include <string>

#include "ground/mission_record.hpp"

namespace rse::ground {

std::string renderMissionReport(const MissionRecord& record, const std::string& mapFileName);
std::string renderMissionMap(const MissionRecord& record);

// Writes <dir>/report.md and <dir>/map.svg (the folder made if missing). On
// failure false and *error says what.
bool writeMissionFiles(const MissionRecord& record, const std::string& dir, std::string* reportPath,
                       std::string* mapPath, std::string* error);

}  // namespace rse::ground
