// Ground-link flood benchmark (make bench; issue 14, item 3): a running rse-fsw
// on loopback is flooded with garbage UDP packets while a valid, signed NOOP
// goes every 100 ms, and its own counters are checked against what was sent.
//
//   1 rse-fsw starts (real time) with --udp on a free command port, telemetry to
//     this program, a fresh random key (--key-file, key id 7), a fresh anti-replay
//     store (--auth-store in the run's directory, --auth-store-create) and --quiet; extra
//     options with --fsw-arg (repeatable), another executable with --fsw.
//   2 after a first NOOP is acknowledged, a sender thread floods the command port
//     with garbage (sendmmsg, 64 a call, paced to --rate packets/s for --seconds):
//     random bytes of random length, CCSDS command headers with a bad checksum,
//     and well-formed packets naming an unknown key. Meanwhile the main thread
//     sends one valid NOOP every --period-ms and a receiver thread counts the
//     acknowledgements (and HK and EVENT packets) on the telemetry port.
//   3 after the flood: one more NOOP (it carries the kernel's drop count of the
//     last packets, SO_RXQ_OVFL), a REQUEST_HK, and a clean stop (SIGTERM); the
//     exit summary gives the command task's overruns and the link counters.
//
// Targets (PASS/FAIL printed, exit 3 on a miss: bench_targets.hpp): garbage
// rate >= 100 000 packets/s; >= 99 % of the valid commands sent during the flood
// acknowledged as accepted; 0 overruns of the command task caused by command
// ingest, i.e. runs over its budget with their stalls taken out (rse-fsw's
// "command runs" summary line: a gap over 300 us between two of ingest's looks
// at the clock, 32 packets apart, is time the thread did not run; runs over
// budget in wall time and in thread CPU time, which on this VM includes
// hypervisor pauses, and the frame overruns are printed as figures); every packet accounted for: read + kernel drops = sent, and
// rse-fsw's kernel-drop count = the kernel's own (/proc/net/udp).
//
// --keyed: the flood is well-formed NOOPs under the rover's own key id with a
// wrong MAC (each passes the cheap screen and costs a MAC); run by make bench
// through bench_ground_flood_keyed.sh at 40 000 packets/s (target >= 36 000
// achieved), the other targets as above.
//
// Usage: bench_ground_flood [--seconds S] [--rate PPS] [--period-ms MS] [--keyed]
//                           [--fsw PATH] [--fsw-arg ARG]... [--verbose]
#include <arpa/inet.h>
#include <fcntl.h>
#include <netinet/in.h>
#include <signal.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <chrono>
#include <cinttypes>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "fsw/cmdtlm/ccsds.hpp"
#include "fsw/cmdtlm/command_auth.hpp"
#include "fsw/cmdtlm/dictionary.hpp"
#include "unit_test/bench/bench_targets.hpp"
#include "ground/command_encoder.hpp"
#include "ground/telemetry_decoder.hpp"

namespace ground = rse::ground;

namespace {

using Clock = std::chrono::steady_clock;

double now() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

void sleepFor(double seconds) {
    if (seconds > 0) {
        std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
    }
}

sockaddr_in loopback(std::uint16_t port) {
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_port = htons(port);
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    return a;
}

int boundUdp(std::uint16_t port, std::uint16_t* boundPort) {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a = loopback(port);
    if (fd < 0 || bind(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) {
        std::perror("bench_ground_flood: udp socket");
        std::exit(2);
    }
    socklen_t size = sizeof a;
    getsockname(fd, reinterpret_cast<sockaddr*>(&a), &size);
    *boundPort = ntohs(a.sin_port);
    return fd;
}

// The kernel's drop count of the socket bound to 127.0.0.1:port (/proc/net/udp).
long procUdpDrops(std::uint16_t port) {
    std::ifstream in("/proc/net/udp");
    char want[32];
    std::snprintf(want, sizeof want, "0100007F:%04X", static_cast<unsigned>(port));
    std::string line;
    long drops = -1;
    while (std::getline(in, line)) {
        std::istringstream fields(line);
        std::string sl, local, field, last;
        fields >> sl >> local;
        while (fields >> field) {
            last = field;  // drops is the last field (the line ends in spaces)
        }
        if (local == want) {
            drops = std::strtol(last.c_str(), nullptr, 10);
        }
    }
    return drops;
}

// Packets the kernel dropped from its per-CPU input backlog (softnet_stat,
// column 2, summed): loopback traffic lost before it reached any socket.
long long softnetDrops() {
    std::ifstream in("/proc/net/softnet_stat");
    std::string line;
    long long total = 0;
    while (std::getline(in, line)) {
        unsigned long long processed = 0, dropped = 0;
        if (std::sscanf(line.c_str(), "%llx %llx", &processed, &dropped) == 2) {
            total += static_cast<long long>(dropped);
        }
    }
    return total;
}

std::string hex(const std::vector<std::uint8_t>& bytes) {
    std::string s;
    char b[3];
    for (const std::uint8_t v : bytes) {
        std::snprintf(b, sizeof b, "%02x", v);
        s += b;
    }
    return s;
}

constexpr double kGarbageRateTarget = 100000.0;  // issue 14's flood
// A forged-MAC packet costs a MAC besides the read (~1.5 us idle, up to ~2.4 us
// with builds running beside): ingest's 1.2 ms a frame drains 50 000 - 80 000 a
// second, so the keyed flood asks 40 000.
constexpr double kKeyedRateTarget = 36000.0;

struct Options {
    double seconds = 10.0;
    double rate = 110000.0;  // asked; the target is >= 100 000 achieved
    double periodMs = 100.0;
    std::string fsw;
    std::vector<std::string> fswArgs;
    bool verbose = false;
    bool keyed = false;  // the flood: packets under the rover's key id with a wrong MAC, not garbage
};

// What the telemetry receiver saw.
struct Telemetry {
    std::mutex mutex;
    std::vector<double> ackTime;             // per valid command index: when its acceptance came (0: none)
    std::vector<int> ackReason;              // -1 none yet
    std::uint32_t seqBase = 0;
    std::size_t acks = 0, rejectionAcks = 0, hk = 0, events = 0, other = 0, undecoded = 0;
    std::size_t hkDuringFlood = 0, eventsDuringFlood = 0;
    std::atomic<bool> flooding{false};
    ground::DecodedPacket lastHk;
    std::vector<std::string> notable;  // warning and worse events other than command rejections
    std::atomic<bool> stop{false};
};

void receiveTelemetry(int fd, Telemetry* t) {
    timeval tv{0, 100000};
    setsockopt(fd, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    std::uint8_t buf[2048];
    while (!t->stop.load()) {
        const ssize_t n = recv(fd, buf, sizeof buf, 0);
        if (n <= 0) {
            continue;
        }
        const double at = now();
        ground::DecodedPacket p = ground::decodeTelemetry(buf, static_cast<std::size_t>(n));
        std::lock_guard<std::mutex> lock(t->mutex);
        if (!p.ok) {
            ++t->undecoded;
            continue;
        }
        const std::string name = p.name();
        if (name == "CMD_ACK") {
            ++t->acks;
            const auto reason = static_cast<int>(p.value("reason").value_or(-1));
            const auto seq = static_cast<std::uint32_t>(p.value("auth_sequence").value_or(0));
            const auto key = static_cast<std::uint16_t>(p.value("key_id").value_or(0));
            const std::uint32_t index = seq - t->seqBase;
            if (key == 7 && index < t->ackReason.size() && t->ackReason[index] < 0) {
                t->ackReason[index] = reason;
                t->ackTime[index] = at;
            }
            if (reason != 0) {
                ++t->rejectionAcks;
            }
        } else if (name == "HK") {
            ++t->hk;
            t->hkDuringFlood += t->flooding.load() ? 1 : 0;
            t->lastHk = p;
        } else if (name == "EVENT") {
            ++t->events;
            t->eventsDuringFlood += t->flooding.load() ? 1 : 0;
            const auto id = static_cast<int>(p.value("event_id").value_or(0));
            const auto severity = static_cast<int>(p.value("severity").value_or(0));
            const bool rejection = (id >= 521 && id <= 534) || id == 503;
            if (severity >= 2 && !rejection && t->notable.size() < 40) {
                const ground::DecodedField* text = p.field("text");
                char line[160];
                std::snprintf(line, sizeof line, "EVT %d %s %s", id, ground::severityName(static_cast<unsigned>(severity)).c_str(),
                              text != nullptr ? text->text.c_str() : "");
                t->notable.push_back(line);
            }
        } else {
            ++t->other;
        }
    }
}

// Garbage the rover must refuse before any MAC: random bytes, command headers
// with a bad checksum, and well-formed packets of an unknown key.
std::vector<std::vector<std::uint8_t>> garbagePool(std::mt19937& rng, const ground::PacketAuth& auth) {
    std::vector<std::vector<std::uint8_t>> pool;
    std::uniform_int_distribution<int> byte(0, 255);
    for (int i = 0; i < 1024; ++i) {
        std::vector<std::uint8_t> p;
        switch (i % 3) {
            case 0: {  // random bytes, 1..200 of them
                p.resize(1 + static_cast<std::size_t>(rng() % 200));
                for (auto& b : p) {
                    b = static_cast<std::uint8_t>(byte(rng));
                }
                break;
            }
            case 1: {  // a NOOP with a broken checksum
                p = ground::encodeCommand("NOOP", {}, auth, 0xF0000000U + static_cast<std::uint32_t>(i));
                p[rse::cmdtlm::kChecksumOffset] ^= 0x5A;
                break;
            }
            default: {  // a well-formed NOOP signed with a key the rover does not have
                ground::PacketAuth stranger = auth;
                stranger.keyId = 0x7777;
                p = ground::encodeCommand("NOOP", {}, stranger, static_cast<std::uint32_t>(i));
                break;
            }
        }
        pool.push_back(std::move(p));
    }
    return pool;
}

// Well-formed NOOPs under the rover's own key id, signed with another key: each
// passes the cheap screen and costs rse-fsw a MAC before it is refused.
std::vector<std::vector<std::uint8_t>> forgedPool(std::mt19937& rng, const ground::PacketAuth& auth) {
    ground::PacketAuth forger = auth;
    for (auto& b : forger.key) {
        b = static_cast<std::uint8_t>(rng());
    }
    std::vector<std::vector<std::uint8_t>> pool;
    for (std::uint32_t i = 0; i < 1024; ++i) {
        pool.push_back(ground::encodeCommand("NOOP", {}, forger, static_cast<std::uint32_t>(rng())));
    }
    return pool;
}

struct FloodResult {
    std::uint64_t sent = 0;
    std::uint64_t refused = 0;  // sendmmsg errors (ENOBUFS ...): never reached the rover's socket
    double seconds = 0;
};

void flood(std::uint16_t port, const Options& o, const std::vector<std::vector<std::uint8_t>>& pool,
           FloodResult* result) {
    const int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const sockaddr_in to = loopback(port);
    if (fd < 0 || connect(fd, reinterpret_cast<const sockaddr*>(&to), sizeof to) != 0) {
        std::perror("bench_ground_flood: flood socket");
        return;
    }
    constexpr std::size_t kBatch = 64;
    mmsghdr msgs[kBatch];
    iovec iov[kBatch];
    std::size_t next = 0;
    const double start = now();
    const double end = start + o.seconds;
    for (;;) {
        const double t = now();
        if (t >= end) {
            break;
        }
        const auto due = static_cast<std::uint64_t>((t - start) * o.rate);
        if (result->sent + result->refused >= due) {
            sleepFor(0.0002);
            continue;
        }
        std::memset(msgs, 0, sizeof msgs);
        for (std::size_t i = 0; i < kBatch; ++i) {
            const auto& p = pool[next++ % pool.size()];
            iov[i].iov_base = const_cast<std::uint8_t*>(p.data());
            iov[i].iov_len = p.size();
            msgs[i].msg_hdr.msg_iov = &iov[i];
            msgs[i].msg_hdr.msg_iovlen = 1;
        }
        const int n = sendmmsg(fd, msgs, kBatch, 0);
        if (n > 0) {
            result->sent += static_cast<std::uint64_t>(n);
        } else {
            ++result->refused;  // this batch's first packet; the rest go again
            next -= kBatch - 1;
        }
    }
    result->seconds = now() - start;
    close(fd);
}

std::string selfDir() {
    char path[4096];
    const ssize_t n = readlink("/proc/self/exe", path, sizeof path - 1);
    if (n <= 0) {
        return ".";
    }
    path[n] = '\0';
    std::string s(path);
    return s.substr(0, s.find_last_of('/'));
}

// The exit summary's figures.
struct Summary {
    bool found = false;
    long frameOverruns = -1;
    long commandsRuns = -1, commandsOver = -1, commandsMeanUs = -1, commandsMaxUs = -1;
    bool commandsCpuFound = false;  // an rse-fsw that times the command task in CPU time
    long commandsCpuOver = -1;
    double commandsCpuMeanUs = -1, commandsCpuMaxUs = -1;
    bool linksFound = false;
    unsigned long read = 0, linkDropped = 0, kernelDropped = 0, limited = 0, acksSuppressed = 0;
    unsigned long accepted = 0, rejected = 0;
    bool stallsFound = false;  // an rse-fsw that tells stalled runs apart
    unsigned long stalledRuns = 0, overLessStalls = 0, longestLessStallsUs = 0;
};

Summary parseSummary(const std::string& path) {
    Summary s;
    std::ifstream in(path);
    std::string line;
    while (std::getline(in, line)) {
        long frames = 0, overruns = 0;
        if (std::sscanf(line.c_str(), "rse-fsw summary: %ld frames run, %ld overruns", &frames, &overruns) == 2) {
            s.found = true;
            s.frameOverruns = overruns;
        }
        // A task row: name, runs, over, last/mean/max us, host mean/max, then
        // cpu_over, cpu_mean, cpu_max for rows timed in CPU time ("-" otherwise).
        char name[64];
        long runs = 0, over = 0, last = 0, mean = 0, max = 0, cpuOver = 0;
        double hostMean = 0, hostMax = 0, cpuMean = 0, cpuMax = 0;
        const int fields = std::sscanf(line.c_str(), " %63s %ld %ld %ld %ld %ld %lf %lf %ld %lf %lf", name, &runs,
                                       &over, &last, &mean, &max, &hostMean, &hostMax, &cpuOver, &cpuMean, &cpuMax);
        if (fields >= 6 && std::strcmp(name, "commands") == 0) {
            s.commandsRuns = runs;
            s.commandsOver = over;
            s.commandsMeanUs = mean;
            s.commandsMaxUs = max;
            if (fields == 11) {
                s.commandsCpuFound = true;
                s.commandsCpuOver = cpuOver;
                s.commandsCpuMeanUs = cpuMean;
                s.commandsCpuMaxUs = cpuMax;
            }
        }
        if (std::sscanf(line.c_str(),
                        "  ground links: %lu packets read, %lu dropped by a link, %lu dropped by the OS (receive "
                        "buffer full); ingest at its limit in %lu frames, %lu rejection acks suppressed",
                        &s.read, &s.linkDropped, &s.kernelDropped, &s.limited, &s.acksSuppressed) == 5) {
            s.linksFound = true;
        }
        std::sscanf(line.c_str(), "  commands: %lu accepted, %lu rejected", &s.accepted, &s.rejected);
        long gapUs = 0;
        if (std::sscanf(line.c_str(),
                        "  command runs: %lu stalled (a gap over %ld us between ingest's clock reads), %lu over "
                        "budget less their stalls, longest less its stalls %lu us",
                        &s.stalledRuns, &gapUs, &s.overLessStalls, &s.longestLessStallsUs) == 4) {
            s.stallsFound = true;
        }
    }
    return s;
}


}  // namespace

int main(int argc, char** argv) {
    Options o;
    for (int i = 1; i < argc; ++i) {
        const std::string a = argv[i];
        const bool hasValue = i + 1 < argc;
        if (a == "--seconds" && hasValue) {
            o.seconds = std::atof(argv[++i]);
        } else if (a == "--rate" && hasValue) {
            o.rate = std::atof(argv[++i]);
        } else if (a == "--period-ms" && hasValue) {
            o.periodMs = std::atof(argv[++i]);
        } else if (a == "--fsw" && hasValue) {
            o.fsw = argv[++i];
        } else if (a == "--fsw-arg" && hasValue) {
            o.fswArgs.push_back(argv[++i]);
        } else if (a == "--verbose") {
            o.verbose = true;
        } else if (a == "--keyed") {
            o.keyed = true;
        } else {
            std::fprintf(stderr,
                         "usage: bench_ground_flood [--seconds S] [--rate PPS] [--period-ms MS] [--keyed] [--fsw PATH] "
                         "[--fsw-arg ARG]... [--verbose]\n");
            return 2;
        }
    }
    if (o.fsw.empty()) {
        const char* dir = std::getenv("RSE_BIN_DIR");
        o.fsw = (dir != nullptr ? std::string(dir) : selfDir()) + "/rse-fsw";
    }
    if (access(o.fsw.c_str(), X_OK) != 0) {
        std::fprintf(stderr, "bench_ground_flood: no rse-fsw at %s (make all, or --fsw PATH)\n", o.fsw.c_str());
        return 2;
    }

    // A fresh key for this run (key id 7), so nothing depends on the lab key or on
    // anti-replay state left by an earlier run; sequence numbers grow with the clock.
    std::random_device entropy;
    std::mt19937 rng(entropy());
    ground::PacketAuth auth;
    auth.keyId = 7;
    auth.key.resize(rse::cmdtlm::kKeySize);
    for (auto& b : auth.key) {
        b = static_cast<std::uint8_t>(rng());
    }
    char dirTemplate[] = "/tmp/bench_ground_flood.XXXXXX";
    if (mkdtemp(dirTemplate) == nullptr) {
        std::perror("bench_ground_flood: mkdtemp");
        return 2;
    }
    const std::string dir = dirTemplate;
    const std::string keyFile = dir + "/keys";
    const std::string logFile = dir + "/rse-fsw.out";
    {
        std::ofstream k(keyFile);
        k << "7:" << hex(auth.key) << "\n";
    }
    chmod(keyFile.c_str(), 0600);

    std::uint16_t tlmPort = 0;
    const int tlmFd = boundUdp(0, &tlmPort);
    const int big = 8 * 1024 * 1024;
    setsockopt(tlmFd, SOL_SOCKET, SO_RCVBUFFORCE, &big, sizeof big);
    std::uint16_t cmdPort = 0;
    close(boundUdp(0, &cmdPort));  // a free port for the rover

    const double fswSeconds = o.seconds + 20.0;  // a backstop: it is stopped with SIGTERM
    // A rover on its first boot: a fresh anti-replay store, provisioned.
    std::vector<std::string> args = {o.fsw,         "--udp",      "--cmd-port", std::to_string(cmdPort),
                                     "--tlm-port",  std::to_string(tlmPort),     "--key-file", keyFile,
                                     "--auth-store", dir + "/auth.dat",          "--auth-store-create",
                                     "--duration",  std::to_string(fswSeconds), "--quiet"};
    args.insert(args.end(), o.fswArgs.begin(), o.fswArgs.end());
    const pid_t fsw = fork();
    if (fsw == 0) {
        const int out = open(logFile.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
        dup2(out, 1);
        dup2(out, 2);
        std::vector<char*> argvFsw;
        for (auto& s : args) {
            argvFsw.push_back(s.data());
        }
        argvFsw.push_back(nullptr);
        execv(argvFsw[0], argvFsw.data());
        _exit(127);
    }

    const std::size_t commands = static_cast<std::size_t>(std::lround(o.seconds * 1000.0 / o.periodMs));
    Telemetry t;
    t.seqBase = static_cast<std::uint32_t>((static_cast<std::uint64_t>(std::time(nullptr)) - 1700000000ULL) * 20ULL);
    t.ackReason.assign(commands + 64, -1);
    t.ackTime.assign(commands + 64, 0.0);
    std::vector<double> sentAt(commands + 64, 0.0);
    std::thread receiver(receiveTelemetry, tlmFd, &t);

    const int cmdFd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    const sockaddr_in cmdTo = loopback(cmdPort);
    std::uint64_t otherSent = 0;  // valid and control packets, besides the garbage
    std::uint32_t index = 0;
    const auto sendCommand = [&](const char* name) -> std::uint32_t {
        const std::uint32_t i = index++;
        const std::vector<std::uint8_t> p = ground::encodeCommand(name, {}, auth, t.seqBase + i);
        if (i < sentAt.size()) {
            sentAt[i] = now();
        }
        if (sendto(cmdFd, p.data(), p.size(), 0, reinterpret_cast<const sockaddr*>(&cmdTo), sizeof cmdTo) ==
            static_cast<ssize_t>(p.size())) {
            ++otherSent;
        }
        return i;
    };
    const auto acked = [&](std::uint32_t i) {
        std::lock_guard<std::mutex> lock(t.mutex);
        return i < t.ackReason.size() && t.ackReason[i] >= 0;
    };

    // Nothing is sent before rse-fsw has bound its port (a datagram sent earlier
    // would be refused by the kernel and counted nowhere); then NOOPs until it answers.
    for (int w = 0; w < 500 && procUdpDrops(cmdPort) < 0; ++w) {
        sleepFor(0.01);
    }
    bool up = false;
    for (int attempt = 0; attempt < 50 && !up; ++attempt) {
        const std::uint32_t i = sendCommand("NOOP");
        for (int w = 0; w < 20 && !up; ++w) {
            sleepFor(0.01);
            up = acked(i);
        }
    }
    if (!up) {
        std::fprintf(stderr, "bench_ground_flood: rse-fsw did not acknowledge a NOOP (log: %s)\n", logFile.c_str());
        kill(fsw, SIGTERM);
        waitpid(fsw, nullptr, 0);
        t.stop = true;
        receiver.join();
        return 1;
    }
    const std::uint32_t firstFloodCommand = index;
    const long long softnetBefore = softnetDrops();

    // The flood, and a valid command every period meanwhile.
    const std::vector<std::vector<std::uint8_t>> pool = o.keyed ? forgedPool(rng, auth) : garbagePool(rng, auth);
    FloodResult floodResult;
    t.flooding = true;
    std::thread sender(flood, cmdPort, std::cref(o), std::cref(pool), &floodResult);
    const double start = now();
    for (std::size_t k = 0; k < commands; ++k) {
        sleepFor(start + static_cast<double>(k + 1) * o.periodMs / 1000.0 - now());
        (void)sendCommand("NOOP");
    }
    sender.join();
    t.flooding = false;
    const std::uint32_t lastFloodCommand = index;
    sleepFor(1.0);  // the last acknowledgements

    // After the flood: a NOOP carries the kernel's drop count of the flood's last
    // packets to rse-fsw; a REQUEST_HK brings its counters.
    const std::uint32_t flush = sendCommand("NOOP");
    for (int w = 0; w < 100 && !acked(flush); ++w) {
        sleepFor(0.01);
    }
    (void)sendCommand("REQUEST_HK");
    sleepFor(0.5);
    const long kernelDrops = procUdpDrops(cmdPort);
    const long long softnetAfter = softnetDrops();
    kill(fsw, SIGTERM);
    int status = 0;
    waitpid(fsw, &status, 0);
    t.stop = true;
    receiver.join();
    close(cmdFd);
    close(tlmFd);

    // Figures.
    std::size_t during = 0, accepted = 0;
    std::vector<double> latency;
    for (std::uint32_t i = firstFloodCommand; i < lastFloodCommand; ++i) {
        ++during;
        if (t.ackReason[i] == 0) {
            ++accepted;
            latency.push_back((t.ackTime[i] - sentAt[i]) * 1000.0);
        }
    }
    std::sort(latency.begin(), latency.end());
    const auto pct = [&](double q) {
        return latency.empty() ? 0.0 : latency[std::min(latency.size() - 1, static_cast<std::size_t>(q * latency.size()))];
    };
    const double garbageRate = floodResult.seconds > 0 ? static_cast<double>(floodResult.sent) / floodResult.seconds : 0;
    const double ackShare = during > 0 ? 100.0 * static_cast<double>(accepted) / static_cast<double>(during) : 0;
    const Summary s = parseSummary(logFile);
    const std::uint64_t sent = floodResult.sent + otherSent;
    const unsigned long read = s.read + s.linkDropped;

    std::printf("ground-link flood: rse-fsw on loopback, %.0f s of %s at %.0f packets/s asked, a valid NOOP "
                "every %.0f ms\n",
                o.seconds, o.keyed ? "NOOPs under its key id with a wrong MAC" : "garbage", o.rate, o.periodMs);
    std::printf("  garbage sent          %" PRIu64 " packets in %.2f s = %.0f packets/s (%" PRIu64
                " send calls refused)\n",
                floodResult.sent, floodResult.seconds, garbageRate, floodResult.refused);
    std::printf("  valid commands        %zu sent during the flood, %zu acknowledged accepted (%.2f %%)\n", during,
                accepted, ackShare);
    std::printf("  ack latency           p50 %.1f ms, p99 %.1f ms, max %.1f ms\n", pct(0.5), pct(0.99),
                latency.empty() ? 0.0 : latency.back());
    std::printf("  telemetry received    %zu CMD_ACK (%zu rejections), %zu HK (%zu during the flood), %zu EVENT "
                "(%zu during the flood), %zu other, %zu undecodable\n",
                t.acks, t.rejectionAcks, t.hk, t.hkDuringFlood, t.events, t.eventsDuringFlood, t.other,
                t.undecoded);
    if (!s.found) {
        std::printf("  rse-fsw summary       not found (exit status %d; log %s)\n", status, logFile.c_str());
    } else {
        std::printf("  rse-fsw               %ld frame overruns; command task: %ld runs, %ld over budget in wall "
                    "time, mean %ld us, max %ld us\n",
                    s.frameOverruns, s.commandsRuns, s.commandsOver, s.commandsMeanUs, s.commandsMaxUs);
        if (s.commandsCpuFound) {
            std::printf("  command task CPU      %ld over budget in thread CPU time, mean %.1f us, max %.1f us; %ld "
                        "over in wall time only (off the CPU)\n",
                        s.commandsCpuOver, s.commandsCpuMeanUs, s.commandsCpuMaxUs, s.commandsOver - s.commandsCpuOver);
        } else {
            std::printf("  command task CPU      not in its summary (an rse-fsw that does not time it in CPU time)\n");
        }
        if (s.stallsFound) {
            std::printf("  command task stalls   %lu runs stalled (off the CPU or the VM paused mid-ingest); %lu over "
                        "budget with their stalls taken out; longest so %lu us\n",
                        s.stalledRuns, s.overLessStalls, s.longestLessStallsUs);
        }
        std::printf("  rse-fsw commands      %lu accepted, %lu rejected\n", s.accepted, s.rejected);
    }
    if (s.linksFound) {
        std::printf("  rse-fsw ground links  %lu read, %lu dropped by the link, %lu dropped by the OS; ingest "
                    "limited in %lu frames; %lu rejection acks suppressed\n",
                    s.read, s.linkDropped, s.kernelDropped, s.limited, s.acksSuppressed);
    } else {
        std::printf("  rse-fsw ground links  no link counters in its summary (an rse-fsw without them)\n");
    }
    std::printf("  kernel                %ld drops on the command socket (/proc/net/udp), %lld input-backlog "
                "drops (softnet_stat)\n",
                kernelDrops, softnetAfter - softnetBefore);
    if (t.lastHk.ok) {
        const auto v = [&](const char* f) { return t.lastHk.value(f).value_or(-1); };
        std::printf("  last HK               link_rx_packets %.0f, link_rx_kernel_drops %.0f, cmd_ingest_limited "
                    "%.0f, cmd_acks_suppressed %.0f, frame_overruns %.0f\n",
                    v("link_rx_packets"), v("link_rx_kernel_drops"), v("cmd_ingest_limited"),
                    v("cmd_acks_suppressed"), v("frame_overruns"));
    }

    const double rateTarget = o.keyed ? kKeyedRateTarget : kGarbageRateTarget;
    const bool rateOk = garbageRate >= rateTarget;
    const bool ackOk = ackShare >= 99.0;
    // Overruns caused by command ingest: runs over budget even with the time the
    // task's thread did not run taken out (stalls: gaps between ingest's looks
    // at the clock that its work cannot take). Wall-time overruns also count
    // time rse-fsw was off the CPU mid-task, and on this VM a hypervisor pause
    // is charged as the thread's CPU time too: both are printed as figures.
    const bool overrunOk = s.stallsFound && s.overLessStalls == 0;
    const bool accountedOk = s.linksFound && read + s.kernelDropped == sent;
    const bool kernelOk = s.linksFound && kernelDrops >= 0 && static_cast<unsigned long>(kernelDrops) == s.kernelDropped;
    rse::bench::Targets targets;
    const auto verdict = [&targets](bool met) { return targets.check(met) ? "PASS" : "FAIL"; };
    std::printf("targets:\n");
    std::printf("  %s %s rate >= %.0f packets/s (%.0f)\n", verdict(rateOk), o.keyed ? "forged-MAC" : "garbage",
                rateTarget, garbageRate);
    std::printf("  %s valid commands acknowledged >= 99 %% (%.2f %%)\n", verdict(ackOk), ackShare);
    std::printf("  %s command task overruns caused by ingest (over budget less stalls) = 0 (%lu; %ld in wall "
                "time, %ld in CPU time, %ld frame overruns)\n",
                verdict(overrunOk), s.overLessStalls, s.commandsOver, s.commandsCpuOver, s.frameOverruns);
    std::printf("  %s read + kernel drops = sent (%lu + %lu = %lu of %" PRIu64 ")\n", verdict(accountedOk), read,
                s.kernelDropped, read + s.kernelDropped, sent);
    std::printf("  %s rse-fsw's kernel drops = the kernel's (%lu, %ld)\n", verdict(kernelOk), s.kernelDropped,
                kernelDrops);
    if (o.verbose) {
        std::printf("events of warning severity and worse, besides command rejections:\n");
        for (const std::string& e : t.notable) {
            std::printf("  %s\n", e.c_str());
        }
        std::printf("rse-fsw output (%s):\n", logFile.c_str());
        std::ifstream in(logFile);
        std::string line;
        while (std::getline(in, line)) {
            std::printf("  | %s\n", line.c_str());
        }
    }
    std::remove(keyFile.c_str());
    if (!o.verbose) {
        std::remove(logFile.c_str());
        rmdir(dir.c_str());
    }
    return targets.finish();
}
