// Small text helpers shared by the ground tool's encoders, decoders and
// exporters: numbers in their shortest exact form, case folding, hex.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rse::ground {

// The shortest text that reads back (strtod) as exactly this double; integral
// values below 2^53 without exponent ("10000", "-2", "1e-09", "0.25", "nan").
std::string formatNumber(double value);
// The same for a float: shortest text that reads back as this float ("0.1").
std::string formatFloat(float value);

std::string toUpper(std::string text);
std::string toLower(std::string text);

// "0A 1B ..." (upper case, space separated; "0A1B..." when not spaced).
std::string hexBytes(const std::uint8_t* data, std::size_t length, bool spaced = true);
// 0..15 for a hex digit (either case), -1 for anything else.
int hexDigit(char c);
// "0A1b..." (an even number of hex digits, nothing else) -> bytes; false
// (out untouched) otherwise.
bool parseHexBytes(const std::string& text, std::vector<std::uint8_t>* out);

// Whole-string number parsing: false unless the entire text is the number.
// parseDouble refuses nothing finite-or-not itself; callers check finiteness.
bool parseDouble(const std::string& text, double* out);
// Decimal or 0x hex, optional sign; false on overflow of 64 bits.
bool parseInteger(const std::string& text, long long* out);

}  // namespace rse::ground
