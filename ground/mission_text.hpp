// How the mission tooling words what it quotes to people: a flight event's
// own words, and a mission time. Text only: nothing decides on it (the ground
// reads its numbers from telemetry fields, docs/mission.md).
// Host only.
#pragma once

#include <cstdio>
#include <string>

namespace rse::ground {

// The words of a flight event after its "layer: " prefix, to quote.
inline std::string eventWords(const std::string& text) {
    const std::size_t colon = text.find(": ");
    return colon == std::string::npos ? text : text.substr(colon + 2);
}

// A mission time as the points print it: "12.34 s".
inline std::string secondsText(double t) {
    char text[32];
    std::snprintf(text, sizeof text, "%.2f s", t);
    return text;
}

}  // namespace rse::ground
