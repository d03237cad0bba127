// Known answers for the one HMAC-SHA-256 class flight and ground share
// (cmdtlm::HmacSha256): the RFC 4231 test cases 1-7 for HMAC-SHA-256, and the
// command MAC of docs/icd.md §5.3 for a fixed packet. The expected values come
// from the RFC (checked with Python's hmac module, i.e. OpenSSL), not from this
// code, so a bug shared by the ground encoder and the flight validator cannot pass.
#include <cstring>
#include <string>
#include <vector>

#include "fsw/cmdtlm/command_auth.hpp"

#include "CppUTest/TestHarness.h"

using namespace rse;
using namespace rse::cmdtlm;

namespace {

std::vector<std::uint8_t> bytes(const std::string& text) { return {text.begin(), text.end()}; }
std::vector<std::uint8_t> repeated(std::uint8_t value, std::size_t count) { return std::vector<std::uint8_t>(count, value); }

std::string hex(const std::uint8_t* data, std::size_t length) {
    static const char digits[] = "0123456789abcdef";
    std::string out;
    for (std::size_t i = 0; i < length; ++i) {
        out += digits[data[i] >> 4];
        out += digits[data[i] & 0x0F];
    }
    return out;
}

struct Rfc4231Case {
    int number;
    std::vector<std::uint8_t> key;
    std::vector<std::uint8_t> data;
    const char* expected;  // hex; case 5 is truncated to 128 bits in the RFC
};

std::vector<Rfc4231Case> rfc4231Cases() {
    std::vector<std::uint8_t> key4;
    for (std::uint8_t b = 0x01; b <= 0x19; ++b) {
        key4.push_back(b);
    }
    return {
        {1, repeated(0x0b, 20), bytes("Hi There"),
         "b0344c61d8db38535ca8afceaf0bf12b881dc200c9833da726e9376c2e32cff7"},
        {2, bytes("Jefe"), bytes("what do ya want for nothing?"),
         "5bdcc146bf60754e6a042426089575c75a003f089d2739839dec58b964ec3843"},
        {3, repeated(0xaa, 20), repeated(0xdd, 50),
         "773ea91e36800e46854db8ebd09181a72959098b3ef8c122d9635514ced565fe"},
        {4, key4, repeated(0xcd, 50), "82558a389a443c0ea4cc819899f2083a85f0faa3e578f8077a2e3ff46729665b"},
        {5, repeated(0x0c, 20), bytes("Test With Truncation"), "a3b6167473100ee06e0c796c2955552b"},
        {6, repeated(0xaa, 131), bytes("Test Using Larger Than Block-Size Key - Hash Key First"),
         "60e431591ee0b67f0d8a26aacbf5b77f8e0bc6213728c5140546040f0ee37f54"},
        {7, repeated(0xaa, 131),
         bytes("This is a test using a larger than block-size key and a larger than block-size data. "
               "The key needs to be hashed before being used by the HMAC algorithm."),
         "9b09ffa71b942fcb27635fbcd5b0e944bfdc63644f0713938a7f51535c3a35e2"},
    };
}

}  // namespace

TEST_GROUP(HmacSha256KnownAnswers) {
    HmacSha256 hmac;
    void setup() override { CHECK(core::isOk(hmac.init())); }
};

TEST(HmacSha256KnownAnswers, Rfc4231TestCases1To7) {
    for (const Rfc4231Case& c : rfc4231Cases()) {
        std::uint8_t out[kHmacSha256Size] = {};
        CHECK(core::isOk(hmac.compute(c.key.data(), c.key.size(), c.data.data(), c.data.size(), out)));
        const std::string expected = c.expected;
        STRCMP_EQUAL_TEXT(expected.c_str(), hex(out, expected.size() / 2).c_str(),
                          ("RFC 4231 test case " + std::to_string(c.number)).c_str());
    }
}

// The same answers with the data split into parts at every byte position
// (packetMac feeds its packet in three parts).
TEST(HmacSha256KnownAnswers, Rfc4231AnswersDoNotDependOnHowTheDataIsSplit) {
    for (const Rfc4231Case& c : rfc4231Cases()) {
        const std::string expected = c.expected;
        for (std::size_t cut = 0; cut <= c.data.size(); ++cut) {
            const HmacSha256::Part parts[] = {{c.data.data(), cut}, {nullptr, 0}, {c.data.data() + cut, c.data.size() - cut}};
            std::uint8_t out[kHmacSha256Size] = {};
            CHECK(core::isOk(hmac.compute(c.key.data(), c.key.size(), parts, 3, out)));
            STRCMP_EQUAL_TEXT(expected.c_str(), hex(out, expected.size() / 2).c_str(),
                              ("RFC 4231 test case " + std::to_string(c.number) + " cut at " + std::to_string(cut)).c_str());
        }
    }
}

// The command MAC (docs/icd.md §5.3): HMAC-SHA-256 over the packet with the
// checksum byte (7) taken as zero, first 16 bytes. Expected value computed
// independently (Python hmac) for bytes i*11+1, i = 0..29, and the lab key.
TEST(HmacSha256KnownAnswers, PacketMacIsTheTruncatedHmacWithTheChecksumByteZeroed) {
    std::uint8_t packet[30];
    for (std::size_t i = 0; i < sizeof packet; ++i) {
        packet[i] = static_cast<std::uint8_t>(i * 11 + 1);
    }
    std::uint8_t mac[kMacSize] = {};
    CHECK(core::isOk(hmac.packetMac(kLabKey, packet, sizeof packet, mac)));
    STRCMP_EQUAL("d4a6351342d28fada47447aada4a8f6b", hex(mac, kMacSize).c_str());
    packet[kChecksumOffset] ^= 0xFF;  // the checksum byte is not covered
    CHECK(core::isOk(hmac.packetMac(kLabKey, packet, sizeof packet, mac)));
    STRCMP_EQUAL("d4a6351342d28fada47447aada4a8f6b", hex(mac, kMacSize).c_str());
    packet[8] ^= 0x01;  // every other byte is
    CHECK(core::isOk(hmac.packetMac(kLabKey, packet, sizeof packet, mac)));
    CHECK(std::string("d4a6351342d28fada47447aada4a8f6b") != hex(mac, kMacSize));
}

TEST(HmacSha256KnownAnswers, RefusesBadArgumentsAndUseBeforeInit) {
    std::uint8_t out[kHmacSha256Size];
    const std::uint8_t data[4] = {1, 2, 3, 4};
    HmacSha256 cold;
    CHECK(core::Status::kNotInitialized == cold.compute(kLabKey, kKeySize, data, sizeof data, out));
    CHECK(core::Status::kInvalidArgument == hmac.compute(nullptr, kKeySize, data, sizeof data, out));
    const std::uint8_t* noData = nullptr;
    const HmacSha256::Part* noParts = nullptr;
    CHECK(core::Status::kInvalidArgument == hmac.compute(kLabKey, kKeySize, noData, 4, out));
    CHECK(core::Status::kInvalidArgument == hmac.compute(kLabKey, kKeySize, data, sizeof data, nullptr));
    CHECK(core::Status::kInvalidArgument == hmac.compute(kLabKey, kKeySize, noParts, 2, out));
    std::uint8_t mac[kMacSize];
    CHECK(core::Status::kInvalidArgument == hmac.packetMac(kLabKey, data, sizeof data, mac));  // no checksum byte
}
