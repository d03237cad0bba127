#include "ground/text_format.hpp"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>

namespace rse::ground {

std::string formatNumber(double value) {
    if (std::isnan(value)) {
        return "nan";
    }
    if (std::isinf(value)) {
        return value > 0 ? "inf" : "-inf";
    }
    if (value == std::floor(value) && std::fabs(value) < 9007199254740992.0) {
        char buffer[32];
        std::snprintf(buffer, sizeof buffer, "%lld", static_cast<long long>(value));
        return buffer;
    }
    char buffer[40];
    for (int precision = 1; precision <= 17; ++precision) {
        std::snprintf(buffer, sizeof buffer, "%.*g", precision, value);
        if (std::strtod(buffer, nullptr) == value) {
            break;
        }
    }
    return buffer;
}

std::string formatFloat(float value) {
    if (std::isnan(value) || std::isinf(value)) {
        return formatNumber(static_cast<double>(value));
    }
    const auto wide = static_cast<double>(value);
    if (value == std::floor(value) && std::fabs(wide) < 16777216.0) {
        return formatNumber(wide);
    }
    char buffer[40];
    for (int precision = 1; precision <= 9; ++precision) {
        std::snprintf(buffer, sizeof buffer, "%.*g", precision, wide);
        if (std::strtof(buffer, nullptr) == value) {
            break;
        }
    }
    return buffer;
}

std::string toUpper(std::string text) {
    for (char& c : text) {
        c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    }
    return text;
}

std::string toLower(std::string text) {
    for (char& c : text) {
        c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    }
    return text;
}

std::string hexBytes(const std::uint8_t* data, std::size_t length, bool spaced) {
    static const char kDigits[] = "0123456789ABCDEF";
    std::string text;
    text.reserve(length * 3);
    for (std::size_t i = 0; i < length; ++i) {
        if (i > 0 && spaced) {
            text += ' ';
        }
        text += kDigits[data[i] >> 4];
        text += kDigits[data[i] & 0xF];
    }
    return text;
}

int hexDigit(char c) {
    const int l = std::tolower(static_cast<unsigned char>(c));
    if (l >= '0' && l <= '9') {
        return l - '0';
    }
    if (l >= 'a' && l <= 'f') {
        return l - 'a' + 10;
    }
    return -1;
}

bool parseHexBytes(const std::string& text, std::vector<std::uint8_t>* out) {
    if (text.size() % 2 != 0) {
        return false;
    }
    std::vector<std::uint8_t> bytes(text.size() / 2);
    for (std::size_t i = 0; i < bytes.size(); ++i) {
        const int high = hexDigit(text[2 * i]);
        const int low = hexDigit(text[2 * i + 1]);
        if (high < 0 || low < 0) {
            return false;
        }
        bytes[i] = static_cast<std::uint8_t>((high << 4) | low);
    }
    *out = std::move(bytes);
    return true;
}

bool parseDouble(const std::string& text, double* out) {
    if (text.empty() || std::isspace(static_cast<unsigned char>(text[0])) != 0) {
        return false;
    }
    char* end = nullptr;
    errno = 0;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0') {
        return false;
    }
    *out = value;  // ERANGE: inf or a denormal/0; callers check the range
    return true;
}

bool parseInteger(const std::string& text, long long* out) {
    std::size_t i = 0;
    bool negative = false;
    if (i < text.size() && (text[i] == '+' || text[i] == '-')) {
        negative = text[i] == '-';
        ++i;
    }
    int base = 10;
    if (i + 1 < text.size() && text[i] == '0' && (text[i + 1] == 'x' || text[i + 1] == 'X')) {
        base = 16;
        i += 2;
    }
    if (i >= text.size()) {
        return false;
    }
    unsigned long long magnitude = 0;
    for (; i < text.size(); ++i) {
        const int c = std::tolower(static_cast<unsigned char>(text[i]));
        int digit = 0;
        if (c >= '0' && c <= '9') {
            digit = c - '0';
        } else if (base == 16 && c >= 'a' && c <= 'f') {
            digit = c - 'a' + 10;
        } else {
            return false;
        }
        const auto d = static_cast<unsigned long long>(digit);
        const auto b = static_cast<unsigned long long>(base);
        if (magnitude > (~0ULL - d) / b) {
            return false;
        }
        magnitude = magnitude * b + d;
    }
    const unsigned long long limit = negative ? (1ULL << 63) : (1ULL << 63) - 1;
    if (magnitude > limit) {
        return false;
    }
    *out = negative ? (magnitude == (1ULL << 63) ? static_cast<long long>(-9223372036854775807LL - 1)
                                                 : -static_cast<long long>(magnitude))
                    : static_cast<long long>(magnitude);
    return true;
}

}  // namespace rse::ground
