#include "sim_stub/lockstep/frame_pacer.hpp"

#include <algorithm>
#include <thread>

#include "fsw/app/fsw_app.hpp"

namespace rse::sim {

FramePacer::Clock::time_point FramePacer::wallNow() { return Clock::now(); }

void FramePacer::wallSleepUntil(Clock::time_point due) { std::this_thread::sleep_until(due); }

void FramePacer::beforeFrame(std::uint64_t frame) {
    if (!(factor_ > 0.0) || (started_ && frame == lastFrame_)) {
        return;
    }
    const Clock::time_point now = now_();
    if (!started_) {
        started_ = true;
        firstFrame_ = frame;
        start_ = now;
    }
    lastFrame_ = frame;
    ++frames_;
    const double periodS = static_cast<double>(app::kMinorFramePeriod) * 1e-9;
    const double dueS = static_cast<double>(frame - firstFrame_) * periodS / factor_;
    const Clock::time_point due =
        start_ + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(dueS));
    if (now < due) {
        sleepUntil_(due);
    } else if (now > due) {
        ++behind_;
        behindMaxMs_ = std::max(behindMaxMs_, std::chrono::duration<double, std::milli>(now - due).count());
    }
}

}  // namespace rse::sim
