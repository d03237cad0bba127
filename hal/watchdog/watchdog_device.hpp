// The Linux watchdog device (Documentation/watchdog/watchdog-api.rst): open
// arms it, every write feeds it, and writing the magic character 'V' just
// before close disarms it (unless the driver was loaded with nowayout), so a
// clean stop of rse-fsw does not restart the computer but a hang or a crash
// does. The timeout is asked for with WDIOC_SETTIMEOUT; a device that refuses
// keeps its own (the answer is evented). A plain file also works (tests): the
// ioctls fail and are reported, the feeds are written bytes.
#pragma once

#include <cstdint>

#include "fsw/core/event_log.hpp"
#include "hal/watchdog/watchdog.hpp"

namespace rse::hal {

class WatchdogDevice final : public Watchdog {
public:
    explicit WatchdogDevice(core::EventLog& events) : events_(events) {}
    ~WatchdogDevice() { disarm(); }
    WatchdogDevice(const WatchdogDevice&) = delete;
    WatchdogDevice& operator=(const WatchdogDevice&) = delete;

    // Opens (arms) path; asks for timeoutS seconds (0: keep the device's).
    core::Status open(const char* path, int timeoutS);
    core::Status feed() override;
    // Magic close: 'V', then close. Safe to call when not open.
    void disarm();

    bool isOpen() const { return fd_ >= 0; }
    int timeoutS() const { return timeoutS_; }  // what the device reports (-1: unknown)
    std::uint32_t feeds() const { return feeds_; }
    std::uint32_t feedFailures() const { return feedFailures_; }
    int lastErrno() const { return lastErrno_; }

private:
    core::EventLog& events_;
    int fd_ = -1;
    int timeoutS_ = -1;
    std::uint32_t feeds_ = 0;
    std::uint32_t feedFailures_ = 0;
    int lastErrno_ = 0;
};

}  // namespace rse::hal
