// CiA 301 predefined connection set and NMT codes (docs/icd.md §1.2-1.3).
#pragma once

#include <cstdint>

namespace rse::hal::canopen {

constexpr std::uint8_t kMaxNodeId = 127;

// COB-ID function codes: cob = function + node id.
constexpr std::uint32_t kNmt = 0x000;
constexpr std::uint32_t kSync = 0x080;
constexpr std::uint32_t kEmcy = 0x080;
constexpr std::uint32_t kTpdo1 = 0x180;
constexpr std::uint32_t kRpdo1 = 0x200;
constexpr std::uint32_t kTpdo2 = 0x280;
constexpr std::uint32_t kSdoResponse = 0x580;  // server -> client
constexpr std::uint32_t kSdoRequest = 0x600;   // client -> server
constexpr std::uint32_t kHeartbeat = 0x700;

// CiA 301 restricted CAN-IDs: they shall not be used for SYNC, TIME, EMCY, PDO
// or SDO, and CANopen stacks flag frames there that are none of their own (NMT,
// the reserved ranges, default SDO, NMT error control, LSS). Ids the rover puts
// on the bus for anything else stay outside them (docs/icd.md §1.2).
struct CanIdRange {
    std::uint32_t first;
    std::uint32_t last;  // inclusive
};
constexpr CanIdRange kCia301RestrictedIds[] = {
    {0x000, 0x000},  // NMT
    {0x001, 0x07F},  // reserved
    {0x101, 0x180},  // reserved
    {0x581, 0x5FF},  // default SDO server -> client
    {0x601, 0x67F},  // default SDO client -> server
    {0x6E0, 0x6FF},  // reserved
    {0x701, 0x77F},  // NMT error control (heartbeat, boot-up)
    {0x780, 0x7FF},  // reserved (LSS 0x7E4/0x7E5)
};
constexpr bool isCia301Restricted(std::uint32_t canId) {
    for (const CanIdRange& r : kCia301RestrictedIds) {
        if (canId >= r.first && canId <= r.last) {
            return true;
        }
    }
    return false;
}

constexpr std::uint32_t functionOf(std::uint32_t cobId) { return cobId & 0x780U; }
constexpr std::uint8_t nodeOf(std::uint32_t cobId) { return static_cast<std::uint8_t>(cobId & 0x7FU); }

enum class NmtCommand : std::uint8_t {
    kStart = 0x01,
    kStop = 0x02,
    kEnterPreOperational = 0x80,
    kResetNode = 0x81,
    kResetCommunication = 0x82,
};

// Heartbeat state byte.
enum class NmtState : std::uint8_t {
    kBootUp = 0x00,
    kStopped = 0x04,
    kOperational = 0x05,
    kPreOperational = 0x7F,
    kUnknown = 0xFF,  // never heard (ours, not on the wire)
};
const char* toString(NmtState state);
bool isValidNmtState(std::uint8_t byte);

}  // namespace rse::hal::canopen
