// The science instruments' CAN protocol (docs/icd.md §1.7), one codec for both
// ends: the flight client (hal/devices/instrument.hpp) encodes commands and
// decodes reports, the simulator's emulator (sim_stub/devices/
// instrument_emulator.hpp) decodes commands and encodes reports.
//
// Two instruments, each an RSE device node with a CANopen-style heartbeat:
//   grinder/sampler  node 0x24, status 0x6A5, command 0x6B5: sample, dig
//   camera           node 0x25, status 0x6A6, command 0x6B6: image
// Both take cancel and extend. Every frame is 8 bytes, little-endian.
//
// Command (master -> instrument):
//   0    action: 1 sample, 2 dig, 3 image, 4 cancel, 5 extend
//   1    science target id 1..255 (cancel: 0, or the target of the command;
//        extend: the target of the command it continues)
//   2-3  command id u16, 1..65535, chosen by the master; cancel: the id of the
//        command to cancel (it must be the one running); extend: a new id, the
//        follow-on's, other than the one it continues
//   4-5  max duration u16 [0.1 s]: the instrument gives up (failed, timed out)
//        when the work is not done by then; 0: no limit (cancel: 0).
//        extend: the extra work, 1..65535 [0.1 s]
//   6-7  reserved, 0; extend: the id of the command it continues (it must be
//        the one running, on that target)
// Extend (a follow-on request): the command running goes on for the extra
// work on the same target, and is from then on known by the follow-on's id
// (its status reports name it, with the action of the command continued);
// its max duration, counted from the original command's start, is unchanged.
// Taken: the status names the new id at once; not: a refusal naming it (7
// when the command named is not the one running, or not on that target).
// Report (instrument -> master): byte 0 = kind << 4 | state, then
//   1    action of the command in bytes 3-4 (0 none; never cancel)
//   2    its target id (0 none)
//   3-4  its command id (0 none)
//   5    status: progress 0..100 %;     refusal: why (Refusal 1..7)
//   6    status: result (Result);       refusal: 0
//   7    the instrument's own fault code: 0 healthy, else it is faulted and
//        refuses every command until the fault clears
//   kind 1 status: sent every 100 ms and at once on every change (a command
//          accepted, finished, failed or cancelled, a fault raised or cleared);
//          the command is the one running or the last one;
//   kind 2 refusal: one per refused command frame, naming it; the state
//          nibble is the instrument's state then.
// Invariants a report must keep (anything else is out of range): state 0..3;
// a fault code only in state failed; a status names a command id, its action
// (one of this instrument's) and its target all together or none of them (and
// then no result);
// busy and done name one, with no result and no fault, busy below 100 %, done
// at 100 %; failed has a fault code or a failure result (timed out, out of
// reach, aborted); progress <= 100, result 0..4; a refusal's reason is 1..7 and
// its byte 6 is 0. The result stays that of the last command whatever the
// state (e.g. cancelled in idle, or cancelled in failed when the instrument
// faulted afterwards).
#pragma once

#include <cstddef>
#include <cstdint>

#include "hal/can/can_frame.hpp"
#include "hal/devices/rse_device_ids.hpp"

namespace rse::hal::instrument {

enum class Kind : std::uint8_t { kGrinder = 0, kCamera = 1 };
constexpr std::size_t kCount = 2;
const char* toString(Kind kind);  // "grinder", "camera"

enum class Action : std::uint8_t { kNone = 0, kSample = 1, kDig = 2, kImage = 3, kCancel = 4, kExtend = 5 };
constexpr std::uint8_t kLastAction = 5;
const char* toString(Action action);

enum class State : std::uint8_t { kIdle = 0, kBusy = 1, kDone = 2, kFailed = 3 };
const char* toString(State state);

// How the last command ended, when not done.
enum class Result : std::uint8_t {
    kNone = 0,
    kCancelled = 1,   // a cancel stopped it (state idle)
    kTimedOut = 2,    // not done within its max duration (failed)
    kOutOfReach = 3,  // the target was, or went, out of the instrument's reach (failed)
    kAborted = 4,     // an instrument fault stopped it (failed; idle once the fault clears)
};
constexpr std::uint8_t kLastResult = 4;
const char* toString(Result result);

// Why a command was not taken. 1..7 come from the instrument (refusal report);
// 8..9 are the flight client's own, never on the wire: the command was not sent.
enum class Refusal : std::uint8_t {
    kNone = 0,
    kBusy = 1,               // another command is running
    kUnsupportedAction = 2,  // not an action of this instrument (or none)
    kUnknownTarget = 3,      // a target id the instrument has no record of (or 0)
    kOutOfReach = 4,         // the target is beyond the instrument's reach from where the rover is
    kFaulted = 5,            // the instrument is faulted
    kMalformed = 6,          // command id 0, reserved bytes not 0, a length other than 8, max duration
                             // out of range (flight side)
    kNoSuchCommand = 7,      // cancel or extend naming a command that is not running (extend: or not on its target)
    kOffline = 8,            // flight side: no status from the instrument, not sent
    kNotSent = 9,            // flight side: the CAN controller refused the frame
};
constexpr std::uint8_t kLastWireRefusal = 7;
constexpr std::uint8_t kLastRefusal = 9;
const char* toString(Refusal refusal);

enum class ReportKind : std::uint8_t { kStatus = 1, kRefusal = 2 };

constexpr std::uint8_t kGrinderNodeId = 0x24;
constexpr std::uint8_t kCameraNodeId = 0x25;
constexpr std::uint8_t kFrameDlc = 8;
constexpr double kDurationUnitS = 0.1;       // max duration field
constexpr double kMaxDurationS = 6553.5;     // its largest value
constexpr core::TimeNs kStatusPeriodNs = 100 * core::kNsPerMs;

struct Ids {
    std::uint8_t node;
    std::uint32_t statusCobId;
    std::uint32_t commandCobId;
};
constexpr Ids idsOf(Kind kind) {
    return kind == Kind::kGrinder
               ? Ids{kGrinderNodeId, device_ids::kGrinderStatus, device_ids::kGrinderCommand}
               : Ids{kCameraNodeId, device_ids::kCameraStatus, device_ids::kCameraCommand};
}

// The actions an instrument works on (cancel and extend are taken by both, but
// are no work of their own: extend continues the command running).
constexpr bool doesWork(Kind kind, Action action) {
    return kind == Kind::kGrinder ? (action == Action::kSample || action == Action::kDig)
                                  : action == Action::kImage;
}

struct Command {
    Action action = Action::kNone;
    std::uint8_t target = 0;
    std::uint16_t commandId = 0;
    std::uint16_t maxDurationDs = 0;     // [0.1 s], 0: no limit; extend: the extra work, >= 1
    std::uint16_t extendsCommandId = 0;  // extend: the command it continues (bytes 6-7); else 0
};

struct Report {
    ReportKind kind = ReportKind::kStatus;
    State state = State::kIdle;
    Action action = Action::kNone;
    std::uint8_t target = 0;
    std::uint16_t commandId = 0;
    std::uint8_t progressPct = 0;         // status
    Result result = Result::kNone;        // status
    Refusal refusal = Refusal::kNone;     // refusal report
    std::uint8_t faultCode = 0;
};

// Max duration in seconds to the wire's 0.1 s, rounded up; false when not
// finite, negative or beyond kMaxDurationS.
bool durationField(double seconds, std::uint16_t* field);

void encodeCommand(Kind kind, const Command& command, CanFrame* frame);
// A command frame as the instrument reads it: false (*why: kMalformed) for a
// length other than 8, RTR, command id 0, reserved bytes not 0 (extend: the
// command it continues 0 or its own id, extra work 0); an action outside 1..5
// decodes (the instrument refuses it as unsupported).
bool decodeCommand(const CanFrame& frame, Command* command, Refusal* why);

void encodeReport(Kind kind, const Report& report, CanFrame* frame);
// The 8 bytes of a report from instrument `kind` (length checked by the
// caller): false with a reason when a field is out of range or the invariants
// above do not hold.
bool decodeReport(Kind kind, const std::uint8_t (&data)[kCanMaxDlc], Report* report, const char** reason);

}  // namespace rse::hal::instrument
