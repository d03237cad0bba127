// rse-isotp: our ISO-TP (hal/can/isotp) on a SocketCAN interface, for ground
// use and for interoperability checks against the kernel's can-isotp
// (can-utils isotpsend / isotprecv). Payloads are written and read in the
// can-utils text form: hex bytes separated by spaces, one message per line.
//
//   rse-isotp --can IFACE --tx ID --rx ID [--pad] [--timeout S] send   < hex line
//   rse-isotp --can IFACE --tx ID --rx ID [--pad] [--timeout S] recv   > hex line
//
// Exit: 0 ok, 1 failed or timed out, 2 bad usage. (Commanding the rover over
// ISO-TP is rse-ground --can's job; this tool moves raw messages.)
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "fsw/core/clock.hpp"
#include "fsw/core/event_log.hpp"
#include "hal/can/isotp.hpp"
#include "hal/can/socketcan_bus.hpp"

namespace {

using rse::core::TimeNs;

int usage(const char* why) {
    std::fprintf(stderr,
                 "rse-isotp: %s\n"
                 "usage: rse-isotp --can IFACE --tx ID --rx ID [--pad] [--timeout S] send|recv\n",
                 why);
    return 2;
}

bool parseId(const char* text, std::uint32_t* out) {
    char* end = nullptr;
    const unsigned long v = std::strtoul(text, &end, 16);
    if (end == text || *end != '\0' || v > rse::hal::kCanMaxStandardId) {
        return false;
    }
    *out = static_cast<std::uint32_t>(v);
    return true;
}

bool readHexLine(std::vector<std::uint8_t>* out) {
    std::string line;
    if (!std::getline(std::cin, line)) {
        return false;
    }
    std::istringstream in(line);
    std::string byte;
    while (in >> byte) {
        char* end = nullptr;
        const unsigned long v = std::strtoul(byte.c_str(), &end, 16);
        if (*end != '\0' || v > 0xFF) {
            std::fprintf(stderr, "rse-isotp: '%s' is not a hex byte\n", byte.c_str());
            return false;
        }
        out->push_back(static_cast<std::uint8_t>(v));
    }
    return true;
}

class Link {
public:
    Link(rse::hal::SocketCanBus& bus, const rse::hal::IsoTpConfig& config)
        : events_(clock_), bus_(bus), channel_(bus, clock_, events_, config), rxId_(config.rxId) {}

    // Reads frames for our id, advances the channel; one call per millisecond.
    void service() {
        rse::hal::CanFrame f;
        for (int i = 0; i < 256 && rse::core::isOk(bus_.receive(&f)); ++i) {
            if (f.id == rxId_ && !f.extended()) {
                channel_.onFrame(f);
            }
        }
        channel_.poll();
    }
    template <typename Done>
    bool runUntil(Done done, double seconds) {
        const TimeNs end = clock_.now() + static_cast<TimeNs>(seconds * 1e9);
        while (clock_.now() < end) {
            service();
            if (done()) {
                return true;
            }
            clock_.sleepUntil(clock_.now() + rse::core::kNsPerMs);
        }
        return false;
    }
    rse::hal::IsoTpChannel& channel() { return channel_; }
    void printEvents() {
        rse::core::Event e;
        while (rse::core::isOk(events_.pop(&e))) {
            std::fprintf(stderr, "rse-isotp: event %u %s\n", static_cast<unsigned>(e.id), e.text);
        }
    }

private:
    rse::core::MonotonicClock clock_;
    rse::core::EventLog events_;
    rse::hal::SocketCanBus& bus_;
    rse::hal::IsoTpChannel channel_;
    std::uint32_t rxId_;
};

bool sendAll(Link& link, const std::vector<std::uint8_t>& data, double timeout) {
    if (!rse::core::isOk(link.channel().send(data.data(), data.size()))) {
        std::fprintf(stderr, "rse-isotp: send of %zu bytes refused\n", data.size());
        return false;
    }
    const bool done = link.runUntil([&] { return !link.channel().txBusy(); }, timeout);
    if (!done || link.channel().txResult() != rse::hal::IsoTpTxResult::kDone) {
        std::fprintf(stderr, "rse-isotp: transmission did not complete\n");
        return false;
    }
    return true;
}

bool receiveOne(Link& link, std::vector<std::uint8_t>* out, double timeout) {
    out->assign(rse::hal::kIsoTpMaxMessage, 0);
    std::size_t length = 0;
    const bool got = link.runUntil(
        [&] { return rse::core::isOk(link.channel().receive(out->data(), out->size(), &length)); }, timeout);
    out->resize(got ? length : 0);
    if (!got) {
        std::fprintf(stderr, "rse-isotp: no message within %.1f s\n", timeout);
    }
    return got;
}

}  // namespace

int main(int argc, char** argv) {
    const char* iface = nullptr;
    rse::hal::IsoTpConfig config;
    bool haveTx = false, haveRx = false;
    double timeout = 10.0;
    std::vector<std::string> rest;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool value = i + 1 < argc;
        if (a == "--can" && value) {
            iface = argv[++i];
        } else if (a == "--tx" && value) {
            haveTx = parseId(argv[++i], &config.txId);
        } else if (a == "--rx" && value) {
            haveRx = parseId(argv[++i], &config.rxId);
        } else if (a == "--pad") {
            config.padFrames = true;
        } else if (a == "--timeout" && value) {
            timeout = std::atof(argv[++i]);
        } else {
            rest.push_back(a);
        }
    }
    if (iface == nullptr || !haveTx || !haveRx || rest.empty() || !(timeout > 0.0)) {
        return usage("--can, --tx and --rx (hex 11-bit ids), a positive --timeout and a command are required");
    }
    rse::hal::SocketCanBus bus;
    if (!rse::core::isOk(bus.open(iface))) {
        std::fprintf(stderr, "rse-isotp: cannot open '%s': %s\n", iface, std::strerror(bus.lastErrno()));
        return 1;
    }
    Link link(bus, config);
    bool ok = false;
    if (rest[0] == "send") {
        std::vector<std::uint8_t> data;
        ok = readHexLine(&data) && !data.empty() && sendAll(link, data, timeout);
    } else if (rest[0] == "recv") {
        std::vector<std::uint8_t> data;
        ok = receiveOne(link, &data, timeout);
        for (std::size_t i = 0; ok && i < data.size(); ++i) {
            std::printf("%02X%s", data[i], i + 1 < data.size() ? " " : "\n");
        }
    } else {
        return usage("unknown command");
    }
    link.printEvents();
    return ok ? 0 : 1;
}
