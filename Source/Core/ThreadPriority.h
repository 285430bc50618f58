#pragma once
// Real-time scheduling for the threads that keep time (device link, simulator, sound card).
// In Core so that Source/Audio needs nothing from Source/Link for it.
namespace armadillo::core {

/// Asks for SCHED_FIFO at `priority` (clamped to the system's range) for the calling thread.
/// False when refused (no permission) or priority <= 0; the thread then keeps running normally.
bool requestRealtimePriority(int priority) noexcept;

} // namespace armadillo::core
