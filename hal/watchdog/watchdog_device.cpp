#include "hal/watchdog/watchdog_device.hpp"

#include <cerrno>
#include <cstring>
#include <fcntl.h>
#include <linux/watchdog.h>
#include <sys/ioctl.h>
#include <unistd.h>

#include "hal/watchdog/watchdog_events.hpp"

namespace rse::hal {

core::Status WatchdogDevice::open(const char* path, int timeoutS) {
    if (path == nullptr || fd_ >= 0) {
        return core::Status::kInvalidArgument;
    }
    fd_ = ::open(path, O_WRONLY | O_CLOEXEC);
    if (fd_ < 0) {
        lastErrno_ = errno;
        events_.report(events::kWatchdogOpenFailed, core::Severity::kCritical, "watchdog: cannot open %s: %s", path,
                       std::strerror(lastErrno_));
        return core::Status::kUnavailable;
    }
    int timeout = timeoutS;
    if (timeoutS > 0 && ::ioctl(fd_, WDIOC_SETTIMEOUT, &timeout) != 0) {
        lastErrno_ = errno;
        events_.report(events::kWatchdogOpenFailed, core::Severity::kWarning,
                       "watchdog: %s refused a %d s timeout (%s): its own applies", path, timeoutS,
                       std::strerror(lastErrno_));
    }
    int actual = -1;
    timeoutS_ = ::ioctl(fd_, WDIOC_GETTIMEOUT, &actual) == 0 ? actual : -1;
    events_.report(events::kWatchdogOpened, core::Severity::kInfo, "watchdog: %s armed, timeout %d s", path,
                   timeoutS_);
    return core::Status::kOk;
}

core::Status WatchdogDevice::feed() {
    if (fd_ < 0) {
        return core::Status::kUnavailable;
    }
    const char keepAlive = '\0';
    if (::write(fd_, &keepAlive, 1) != 1) {
        lastErrno_ = errno;
        ++feedFailures_;
        if (core::isReportableOccurrence(feedFailures_)) {
            events_.report(events::kWatchdogFeedFailed, core::Severity::kError, "watchdog: feed failed: %s (%u so far)",
                           std::strerror(lastErrno_), static_cast<unsigned>(feedFailures_));
        }
        return core::Status::kUnavailable;
    }
    ++feeds_;
    return core::Status::kOk;
}

void WatchdogDevice::disarm() {
    if (fd_ < 0) {
        return;
    }
    const char magic = 'V';
    (void)::write(fd_, &magic, 1);
    (void)::close(fd_);
    fd_ = -1;
    events_.report(events::kWatchdogDisarmed, core::Severity::kInfo, "watchdog: disarmed (clean stop)");
}

}  // namespace rse::hal
