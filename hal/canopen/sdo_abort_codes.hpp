// CiA 301 SDO abort codes (the values of the standard), shared by the flight SDO
// client and the simulator's SDO server.
#pragma once

#include <cstdint>

namespace rse::hal::canopen::sdo_abort {

constexpr std::uint32_t kNone = 0;
constexpr std::uint32_t kToggleNotAlternated = 0x05030000;
constexpr std::uint32_t kTimeout = 0x05040000;
constexpr std::uint32_t kInvalidCommand = 0x05040001;
constexpr std::uint32_t kOutOfMemory = 0x05040005;
constexpr std::uint32_t kReadOfWriteOnly = 0x06010001;
constexpr std::uint32_t kWriteToReadOnly = 0x06010002;
constexpr std::uint32_t kObjectDoesNotExist = 0x06020000;
constexpr std::uint32_t kLengthMismatch = 0x06070010;
constexpr std::uint32_t kSubIndexDoesNotExist = 0x06090011;
constexpr std::uint32_t kValueRangeExceeded = 0x06090030;
constexpr std::uint32_t kGeneralError = 0x08000000;

}  // namespace rse::hal::canopen::sdo_abort
