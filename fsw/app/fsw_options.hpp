// rse-fsw's command line (docs/operations.md, "Command lines"): the options, parsed
// with getopt_long before anything is initialised, and the usage text.
//
// Parsing writes nothing and allocates nothing: a bad command line comes back as
// FswCommandLine::kBad with one line saying what is wrong (the option and its
// value) in the caller's buffer; main prints it, then "see 'rse-fsw --help'", and
// exits 2. --help (-h) comes back as kHelp: main prints the usage on stdout and
// exits 0.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>

#include "fsw/cmdtlm/key_loader.hpp"
#include "hal/link/udp_packet_link.hpp"

namespace rse::app {

struct FswOptions {
    bool lockstep = false;
    bool quiet = false;
    bool realtimePosture = true;
    double durationSec = 0.0;  // 0: until a signal
    const char* canInterface = nullptr;
    bool udp = false;
    const char* udpBind = "127.0.0.1";
    std::uint16_t commandPort = hal::kDefaultCommandPort;
    const char* telemetryHost = "127.0.0.1";
    std::uint16_t telemetryPort = hal::kDefaultTelemetryPort;
    const char* keyFile = nullptr;
    cmdtlm::KeyLoadOptions keyOptions;  // --lab-key, --allow-weak-key, --allow-readable-key
    bool authRequired = true;
    const char* authStore = "rse-fsw-auth.dat";
    bool authStoreCreate = false;
    bool authStoreSync = false;
    const char* watchdogDevice = nullptr;
    int watchdogTimeoutS = 30;
    std::uint32_t timeScale = 0;  // 0: not given (CLOCK_MONOTONIC as it is)
    long spinMarginUs = -1;       // -1: not given (sleep only)
};

enum class FswCommandLine : std::uint8_t {
    kRun,   // options parsed and consistent
    kHelp,  // --help or -h
    kBad,   // why says what is wrong
};

// Parses argv[1..argc-1] into *options (string values point into argv). getopt_long
// may reorder argv. why receives one line without the program name or a newline.
FswCommandLine parseFswOptions(int argc, char** argv, FswOptions* options, char* why, std::size_t whySize);

// The usage text: every option, its argument and its default.
void printFswUsage(std::FILE* out);

}  // namespace rse::app
