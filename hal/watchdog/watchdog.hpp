// A hardware (or kernel) watchdog: if it is not fed within its timeout the
// computer restarts, as flight computers do when their software hangs.
// WatchdogDevice is the Linux one (/dev/watchdog, softdog in tests); tests of
// whoever feeds it use a fake.
#pragma once

#include "fsw/core/status.hpp"

namespace rse::hal {

class Watchdog {
public:
    virtual core::Status feed() = 0;

protected:
    ~Watchdog() = default;
};

}  // namespace rse::hal
