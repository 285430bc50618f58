#pragma once
// Who runs the control step: the audio thread (processBlock) or, while no audio callbacks come,
// the idle control clock. Whoever runs it holds this try-only token; nobody waits for it on a
// real-time path. Only prepareToPlay (message thread, audio stopped) waits, for < 1 ms.
#include <atomic>
#include <thread>

namespace armadillo::live {

class ControlToken {
public:
    /// Real-time: never waits.
    bool tryTake() noexcept
    {
        bool expected = false;
        return held_.compare_exchange_strong(expected, true, std::memory_order_acquire);
    }
    void release() noexcept { held_.store(false, std::memory_order_release); }
    /// Not real-time (prepareToPlay): yields until the current holder (the clock, < 1 ms) is done.
    void take() noexcept
    {
        while (! tryTake()) std::this_thread::yield();
    }

private:
    std::atomic<bool> held_ {false};
};

} // namespace armadillo::live
