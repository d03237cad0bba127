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
