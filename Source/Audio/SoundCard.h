#pragma once
// Sound-card playback for the headless `armadillo play` (ALSA; the app and the plugin get their
// audio device from JUCE or the host). INTERFACES.md: audio goes to the sound card when there is
// no --out.
//
// Threads: start() runs one audio thread that asks the render callback for a period of stereo
// float samples and writes it to the card. The callback is the engine's renderAudio() (no locks,
// allocation or I/O). The device is non-blocking: when its buffer is full the thread waits in
// snd_pcm_wait() (≤ 100 ms at a time, so stop() never hangs behind a stalled sound server), and
// that wait is what paces it on a real card. ALSA devices that never make it wait (its `null`
// and `file` plugins, handy for tests) would let the loop run flat out, so without a wait it is
// held to one buffer ahead of the wall clock, counted from the last time the device made it
// wait (a card whose crystal runs fast against the system clock is never starved). Underruns are
// recovered and counted; a card that goes away (USB unplugged) ends the thread with lastError()
// set, and the session goes on without sound.
#include <atomic>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <thread>

namespace armadillo::audio {

struct SoundCardInfo {
    std::string device;          ///< ALSA PCM name as opened ("default", "hw:1", "file:'x.raw',raw", …)
    double sampleRate = 0.0;     ///< Hz (ALSA's plug layer resamples when the card differs)
    int periodFrames = 0;        ///< frames per write
    int bufferFrames = 0;        ///< frames the card queues (≈ output latency)
    std::string format;          ///< "FLOAT_LE" or "S16_LE"
    int channels = 2;            ///< interleaved output channels
};

class SoundCard {
public:
    using Render = std::function<void(float* left, float* right, int numSamples)>;
    /// N channels (the tactor output, issue 33): one buffer per channel, zeroed before the call.
    using RenderChannels = std::function<void(float* const* channels, int numChannels, int numSamples)>;

    /// Opens `device` for 2-channel playback at `sampleRate` with about `latencySeconds` of
    /// buffer. IoError ("sound card 'NAME': <ALSA's reason>") when it cannot be opened/configured.
    SoundCard(const std::string& device, double sampleRate, double latencySeconds = 0.02);
    /// The same for `channels` (1…32) output channels. IoError also when the device has fewer
    /// ("sound card 'hw:1': 8 output channels, 9 needed").
    SoundCard(const std::string& device, double sampleRate, double latencySeconds, int channels);
    ~SoundCard();
    SoundCard(const SoundCard&) = delete;
    SoundCard& operator=(const SoundCard&) = delete;

    /// Starts the audio thread; `render` is called on it for every period (it must be real-time
    /// safe). `realtimePriority` > 0 asks for SCHED_FIFO (falls back silently).
    void start(Render render, int realtimePriority = 0);
    /// Starts the audio thread with an N-channel callback (a card opened with N channels).
    void start(RenderChannels render, int realtimePriority = 0);
    /// Stops the thread (what is queued in the card is dropped: silence at once) and joins it.
    void stop();

    const SoundCardInfo& info() const noexcept { return info_; }
    std::uint64_t framesWritten() const noexcept { return frames_.load(std::memory_order_relaxed); }
    std::uint64_t underruns() const noexcept { return underruns_.load(std::memory_order_relaxed); }
    /// Why the thread ended early (empty while all is well). Read after stop() or from any thread
    /// once failed() is true.
    std::string lastError() const;
    bool failed() const noexcept { return failed_.load(std::memory_order_acquire); }
    /// Frames queued in the device ahead of the period being rendered, read by the audio thread
    /// just before it calls the render callback (snd_pcm_delay): how long that period's first
    /// sample waits before it is played. Any thread; read it from inside the callback for that period.
    int queuedFrames() const noexcept { return queued_.load(std::memory_order_relaxed); }

private:
    void loop(int realtimePriority);

    struct Pcm;
    std::unique_ptr<Pcm> pcm_;
    SoundCardInfo info_;
    Render render_;
    RenderChannels renderChannels_;
    std::atomic<int> queued_ {0};
    std::thread thread_;
    std::atomic<bool> running_ {false}, failed_ {false};
    std::atomic<std::uint64_t> frames_ {0}, underruns_ {0};
    std::string error_;   // written by the audio thread before failed_ is released
};

} // namespace armadillo::audio
