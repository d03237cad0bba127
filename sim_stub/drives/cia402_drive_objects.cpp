#include "sim_stub/drives/cia402_drive_emulator.hpp"

#include "sim_stub/drives/canopen_le.hpp"
#include "sim_stub/drives/cia402_drive_codes.hpp"

// The wheel drive emulator's object dictionary, as its SDO server sees it
// (SdoObjectDictionary: describe, read, write).

namespace rse::sim {

namespace {

using namespace drive_codes;

// The object dictionary (docs/icd.md §1.4 and CiA 301/402). Size 0 = the device
// name string. PDO mappings and COB-IDs are static (read-only), as CiA 301 allows;
// a write answers 0x06010002.
enum class Access : std::uint8_t { kReadOnly, kReadWrite };
struct ObjectEntry {
    std::uint16_t index;
    std::uint8_t subIndex;
    std::uint8_t size;
    Access access;
};
constexpr ObjectEntry kObjects[] = {
    {0x1000, 0, 4, Access::kReadOnly},   // device type
    {0x1001, 0, 1, Access::kReadOnly},   // error register
    {0x1008, 0, 0, Access::kReadOnly},   // manufacturer device name (string)
    {0x1017, 0, 2, Access::kReadWrite},  // producer heartbeat time, ms
    {0x1018, 0, 1, Access::kReadOnly},   // identity: highest sub-index
    {0x1018, 1, 4, Access::kReadOnly},   //   vendor id (0: none registered)
    {0x1018, 2, 4, Access::kReadOnly},   //   product code
    {0x1018, 3, 4, Access::kReadOnly},   //   revision
    {0x1018, 4, 4, Access::kReadOnly},   //   serial number (= node id)
    {0x1400, 0, 1, Access::kReadOnly},   // RPDO1 communication: highest sub-index
    {0x1400, 1, 4, Access::kReadOnly},   //   COB-ID
    {0x1400, 2, 1, Access::kReadOnly},   //   transmission type (synchronous)
    {0x1600, 0, 1, Access::kReadOnly},   // RPDO1 mapping
    {0x1600, 1, 4, Access::kReadOnly},
    {0x1600, 2, 4, Access::kReadOnly},
    {0x1800, 0, 1, Access::kReadOnly},   // TPDO1 communication: highest sub-index
    {0x1800, 1, 4, Access::kReadOnly},   //   COB-ID
    {0x1800, 2, 1, Access::kReadWrite},  //   transmission type: 1..240 = every n-th SYNC
    {0x1A00, 0, 1, Access::kReadOnly},   // TPDO1 mapping
    {0x1A00, 1, 4, Access::kReadOnly},
    {0x1A00, 2, 4, Access::kReadOnly},
    {0x1A00, 3, 4, Access::kReadOnly},
    {0x6007, 0, 2, Access::kReadOnly},   // abort connection option code (2: disable voltage)
    {0x6040, 0, 2, Access::kReadWrite},  // controlword
    {0x6041, 0, 2, Access::kReadOnly},   // statusword
    {0x6060, 0, 1, Access::kReadWrite},  // modes of operation (3 only)
    {0x6061, 0, 1, Access::kReadOnly},   // modes of operation display
    {0x606C, 0, 4, Access::kReadOnly},   // velocity actual value, mrad/s
    {0x6078, 0, 2, Access::kReadOnly},   // current actual value, mA (ICD deviation from per mille)
    {0x60FF, 0, 4, Access::kReadWrite},  // target velocity, mrad/s
    {0x6502, 0, 4, Access::kReadOnly},   // supported drive modes: pv
};

constexpr std::size_t kDeviceNameLength = sizeof Cia402DriveEmulator::kDeviceName - 1;

constexpr std::uint32_t key(std::uint16_t index, std::uint8_t subIndex) {
    return (static_cast<std::uint32_t>(index) << 8U) | subIndex;
}


}  // namespace

std::uint32_t Cia402DriveEmulator::describe(std::uint16_t index, std::uint8_t subIndex, SdoObjectInfo* info) const {
    bool indexFound = false;
    for (const ObjectEntry& e : kObjects) {
        if (e.index != index) {
            continue;
        }
        indexFound = true;
        if (e.subIndex == subIndex) {
            info->size = e.size == 0 ? kDeviceNameLength : e.size;
            info->readable = true;
            info->writable = e.access == Access::kReadWrite;
            return sdo_abort::kNone;
        }
    }
    return indexFound ? sdo_abort::kSubIndexDoesNotExist : sdo_abort::kObjectDoesNotExist;
}

std::uint32_t Cia402DriveEmulator::read(std::uint16_t index, std::uint8_t subIndex, std::uint8_t* out,
                                        std::size_t capacity) {
    if (index == 0x1008 && subIndex == 0) {
        if (capacity < kDeviceNameLength) {
            return sdo_abort::kGeneralError;
        }
        for (std::size_t i = 0; i < kDeviceNameLength; ++i) {
            out[i] = static_cast<std::uint8_t>(kDeviceName[i]);
        }
        return sdo_abort::kNone;
    }
    std::uint32_t v = 0;
    switch (key(index, subIndex)) {
        case key(0x1000, 0): v = kDeviceType; break;
        case key(0x1001, 0): v = errorRegister(); break;
        case key(0x1017, 0): v = heartbeatMs_; break;
        case key(0x1018, 0): v = 4; break;
        case key(0x1018, 1): v = 0; break;
        case key(0x1018, 2): v = 0x00000402; break;
        case key(0x1018, 3): v = 0x00010000; break;
        case key(0x1018, 4): v = nodeId_; break;
        case key(0x1400, 0): v = 2; break;
        case key(0x1400, 1): v = kCobRpdo1 + nodeId_; break;
        case key(0x1400, 2): v = 1; break;
        case key(0x1600, 0): v = 2; break;
        case key(0x1600, 1): v = 0x60400010; break;
        case key(0x1600, 2): v = 0x60FF0020; break;
        case key(0x1800, 0): v = 2; break;
        case key(0x1800, 1): v = kCobTpdo1 + nodeId_; break;
        case key(0x1800, 2): v = tpdoType_; break;
        case key(0x1A00, 0): v = 3; break;
        case key(0x1A00, 1): v = 0x60410010; break;
        case key(0x1A00, 2): v = 0x606C0020; break;
        case key(0x1A00, 3): v = 0x60780010; break;
        case key(0x6007, 0): v = 2; break;
        case key(0x6040, 0): v = controlword_; break;
        case key(0x6041, 0): v = statusword(); break;
        case key(0x6060, 0): v = static_cast<std::uint8_t>(mode_); break;
        case key(0x6061, 0): v = static_cast<std::uint8_t>(mode_); break;
        case key(0x606C, 0): v = static_cast<std::uint32_t>(reportVelocityMradS()); break;
        case key(0x6078, 0): v = static_cast<std::uint16_t>(reportCurrentMa()); break;
        case key(0x60FF, 0): v = static_cast<std::uint32_t>(targetVelocity_); break;
        case key(0x6502, 0): v = 0x00000004; break;  // bit 2: profile velocity
        default: return sdo_abort::kObjectDoesNotExist;
    }
    if (capacity < 4) {
        return sdo_abort::kGeneralError;
    }
    le::put32(out, v);  // the server sends the object's size of these bytes
    return sdo_abort::kNone;
}

std::uint32_t Cia402DriveEmulator::write(std::uint16_t index, std::uint8_t subIndex, const std::uint8_t* data,
                                         std::size_t size, core::TimeNs now) {
    std::uint8_t bytes[4] = {};
    for (std::size_t i = 0; i < size && i < 4; ++i) {
        bytes[i] = data[i];
    }
    const std::uint32_t v = le::u32(bytes);
    switch (key(index, subIndex)) {
        case key(0x1017, 0):
            heartbeatMs_ = static_cast<std::uint16_t>(v);
            nextHeartbeat_ = now + static_cast<core::TimeNs>(heartbeatMs_) * core::kNsPerMs;
            return sdo_abort::kNone;
        case key(0x1800, 2):
            if (v < 1 || v > 240) {
                return sdo_abort::kValueRangeExceeded;  // only synchronous cyclic types are supported
            }
            tpdoType_ = static_cast<std::uint8_t>(v);
            syncsSinceTpdo_ = 0;
            return sdo_abort::kNone;
        case key(0x6040, 0):
            applyControlword(static_cast<std::uint16_t>(v), now);
            return sdo_abort::kNone;
        case key(0x6060, 0):
            if (static_cast<std::int8_t>(bytes[0]) != static_cast<std::int8_t>(kProfileVelocityMode)) {
                return sdo_abort::kValueRangeExceeded;  // profile velocity is the only mode
            }
            mode_ = static_cast<std::int8_t>(kProfileVelocityMode);
            return sdo_abort::kNone;
        case key(0x60FF, 0):
            targetVelocity_ = static_cast<std::int32_t>(v);
            return sdo_abort::kNone;
        default:
            return sdo_abort::kWriteToReadOnly;
    }
}

}  // namespace rse::sim
