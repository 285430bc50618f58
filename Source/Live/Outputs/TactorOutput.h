#pragma once
// The live tactor output (issue 33, docs/TACTORS.md): the motor levels of every control step,
// rendered by the tactor renderer (Source/Tactors) onto the channels of an ALSA PCM or the output
// ports of a JACK client (`tactor_1`…), beside (not instead of) a serial device.
//
// Threads: push() is called by the control thread after each step (real-time: it writes one
// record into a single-producer/single-consumer queue). The output's own audio thread (the sound
// card's, or JACK's process thread) drains the queue at the head of every period, hands each
// record to the renderer with its control-step dt, and renders the period; so a level change
// reaches the channel at the next period's first sample. When no record arrived for
// kStaleSeconds (a stalled source) the channels go silent until one does. Nothing in the period
// allocates, locks or throws (tested with the RealtimeGuard).
#include "Core/SpscQueue.h"
#include "Core/Types.h"
#include "Live/Outputs/TactorOutputConfig.h"
#include "Tactors/TactorRenderer.h"
#include <array>
#include <atomic>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armadillo::audio {
class SoundCard;
class JackOutput;
}

namespace armadillo::live {

/// One latency record: a control step's levels from push() to the first sample that carries them.
struct TactorLatency {
    double toRender = 0.0;   ///< s from push() to the start of the period that renders it
    double toOutput = 0.0;   ///< s from push() to that period's first sample leaving the device (+ the device's queue)
};

class TactorOutput {
public:
    static constexpr double kStaleSeconds = 0.1;

    /// Opens the device and prepares the renderer; nothing runs yet. IoError for a device that is
    /// not there, has fewer channels than the map, or a JACK server that is not running;
    /// InputError for settings or gains out of range.
    explicit TactorOutput(const TactorOutputConfig& config);
    ~TactorOutput();
    TactorOutput(const TactorOutput&) = delete;
    TactorOutput& operator=(const TactorOutput&) = delete;

    /// Starts the audio thread (JACK: activates the client and makes the connections; IoError
    /// when they cannot be made — the client is stopped again then).
    void start();
    /// Control thread: the levels of the step at source time `t` (s). Real-time.
    void push(double t, const core::MotorLevels& levels) noexcept;
    /// Every channel silent, the device stopped. Idempotent.
    void stop();
    /// The scene's sound for a voice coil that is handed it (TactorParams::voiceCoilSound,
    /// `--tactor-sound`): the session's audio thread pushes each block it renders (mixed to mono)
    /// into a lock-free ring, and each period takes as many samples as it renders. The sound's
    /// rate must be the output's. When the output runs ahead (nothing waiting) the carrier falls
    /// back after its envelope; when the sound runs ahead by more than kSoundBacklog samples the
    /// oldest are dropped, so the two audio clocks' drift never builds up latency. Real-time.
    void pushSound(const float* left, const float* right, int n) noexcept;
    bool wantsSound() const noexcept { return config_.params.voiceCoilSound; }
    static constexpr std::size_t kSoundBacklog = 4096;
    /// Samples of the sound waiting for the output (tests, the benchmark).
    std::size_t soundWaiting() const noexcept { return sound_.size(); }

    /// "jack: armadillo:tactor_1…tactor_9, 48000 Hz, 256 frames" or "ALSA 'hw:1': 9 channels, …".
    std::string describe() const;
    int channels() const noexcept { return renderer_.channels(); }
    /// Which motor each channel plays.
    const tactors::ChannelMap& map() const noexcept { return renderer_.map(); }
    double sampleRate() const noexcept { return sampleRate_; }
    int periodFrames() const noexcept { return periodFrames_; }
    std::uint64_t framesRendered() const noexcept { return frames_.load(std::memory_order_relaxed); }
    std::uint64_t recordsDropped() const noexcept { return dropped_.load(std::memory_order_relaxed); }
    /// The output failed on its own (JACK server gone, card unplugged).
    bool failed() const noexcept;
    /// The guard's limited count (0 while it only sees an engine's levels).
    std::uint64_t limited() const noexcept { return limited_.load(std::memory_order_relaxed); }
    /// Latency records of the steps rendered so far (one consumer thread; bounded queue: the oldest
    /// are kept, later ones dropped when nobody reads).
    bool popLatency(TactorLatency& out) noexcept { return latency_.pop(out); }

    /// The period as the audio thread runs it (public for tests and the benchmark): drains the
    /// queue, renders `n` samples into `out` (channels() buffers). Real-time.
    void renderPeriod(float* const* out, int n, double outputDelaySeconds) noexcept;

private:
    struct Record {
        double t = 0.0;
        double pushed = 0.0;   ///< monotonic s
        core::MotorLevels levels {};
    };
    TactorOutputConfig config_;
    tactors::TactorRenderer renderer_;
    std::unique_ptr<audio::SoundCard> card_;
    std::unique_ptr<audio::JackOutput> jack_;
    core::SpscQueue<Record, 1024> queue_;
    core::SpscQueue<TactorLatency, 8192> latency_;
    core::SpscQueue<float, 16384> sound_;
    std::array<float, 4096> soundScratch_ {};   // audio thread
    double sampleRate_ = 0.0;
    int periodFrames_ = 0;
    bool started_ = false;
    // audio thread
    double lastT_ = -1.0;
    double lastPushed_ = -1.0;
    bool muted_ = true;
    std::atomic<std::uint64_t> frames_ {0}, dropped_ {0}, limited_ {0};
};

} // namespace armadillo::live
