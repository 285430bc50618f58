#pragma once
// One monotonic clock for producers and consumers that meet on a timeline across threads (the
// plugin's control ticks stamp motor levels with it, the device link sends them by it:
// Link/LevelSchedule.h). Real-time safe: a vDSO clock read, no lock, no allocation.
#include <chrono>

namespace armadillo::core {

/// Seconds on the steady clock (arbitrary epoch, never jumps).
inline double monotonicSeconds() noexcept
{
    return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

} // namespace armadillo::core
