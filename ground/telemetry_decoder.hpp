// Generic telemetry decoding by the dictionary's descriptors: packet bytes ->
// name, APID, sequence count, MET time and every field, and one readable line.
// Nothing here knows a packet's layout but the descriptors, so a packet added to
// fsw/cmdtlm/dictionary.def decodes without a change here (the unit test checks
// every packet against the flight's generated encoders).
//
// Checks, in order: at least a telemetry header; primary header (version 0,
// telemetry type, secondary header, unsegmented); length field == actual length;
// APID known; payload size == the dictionary's size. A packet failing any check
// is not decoded: `error` says why and the line shows the raw bytes.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "fsw/cmdtlm/dictionary.hpp"

namespace rse::ground {

struct DecodedField {
    const cmdtlm::FieldDesc* desc = nullptr;
    std::vector<double> values;      // one per element (chr: the byte values)
    std::vector<std::uint64_t> raw;  // each element's wire bits, zero-extended (exact for u64/i64)
    std::string text;                // chr fields: the text up to the first NUL
};

struct DecodedPacket {
    bool ok = false;
    std::string error;  // why it was not decoded (ok == false)
    const cmdtlm::TelemetryDesc* desc = nullptr;  // nullptr: unknown APID or unreadable header
    std::uint16_t apid = 0;
    std::uint16_t sequenceCount = 0;
    double met = 0.0;  // mission elapsed time, seconds
    std::size_t length = 0;
    std::vector<std::uint8_t> bytes;  // the packet as received
    std::vector<DecodedField> fields;

    const char* name() const { return desc != nullptr ? desc->name : "?"; }
    // The field of that name (exact, or case-insensitive), or nullptr.
    const DecodedField* field(const std::string& fieldName) const;
    // Element `index` of a field as a number; nullopt when absent.
    std::optional<double> value(const std::string& fieldName, std::size_t index = 0) const;
};

DecodedPacket decodeTelemetry(const std::uint8_t* data, std::size_t length);
inline DecodedPacket decodeTelemetry(const std::vector<std::uint8_t>& packet) {
    return decodeTelemetry(packet.data(), packet.size());
}

// One line, no newline:
//   HK       apid=0x001 seq=12 met=1234.500 utc_at_met_zero=1.7e9 mode=1 ... cmd_rejected_by_reason=[0,1,...]
//   EVENT    apid=0x003 seq=4 met=12.000 EVT 42 WARN some text (event_sequence=7 event_time=11.98)
//   EVENT_DATA apid=0x005 ... event 905 LEG_SENT leg_id=3 index=2 ...  [event_sequence=7 data_withheld=0]
//            (the values by the names fsw/cmdtlm/dictionary.def gives that event's numbers)
//   CMD_ACK  apid=0x002 ... GOTO accepted / rejected: wrong_mode (detail 1)
//   POWER    apid=0x018 ... battery_voltage=23.9!ALARM ...   (a value outside the field's display
//            limits, ground/telemetry_limits.hpp, marked !WARN or !ALARM)
//   HAZARDS  apid=0x019 ... revision=4 count=1 hazards=[#7 (12.5,-1.25) r=0.5]   (the count in use only)
//   UNKNOWN  apid=0x07f seq=3 length 20: 00 01 ...
//   MALFORMED length 3 (shorter than the 12-byte telemetry header): 00 01 02
std::string renderPacket(const DecodedPacket& packet);

// "DEBUG" .. "CRIT" for EVENT.severity; "SEV<n>" otherwise.
std::string severityName(unsigned severity);

// The one-line summary of a CMD_ACK (used by `send`): "GOTO (0x181/0) accepted"
// or "GOTO (0x181/0) rejected: wrong_mode (detail 1)".
std::string describeAck(const DecodedPacket& ack);

// The reason code's snake_case name ("replayed_sequence"); "reason_<n>" if unknown.
std::string rejectReasonName(unsigned reason);
// The code of a reason name (case-insensitive); -1 if none.
int rejectReasonCode(const std::string& name);

}  // namespace rse::ground
