#pragma once
// Plays short tactile sequences (stimuli, braille cells, feedback sensations) on the device for
// the guided procedures (touch-profile, adaptive training), through the normal TactileEngine —
// drive shaping, the reader's touch profile, the SafetyStage — exactly like a scene's intents.
// The front end's thread queues a sequence of segments; the device link's control thread (one
// onPacket() per sensor packet) plays it and reports when it is over. Real-time on the control
// thread: segments cross in an SPSC queue, progress in atomics; onPacket() allocates, locks and
// throws nothing (tests_access proves it with the RealtimeGuard).
#include "Access/ArmGestures.h"
#include "Core/SpscQueue.h"
#include "Tactile/TactileEngine.h"
#include <array>
#include <atomic>
#include <limits>
#include <vector>

namespace armadillo::access {

struct TactileSegment {
    double at = 0.0;          ///< s after the sequence starts
    double duration = 0.0;    ///< s
    std::uint16_t motors = 0; ///< bit i = motor index i (right-arm layout)
    float level = 0.0f;
    bool soft = false;        ///< no jump-start spike (thresholds: the level asked is the level felt)
    bool end = false;         ///< the sequence's end marker (at = its length)
};

class TactilePlayer {
public:
    /// packetPeriod > 0: each packet counts that many seconds (unpaced), else the link's clock.
    TactilePlayer(const tactile::TactileConfig& config, double packetPeriod);

    /// Main thread: queues a sequence (an end marker is added at its length + `after` s of
    /// stillness). Returns its number (1, 2, …).
    int play(std::vector<TactileSegment> segments, double after = 0.0);
    /// Main thread: sequences played to their end.
    int completed() const noexcept { return completed_.load(std::memory_order_acquire); }
    /// Main thread: highest level each motor got (after safety) during the last completed sequence.
    int maxLevel(int motor) const noexcept { return maxSent_[static_cast<std::size_t>(motor)].load(); }
    double clock() const noexcept { return clock_.load(); }   ///< s of stimulus clock
    std::uint64_t packets() const noexcept { return packets_.load(); }

    /// Control thread: one call per sensor packet (t = the link's clock, s); the levels of the
    /// answering motor packet. `rollRate` (rad/s, the gyro's x: the forearm axis), when given,
    /// feeds the arm gestures (ArmGestures.h: a twist and back = repeat, two = skip).
    core::MotorLevels onPacket(double t, double rollRate = std::numeric_limits<double>::quiet_NaN()) noexcept;
    /// Main thread (any time): the reader's touch profile as a gain per motor index (the player's
    /// right-arm layout: index i = motor m(i+1), as link::touchProfileGains gives them), applied
    /// to every segment's level before the engine's drive shaping and safety stage, as
    /// TactileConfig::motorGain is in a scene (result clamped to 15; non-finite or negative = 1).
    /// All 1 (the default) = none. The sensitivity test's player never gets one (raw thresholds).
    void setMotorGains(const std::array<float, core::kMaxMotors>& gains) noexcept;
    /// Main thread: twists seen so far (the app's adaptive training takes them as repeat / skip).
    int repeats() const noexcept { return repeats_.load(std::memory_order_relaxed); }
    int skips() const noexcept { return skips_.load(std::memory_order_relaxed); }

private:
    tactile::TactileEngine engine_;
    const double packetPeriod_;
    core::SpscQueue<TactileSegment, 512> queue_;
    std::atomic<int> queued_ {0}, completed_ {0};
    std::array<std::atomic<int>, core::kMaxMotors> maxSent_ {};
    std::atomic<double> clock_ {0.0};
    std::atomic<std::uint64_t> packets_ {0};
    std::atomic<int> repeats_ {0}, skips_ {0};
    std::array<std::atomic<float>, core::kMaxMotors> gains_ {};
    TwistDetector twist_;   // link thread only
    // Link thread only.
    std::array<TactileSegment, 128> active_ {};
    int activeCount_ = 0;
    bool running_ = false;
    double anchor_ = 0.0, endAt_ = -1.0, lastT_ = -1.0;
    std::array<int, core::kMaxMotors> max_ {};
};

} // namespace armadillo::access
