// rse-demo --pace: the lockstep frames paced against the wall clock. Frame k
// of the run is due at wall time start + k x period / factor, the start being
// the first frame paced. Each frame is waited for, not each period: lateness
// in one frame does not shift the later ones, so a machine that falls behind
// (a planner's long frame, a factor beyond what it can run) runs the frames
// that are due at once until it has caught up; those are counted, with the
// most any of them was late. Factor 0: no pacing.
//
// Host side (sim_stub/): full language; rse-fsw never links it.
#pragma once

#include <chrono>
#include <cstdint>

namespace rse::sim {

class FramePacer {
public:
    using Clock = std::chrono::steady_clock;
    // The wall clock read and waited on: steady_clock and sleep_until, or a
    // test's own (so its schedule and lateness can be checked exactly).
    using NowFn = Clock::time_point (*)();
    using SleepUntilFn = void (*)(Clock::time_point);
    static Clock::time_point wallNow();
    static void wallSleepUntil(Clock::time_point due);

    explicit FramePacer(double factor, NowFn now = &wallNow, SleepUntilFn sleepUntil = &wallSleepUntil)
        : factor_(factor), now_(now), sleepUntil_(sleepUntil) {}
    // Before `frame` runs (the executive's next frame); called again for the
    // same frame, it does nothing.
    void beforeFrame(std::uint64_t frame);

    double factor() const { return factor_; }
    std::uint64_t framesPaced() const { return frames_; }
    std::uint64_t framesBehind() const { return behind_; }  // reached after their due time
    double behindMaxMs() const { return behindMaxMs_; }      // the most a frame was late

private:
    double factor_;
    NowFn now_;
    SleepUntilFn sleepUntil_;
    bool started_ = false;
    std::uint64_t firstFrame_ = 0;
    std::uint64_t lastFrame_ = 0;
    Clock::time_point start_{};
    std::uint64_t frames_ = 0;
    std::uint64_t behind_ = 0;
    double behindMaxMs_ = 0.0;
};

}  // namespace rse::sim
