// What two ground-link design choices rest on (make bench; issue 14):
//   - a durable anti-replay store write (hal::FileRecordStore: write, fsync,
//     rename, fsync of the directory) costs milliseconds, more than the command
//     task's 2 ms budget, so rse-fsw writes it on a thread (docs/icd.md,
//     "Anti-replay");
//   - a command MAC (HmacSha256::packetMac of a small packet) costs about a
//     microsecond, so command ingest can check it on every packet before it
//     may queue (docs/icd.md, "Floods").
// Figures: the write's wall time (median, max) in a fresh directory under
// $TMPDIR (default /tmp), and the MAC's thread CPU time per packet.
// Targets (bench_targets.hpp): every record written reads back whole; a MAC
// costs <= 2 us of CPU (ingest's flood capacity assumes ~1.5 us with the read).
//
// Usage: bench_ground_link_costs [writes]   (default 50)
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "fsw/cmdtlm/command_auth.hpp"
#include "hal/nvm/file_record_store.hpp"
#include "unit_test/bench/bench_targets.hpp"

namespace {

double seconds(clockid_t clock) {
    timespec t{};
    clock_gettime(clock, &t);
    return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

constexpr double kMacTargetUs = 2.0;

}  // namespace

int main(int argc, char** argv) {
    const int writes = argc > 1 ? std::atoi(argv[1]) : 50;
    if (writes < 1 || writes > 100000) {
        std::fprintf(stderr, "usage: bench_ground_link_costs [writes 1..100000]\n");
        return 2;
    }
    const char* base = std::getenv("TMPDIR");
    std::string dir = std::string(base != nullptr && base[0] != '\0' ? base : "/tmp") + "/bench_link_costs.XXXXXX";
    if (mkdtemp(dir.data()) == nullptr) {
        std::perror("bench_ground_link_costs: mkdtemp");
        return 1;
    }
    const std::string path = dir + "/auth.dat";
    rse::hal::FileRecordStore store;
    if (!rse::core::isOk(store.open(path.c_str()))) {
        std::fprintf(stderr, "bench_ground_link_costs: cannot use %s\n", path.c_str());
        return 1;
    }
    std::vector<double> ms;
    int readBack = 0;
    for (int i = 0; i < writes; ++i) {
        std::uint8_t record[60];
        for (std::size_t k = 0; k < sizeof record; ++k) {
            record[k] = static_cast<std::uint8_t>(i * 31 + static_cast<int>(k));
        }
        const double t0 = seconds(CLOCK_MONOTONIC);
        const rse::core::Status st = store.write(record, sizeof record);
        ms.push_back((seconds(CLOCK_MONOTONIC) - t0) * 1e3);
        std::uint8_t back[64];
        std::size_t length = 0;
        readBack += rse::core::isOk(st) && rse::core::isOk(store.read(back, sizeof back, &length)) &&
                            length == sizeof record && std::memcmp(back, record, sizeof record) == 0
                        ? 1
                        : 0;
    }
    (void)unlink(path.c_str());
    (void)rmdir(dir.c_str());
    std::sort(ms.begin(), ms.end());

    rse::cmdtlm::HmacSha256 hmac;
    if (!rse::core::isOk(hmac.init())) {
        std::fprintf(stderr, "bench_ground_link_costs: no HMAC engine\n");
        return 1;
    }
    std::uint8_t key[rse::cmdtlm::kKeySize];
    for (std::size_t k = 0; k < sizeof key; ++k) {
        key[k] = static_cast<std::uint8_t>(0xA5 ^ k);
    }
    std::uint8_t packet[40] = {};  // a NOOP-sized packet before its MAC
    std::uint8_t mac[rse::cmdtlm::kMacSize];
    const int macs = 200000;
    unsigned sink = 0;
    const double c0 = seconds(CLOCK_THREAD_CPUTIME_ID);
    for (int i = 0; i < macs; ++i) {
        packet[12] = static_cast<std::uint8_t>(i);
        (void)hmac.packetMac(key, packet, sizeof packet, mac);
        sink += mac[0];
    }
    const double macUs = (seconds(CLOCK_THREAD_CPUTIME_ID) - c0) * 1e6 / macs;

    std::printf("ground-link costs (%s)\n", dir.c_str());
    std::printf("  anti-replay store write (write, fsync, rename, fsync dir): %d writes, median %.2f ms, max %.2f ms "
                "(wall)\n",
                writes, ms[ms.size() / 2], ms.back());
    std::printf("  command MAC (HMAC-SHA-256 of a %zu-byte packet): %.3f us of thread CPU each (%d MACs; %u)\n",
                sizeof packet, macUs, macs, sink & 1U);
    rse::bench::Targets targets;
    std::printf("  %s every record written reads back whole (%d of %d)\n",
                targets.check(readBack == writes) ? "PASS" : "FAIL", readBack, writes);
    std::printf("  %s a MAC costs <= %.1f us of CPU (%.3f us)\n", targets.check(macUs <= kMacTargetUs) ? "PASS" : "FAIL",
                kMacTargetUs, macUs);
    return targets.finish();
}
