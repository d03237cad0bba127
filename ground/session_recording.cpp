#include "ground/session_recording.hpp"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "ground/telemetry_decoder.hpp"
#include "ground/text_format.hpp"

namespace rse::ground {

namespace {

constexpr const char* kLinkPrefix = "# link ";
constexpr const char* kStartedPrefix = "# started ";

bool startsWith(const std::string& text, const char* prefix) { return text.rfind(prefix, 0) == 0; }

// The rendering on one line: control characters (an event's text is the
// rover's) cannot start a line of their own.
std::string oneLine(std::string text) {
    for (char& c : text) {
        const auto u = static_cast<unsigned char>(c);
        if (u < 0x20 || u == 0x7F) {
            c = '?';
        }
    }
    return text;
}

}  // namespace

SessionRecorder::SessionRecorder(std::ostream& out, const std::string& link, double startUtc) : out_(out) {
    char started[64];
    std::snprintf(started, sizeof started, "%.6f", startUtc);
    out_ << kRecordingMagic << "\n"
         << kLinkPrefix << oneLine(link) << "\n"
         << kStartedPrefix << started << " (UTC, Unix seconds)\n"
         << "# fields: seconds since the start, the packet in hex, its rendering\n"
         << std::flush;
}

void SessionRecorder::record(double receivedS, const std::vector<std::uint8_t>& bytes) {
    char when[32];
    std::snprintf(when, sizeof when, "%.6f", receivedS);
    out_ << when << ' ' << hexBytes(bytes.data(), bytes.size(), false) << ' '
         << oneLine(renderPacket(decodeTelemetry(bytes))) << '\n'
         << std::flush;
    ++packets_;
}

SessionRecording readSessionRecording(std::istream& in) {
    SessionRecording r;
    std::string line;
    if (!std::getline(in, line) || line != kRecordingMagic) {
        r.errors.push_back(std::string("line 1: not a session recording (expected '") + kRecordingMagic + "')");
        return r;
    }
    std::size_t number = 1;
    double last = 0.0;
    while (std::getline(in, line)) {
        ++number;
        if (line.empty()) {
            continue;
        }
        if (line[0] == '#') {
            if (startsWith(line, kLinkPrefix)) {
                r.link = line.substr(std::char_traits<char>::length(kLinkPrefix));
            } else if (startsWith(line, kStartedPrefix)) {
                std::istringstream fields(line.substr(std::char_traits<char>::length(kStartedPrefix)));
                std::string utc;
                fields >> utc;
                double value = 0.0;
                if (parseDouble(utc, &value) && std::isfinite(value)) {
                    r.startUtc = value;
                }
            }
            continue;
        }
        std::istringstream fields(line);
        std::string when, hex;
        fields >> when >> hex;
        double seconds = 0.0;
        RecordedPacket packet;
        const char* why = nullptr;
        if (!parseDouble(when, &seconds) || !std::isfinite(seconds) || seconds < 0.0) {
            why = "no receive time";
        } else if (seconds < last) {
            why = "receive time goes backwards";
        } else if (hex.empty() || hex.size() > 2 * kMaxRecordedPacket || !parseHexBytes(hex, &packet.bytes)) {
            why = "no packet (hex bytes)";
        }
        if (why != nullptr) {
            r.errors.push_back("line " + std::to_string(number) + ": " + why);
            continue;
        }
        last = seconds;
        packet.receivedS = seconds;
        r.packets.push_back(std::move(packet));
    }
    return r;
}

}  // namespace rse::ground
