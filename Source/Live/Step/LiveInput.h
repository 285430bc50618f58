#pragma once
// The mailbox between live sources (simulator, OSC receiver, device link) and the control loop.
// Producers run on their own threads (one producer per mailbox at a time); the control loop
// (audio thread, or the idle clock) reads the latest orientation from a seqlock with a bounded
// read and drains IMU samples from an SPSC queue: no locks, no waiting.
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include <Eigen/Geometry>
#include <atomic>
#include <cstdint>

namespace armadillo::live {

/// One orientation from a live source, q = (w, x, y, z) device → earth (INTERFACES.md).
struct LiveOrientation {
    double t = 0.0;                  ///< s, source clock
    /// s on the monotonic clock (Core/Clock.h) when the mailbox took it: where the plugin places
    /// its control step in the host's block (BlockControl, issue 36).
    double arrival = 0.0;
    double w = 1.0, x = 0.0, y = 0.0, z = 0.0;
    std::uint64_t serial = 0;        ///< increments with every new value; 0 = nothing yet
};

/// A calibrated inertial sample as plain numbers (Eigen vectors are not trivially copyable).
struct LiveImu {
    double t = 0.0;                  ///< s
    double arrival = 0.0;            ///< s, monotonic clock, stamped by LiveInput::pushImu
    float g[3] {};                   ///< rad/s, device frame
    float a[3] {};                   ///< m/s², device frame
    float m[3] {};                   ///< any unit; NaN when absent
};

/// ImuSample ↔ LiveImu (the mailbox stores floats; the fusion works in doubles).
LiveImu toLiveImu(const core::ImuSample& s) noexcept;
core::ImuSample toImuSample(const LiveImu& s) noexcept;

class LiveInput {
public:
    /// One producer at a time (whichever source is selected).
    void storeOrientation(double t, const Eigen::Quaterniond& q) noexcept;
    /// Stamps the sample's arrival on the monotonic clock; false when the queue is full.
    bool pushImu(const LiveImu& sample) noexcept;
    /// The same from a calibrated sample (device link, OSC receiver); false when the queue is full.
    bool pushImu(const core::ImuSample& sample) noexcept { return pushImu(toLiveImu(sample)); }

    /// Not for the audio thread (may wait for a pre-empted writer).
    LiveOrientation latest() const noexcept { return orientation_.load(); }
    /// Real-time: the latest orientation, or `lastGood` when a write overlapped every attempt.
    LiveOrientation latest(const LiveOrientation& lastGood) const noexcept { return orientation_.load(lastGood); }
    /// Consumer (control loop) only.
    bool popImu(LiveImu& out) noexcept { return imu_.pop(out); }
    /// Consumer only: the oldest waiting sample, left in the queue.
    bool peekImu(LiveImu& out) const noexcept { return imu_.peek(out); }
    std::size_t imuWaiting() const noexcept { return imu_.size(); }

private:
    core::SeqLock<LiveOrientation> orientation_;
    core::SpscQueue<LiveImu, 512> imu_;
    std::atomic<std::uint64_t> serial_ {0};
};

} // namespace armadillo::live
