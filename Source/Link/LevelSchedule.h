#pragma once
// The last stage before the wire, in real time (issue 13): motor levels carry the time of the
// control tick that computed them, on the link's clock, and the link sends each when its time
// comes. A host that computes a whole audio block's ticks back to back (a plugin at 4096 samples
// runs 17 ticks in one go) therefore still reaches the motors tick by tick, and a host that stops
// computing (stalled, transport stopped, huge blocks late, plugin bypassed or removed) reaches
// them as all-off once its last level is `staleAfter` old: the safety stage budgets every level
// for at most max(25 ms, its tick) on the motor (docs/TACTILE.md), and this is where that holds.
//
// Threads: one producer (the control step: the audio thread in the plugin) calls push(); one
// consumer (the link thread) calls due() for every motor packet it writes. Lock- and
// allocation-free; a full queue drops the newest level and counts it (the consumer then goes
// all-off when what it has is stale, never holds an old level longer).
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include <algorithm>
#include <atomic>
#include <cstdint>

namespace armadillo::link {

class LevelSchedule {
public:
    struct Params {
        double staleAfter = 0.025;   ///< s: a level older than this (and not replaced) is sent as all-off
        double packetInterval = 0.005;   ///< s: the longest interval between motor packets (57 600 baud: 3.3 ms + jitter)
    };
    /// How long the level stamped `previous` can be on the motor once the next one is stamped
    /// `next`: until `next`, but never past the stale limit and the packet that carries it out. A
    /// producer whose ticks stop (a stalled host) must give its safety stage this, not its tick,
    /// as the previous output's time on (SafetyStage::process's dt): the stage then charges what
    /// the motor really got.
    double onTime(double previous, double next) const noexcept
    {
        return std::min(next - previous, params_.staleAfter + 2.0 * params_.packetInterval);
    }
    LevelSchedule() = default;
    explicit LevelSchedule(const Params& p) : params_(p) {}

    /// Producer: the levels of the control tick at time `t` (s, the link's clock). False when full.
    bool push(double t, const core::MotorLevels& levels) noexcept;
    /// Producer: motors off from now on (disconnect, error, shutdown) until the next push().
    void allOff() noexcept { offRequested_.store(true, std::memory_order_release); }

    /// Consumer: the levels to send at `now`: per motor, the lower of the newest level whose time
    /// has come and the one sent before (so a rise waits one packet and a fall never waits, and
    /// quantising the tick timeline to packets never lengthens a run); all-off if the newest level
    /// is older than staleAfter, or after allOff().
    core::MotorLevels due(double now) noexcept;

    std::uint64_t dropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
    /// Times the consumer switched to all-off because its newest level went stale.
    std::uint64_t staleOffs() const noexcept { return staleOffs_.load(std::memory_order_relaxed); }
    const Params& params() const noexcept { return params_; }

private:
    struct Stamped {
        double t = 0.0;
        core::MotorLevels levels {};
        bool off = false;   ///< an allOff() marker: zeros from t on
    };
    Params params_ {};
    core::SpscQueue<Stamped, 1024> queue_;
    std::atomic<bool> offRequested_ {false};
    std::atomic<std::uint64_t> dropped_ {0};
    std::atomic<std::uint64_t> staleOffs_ {0};
    // Consumer side.
    Stamped current_ {-1e300, {}, true};
    Stamped pending_ {};
    bool havePending_ = false;
    bool stale_ = true;
    core::MotorLevels dueBefore_ {}; ///< what was due at the previous call
};

} // namespace armadillo::link
