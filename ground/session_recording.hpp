// A ground session recording: every packet the ground received on its link,
// in the order received, each with its receive time, written as it comes (one
// line a packet, flushed) so a recording cut short keeps what it had. The
// packet's bytes are kept whole (hex), so the recording decodes again with
// any later dictionary; a rendered copy of each line follows for people.
//
//   # rse-ground session recording 1
//   # link ISO-TP vcan0 tx 0x6C0 rx 0x6C1
//   # started 1733157000.123456 (UTC, Unix seconds)
//   0.004121 0803C00400780000002A8000... EVENT apid=0x003 seq=0 met=12.340 EVT 905 INFO ...
//
// The first field is seconds since the recording started (this machine's
// CLOCK_MONOTONIC), the second the packet in hex, the rest the rendering
// (control characters replaced by '?'). Lines starting with '#' are comments.
//
// Host code (ground/): full language.
#pragma once

#include <cstdint>
#include <istream>
#include <ostream>
#include <string>
#include <vector>

namespace rse::ground {

constexpr const char* kRecordingMagic = "# rse-ground session recording 1";
// The longest packet a recording line may hold (a CCSDS packet is at most
// 65542 bytes; the rover's are far shorter).
constexpr std::size_t kMaxRecordedPacket = 65542;

struct RecordedPacket {
    double receivedS = 0.0;  // since the recording started
    std::vector<std::uint8_t> bytes;
};

struct SessionRecording {
    std::string link;        // the link it was received on
    double startUtc = 0.0;   // UTC when the recording started (0: not said)
    std::vector<RecordedPacket> packets;
    std::vector<std::string> errors;  // "line N: why" for each line that was not a packet
};

// Writes a recording to `out`: the header at construction, then a line per
// packet (flushed).
class SessionRecorder {
public:
    SessionRecorder(std::ostream& out, const std::string& link, double startUtc);
    void record(double receivedS, const std::vector<std::uint8_t>& bytes);
    std::size_t packets() const { return packets_; }
    bool ok() const { return static_cast<bool>(out_); }

private:
    std::ostream& out_;
    std::size_t packets_ = 0;
};

// Reads a recording. A file that does not start with kRecordingMagic is an
// error (errors[0] says so, no packets); a bad line is skipped and named in
// errors, the others are kept. Receive times must not go backwards (a line
// that does is refused as a bad line).
SessionRecording readSessionRecording(std::istream& in);

}  // namespace rse::ground
