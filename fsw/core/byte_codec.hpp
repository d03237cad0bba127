// Big-endian (network order) field codec over a caller's fixed buffer.
//
// Everything that crosses the ground link or lives in a table image is
// big-endian, whatever the flight computer's byte order. Both classes carry a
// sticky error flag instead of failing each call: write or read past the end
// sets it, further calls do nothing (reads give zero), and the caller checks
// ok() once at the end. That keeps encoders and decoders straight-line code.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>

namespace rse::core {

class BeWriter {
public:
    BeWriter(std::uint8_t* buffer, std::size_t capacity) : buffer_(buffer), capacity_(capacity) {}

    void u8(std::uint8_t v) { put(v, 1); }
    void u16(std::uint16_t v) { put(v, 2); }
    void u32(std::uint32_t v) { put(v, 4); }
    void u64(std::uint64_t v) { put(v, 8); }
    void i8(std::int8_t v) { put(static_cast<std::uint8_t>(v), 1); }
    void i16(std::int16_t v) { put(static_cast<std::uint16_t>(v), 2); }
    void i32(std::int32_t v) { put(static_cast<std::uint32_t>(v), 4); }
    void i64(std::int64_t v) { put(static_cast<std::uint64_t>(v), 8); }
    void f32(float v) {
        std::uint32_t bits = 0;
        std::memcpy(&bits, &v, sizeof bits);
        put(bits, 4);
    }
    void f64(double v) {
        std::uint64_t bits = 0;
        std::memcpy(&bits, &v, sizeof bits);
        put(bits, 8);
    }
    void bytes(const void* data, std::size_t length) {
        if (!reserve(length)) {
            return;
        }
        if (length > 0) {
            std::memcpy(buffer_ + size_, data, length);
        }
        size_ += length;
    }
    // Writes at an absolute position already written (e.g. a length field).
    void patchU16(std::size_t at, std::uint16_t v) {
        if (at + 2 > size_) {
            ok_ = false;
            return;
        }
        buffer_[at] = static_cast<std::uint8_t>(v >> 8);
        buffer_[at + 1] = static_cast<std::uint8_t>(v);
    }

    bool ok() const { return ok_; }
    std::size_t size() const { return size_; }
    std::uint8_t* data() { return buffer_; }

private:
    bool reserve(std::size_t length) {
        if (!ok_ || length > capacity_ - size_) {
            ok_ = false;
            return false;
        }
        return true;
    }
    void put(std::uint64_t value, std::size_t width) {
        if (!reserve(width)) {
            return;
        }
        for (std::size_t i = 0; i < width; ++i) {
            buffer_[size_ + i] = static_cast<std::uint8_t>(value >> (8 * (width - 1 - i)));
        }
        size_ += width;
    }

    std::uint8_t* buffer_;
    std::size_t capacity_;
    std::size_t size_ = 0;
    bool ok_ = true;
};

class BeReader {
public:
    BeReader(const std::uint8_t* data, std::size_t length) : data_(data), length_(length) {}

    std::uint8_t u8() { return static_cast<std::uint8_t>(get(1)); }
    std::uint16_t u16() { return static_cast<std::uint16_t>(get(2)); }
    std::uint32_t u32() { return static_cast<std::uint32_t>(get(4)); }
    std::uint64_t u64() { return get(8); }
    std::int8_t i8() { return static_cast<std::int8_t>(get(1)); }
    std::int16_t i16() { return static_cast<std::int16_t>(get(2)); }
    std::int32_t i32() { return static_cast<std::int32_t>(get(4)); }
    std::int64_t i64() { return static_cast<std::int64_t>(get(8)); }
    float f32() {
        const auto bits = static_cast<std::uint32_t>(get(4));
        float v = 0.0F;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    double f64() {
        const std::uint64_t bits = get(8);
        double v = 0.0;
        std::memcpy(&v, &bits, sizeof v);
        return v;
    }
    void bytes(void* out, std::size_t length) {
        if (!take(length)) {
            std::memset(out, 0, length);
            return;
        }
        if (length > 0) {
            std::memcpy(out, data_ + position_ - length, length);
        }
    }
    void skip(std::size_t length) { (void)take(length); }

    bool ok() const { return ok_; }
    std::size_t position() const { return position_; }
    std::size_t remaining() const { return ok_ ? length_ - position_ : 0; }

private:
    bool take(std::size_t length) {
        if (!ok_ || length > length_ - position_) {
            ok_ = false;
            return false;
        }
        position_ += length;
        return true;
    }
    std::uint64_t get(std::size_t width) {
        if (!take(width)) {
            return 0;
        }
        std::uint64_t value = 0;
        for (std::size_t i = 0; i < width; ++i) {
            value = (value << 8) | data_[position_ - width + i];
        }
        return value;
    }

    const std::uint8_t* data_;
    std::size_t length_;
    std::size_t position_ = 0;
    bool ok_ = true;
};

}  // namespace rse::core
