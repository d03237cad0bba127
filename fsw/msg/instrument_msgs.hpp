// The science instruments across the hal I/O boundary: what the plan executive
// asks of them (InstrumentCommandMsg) and what the CAN I/O task says they are
// doing (InstrumentStatusMsg, one per instrument). The instruments are CAN
// devices (docs/icd.md §1.7; hal/devices/instrument.hpp): a grinder/sampler
// that samples or digs a science target and a camera that images one. Each
// works on one command at a time; a command names its target (the
// instrument checks it is within reach of the rover) and carries an id of the
// sender's choosing that every report about it repeats.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fsw/msg/msg_ids.hpp"

namespace rse::msg {

enum class Instrument : std::uint8_t { kGrinder = 0, kCamera = 1 };
constexpr std::size_t kInstrumentCount = 2;
inline const char* instrumentName(std::size_t i) { return i == 0 ? "grinder" : (i == 1 ? "camera" : "?"); }

// What to do. The grinder takes sample and dig, the camera image; both take cancel and extend.
enum class InstrumentAction : std::uint8_t {
    kNone = 0,    // never valid in a command
    kSample = 1,  // grinder: grind and collect a sample of the target
    kDig = 2,     // grinder: dig a trench at the target
    kImage = 3,   // camera: image the target
    kCancel = 4,  // stop the command commandId (it must be the one running); the instrument goes idle
    kExtend = 5,  // a follow-on: the command extendsCommandId (running, on targetId) goes on for
                  // maxDurationS more work and is known by commandId from then on (docs/icd.md §1.7)
};

// Published by the plan executive (or a test); taken by the CAN I/O task in the
// frame it arrives and sent to the instrument at once. A command that cannot
// be sent (an action not the instrument's, target 0, command id 0, a max
// duration out of range, the instrument offline) is not sent; the instrument's
// InstrumentStatusMsg then names it (lastRefusal, lastRefusedCommandId). A
// message that does not decode or names no instrument is dropped (event 211).
struct InstrumentCommandMsg {
    static constexpr core::MsgId kMsgId = ids::kInstrumentCommand;
    std::int64_t timeNs;           // when published
    Instrument instrument;         // which instrument
    InstrumentAction action;
    std::uint8_t targetId;         // science target 1..255 (the scenario's / the site's target ids); cancel: ignored
    std::uint8_t pad;
    std::uint16_t commandId;       // 1..65535, the sender's; a new id for every command (the instrument counts
                                   // a command as new by its id); cancel: the id of the command to stop;
                                   // extend: the follow-on's new id
    std::uint16_t extendsCommandId;  // extend: the id of the command running that it continues; else 0
    double maxDurationS;           // the instrument gives up (failed, timed out) if not done by then;
                                   // [0, 6553.5] s, rounded up to 0.1 s; 0: no limit. Cancel: ignored.
                                   // Extend: the extra work, (0, 6553.5] s (the limit stays the command's)
};

// Where an instrument stands. kOffline is the flight side's: no report from it
// for 500 ms (hal::kInstrumentStatusTimeout) or never one since start; the
// other fields then keep what it last reported.
enum class InstrumentState : std::uint8_t {
    kOffline = 0,
    kIdle = 1,    // ready; nothing running (after start-up, a cancel, or a fault cleared)
    kBusy = 2,    // working on commandId
    kDone = 3,    // commandId finished; ready for the next
    kFailed = 4,  // commandId failed (result says why; ready for the next), or the instrument is faulted
                  // (faultCode != 0: every command refused until the fault clears)
};

// How the command in commandId ended, when it did not finish.
enum class InstrumentResult : std::uint8_t {
    kNone = 0,
    kCancelled = 1,   // stopped by a cancel (state idle)
    kTimedOut = 2,    // not done within its maxDurationS (failed)
    kOutOfReach = 3,  // the target was or went beyond the instrument's reach (failed)
    kAborted = 4,     // an instrument fault stopped it (failed; idle once the fault clears)
};

// Why the command in lastRefusedCommandId was not taken.
enum class InstrumentRefusal : std::uint8_t {
    kNone = 0,
    kBusy = 1,               // the instrument: another command is running
    kUnsupportedAction = 2,  // not an action of this instrument (not sent)
    kUnknownTarget = 3,      // the instrument has no such target (target 0: not sent)
    kOutOfReach = 4,         // the instrument: the target is beyond its reach from where the rover stands
    kFaulted = 5,            // the instrument is faulted
    kMalformed = 6,          // command id 0 or max duration out of range (not sent), or the instrument found
                             // the frame malformed
    kNoSuchCommand = 7,      // the instrument: a cancel or extend naming a command that is not running
    kOffline = 8,            // not sent: the instrument is offline
    kNotSent = 9,            // not sent: the CAN controller refused the frame
};

// Published by the CAN I/O task for each instrument whenever any field but
// timeNs / lastReportNs changes, and at 1 Hz otherwise (each instrument its own
// message; `instrument` says which). "The instrument is usable" for a plan's
// Ask condition: state is neither kOffline nor kFailed with faultCode != 0.
struct InstrumentStatusMsg {
    static constexpr core::MsgId kMsgId = ids::kInstrumentStatus;
    std::int64_t timeNs;             // when published
    std::int64_t lastReportNs;       // when the last good report from the instrument came (0: never)
    Instrument instrument;
    InstrumentState state;
    InstrumentAction action;         // of commandId (kNone when commandId is 0)
    std::uint8_t targetId;           // of commandId (0 when commandId is 0)
    std::uint16_t commandId;         // the command running, or the last one; 0: none since the instrument started
    std::uint8_t progressPct;        // 0..100 of commandId (100 when done; where it stopped otherwise)
    InstrumentResult result;         // how commandId ended when not done
    std::uint8_t faultCode;          // the instrument's own fault (as it reports it), 0: healthy
    InstrumentRefusal lastRefusal;   // the latest command not taken, and why (kNone: none yet)
    std::uint16_t lastRefusedCommandId;
    std::uint8_t pad[4];
    std::uint32_t commandsSent;      // commands sent to the instrument
    std::uint32_t commandsAccepted;  // new command ids the instrument reported working on
    std::uint32_t commandsRefused;   // refused by the instrument (refusal reports)
    std::uint32_t commandsNotSent;   // refused before sending: invalid, offline, CAN refused
    std::uint32_t framesBad;         // reports rejected: wrong length or RTR, a field out of range
    std::uint32_t offlineCount;      // times declared offline
};

}  // namespace rse::msg
